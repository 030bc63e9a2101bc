"""Semantic checks of ``<processing>`` beyond the declared ranges (validate_declared),
what the XSD cannot say: control ids that name targets, enough control points."""

from __future__ import annotations

from designer.project import model as m
from designer.project.problems import Issue

CALIBRATION_MODES = ("fixed", "focal", "focal-principal-point", "radial", "full")
GCP_MODES = ("none", "similarity", "bundle")
PRIOR_MODES = ("none", "gnss", "rtk")
PAIRINGS = ("footprint", "position", "exhaustive")
#: a similarity (7 parameters) needs three well-spread points
MIN_SIMILARITY_CONTROL = 3


def processing_issues(project: m.Project) -> list[Issue]:
    """Every problem of ``project.processing`` (none when it is absent)."""
    p = project.processing
    if p is None:
        return []
    # the declared ranges and choices of each part: validate_declared
    return _gcp_issues(project, p.gcps)


def _gcp_issues(project: m.Project, g: m.GcpProcessing) -> list[Issue]:
    out: list[Issue] = []
    c = g.control
    if c is None:
        return out
    ids = [t.id for t in project.targets]
    if bool(c.ids) == (c.count is not None):
        out.append(Issue(c, "control", "give either ids (a list of target ids) or count, "
                                       "not both and not neither", attr="ids"))
    unknown = [i for i in c.ids if i not in ids]
    if unknown:
        out.append(Issue(c, "control", f"unknown target id {unknown[0]!r}; use ids of "
                                       f"<target> elements ({', '.join(ids) or 'none'})",
                         attr="ids"))
    if len(set(c.ids)) != len(c.ids):
        out.append(Issue(c, "control", "a target id is listed twice; list each once",
                         attr="ids"))
    if c.count is not None and len(ids) < c.count <= 10000:  # below 1: the declared range
        out.append(Issue(c, "control", f"count = {c.count} but the scene has {len(ids)} "
                                       f"targets; choose 1 to {len(ids)}", attr="count"))
    n = len(c.ids) if c.ids else (c.count or 0)
    if g.mode == "similarity" and 0 < n < MIN_SIMILARITY_CONTROL:
        out.append(Issue(c, "control", f"{n} control point(s): a similarity needs at least "
                                       f"{MIN_SIMILARITY_CONTROL}; add control points or use "
                                       "mode=\"bundle\"", attr="ids" if c.ids else "count"))
    return out
