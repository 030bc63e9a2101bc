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


#: where the control selection is set in the window
WHERE_IDS = "Processing panel, ground control, by id"
WHERE_COUNT = "Processing panel, ground control, or a count"


def _gcp_issues(project: m.Project, g: m.GcpProcessing) -> list[Issue]:
    """The control selection's problems, worded as the Processing panel shows the
    setting: "control GCPs (G01, G04)" for GCPs named by id, "control count 5"."""
    out: list[Issue] = []
    c = g.control
    if c is None:
        return out
    ids = [t.id for t in project.targets]
    named = f"control GCPs ({', '.join(c.ids)})"
    if bool(c.ids) == (c.count is not None):
        what = (f"{named} and control count {c.count} are both given" if c.ids else
                "control GCPs are neither named nor counted")
        out.append(Issue(c, "control", f"{what}; name the GCPs or give a count, not both "
                                       f"({WHERE_IDS} or count)", attr="ids"))
    unknown = [i for i in c.ids if i not in ids]
    if unknown:
        have = ", ".join(ids[:2] + ["…"] + ids[-1:] if len(ids) > 4 else ids)
        out.append(Issue(c, "control", f"{named}: {unknown[0]} is not a GCP of the project "
                                       f"({have or 'it has none'}); name its GCPs or remove "
                                       f"{unknown[0]} ({WHERE_IDS})", attr="ids"))
    twice = [i for i in dict.fromkeys(c.ids) if c.ids.count(i) > 1]
    if twice:
        out.append(Issue(c, "control", f"{named}: {twice[0]} is listed twice; list each "
                                       f"once ({WHERE_IDS})", attr="ids"))
    if c.count is not None and len(ids) < c.count <= 10000:  # below 1: the declared range
        out.append(Issue(c, "control", f"control count {c.count}, but the project has "
                                       f"{len(ids)} GCPs; choose 1 to {len(ids)} "
                                       f"({WHERE_COUNT})", attr="count"))
    n = len(c.ids) if c.ids else (c.count or 0)
    if g.mode == "similarity" and 0 < n < MIN_SIMILARITY_CONTROL:
        what = (f"{named}: {n} GCP{'s' if n > 1 else ''}" if c.ids else
                f"control count {n}")
        where = WHERE_IDS if c.ids else WHERE_COUNT
        out.append(Issue(c, "control", f"{what}, but a similarity after SfM needs at least "
                                       f"{MIN_SIMILARITY_CONTROL}; "
                                       f"{'name' if c.ids else 'choose'} more ({where}) or "
                                       "set GCPs to “in the bundle adjustment”",
                         attr="ids" if c.ids else "count"))
    return out
