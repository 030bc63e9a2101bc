"""Semantic checks of ``<processing>``: the ranges the XSD states (for models built in
code) and what it cannot say — control ids that name targets, enough control points."""

from __future__ import annotations

import math

from designer.project import model as m
from designer.project.problems import Issue

CALIBRATION_MODES = ("fixed", "focal", "focal-principal-point", "radial", "full")
GCP_MODES = ("none", "similarity", "bundle")
PRIOR_MODES = ("none", "gnss", "rtk")
PAIRINGS = ("footprint", "position", "exhaustive")
DENSE_MODES = ("none", "cpu", "auto")
#: a similarity (7 parameters) needs three well-spread points
MIN_SIMILARITY_CONTROL = 3


def _choice(obj, tag: str, attr: str, value: str, allowed: tuple[str, ...]) -> list[Issue]:
    if value in allowed:
        return []
    return [Issue(obj, tag, f"{attr} = {value!r} is not one of {', '.join(allowed)}; "
                            "use one of them", attr=attr)]


def _sigma(obj, tag: str, attr: str, value: float, positive: bool = False,
           most: float = 1e6) -> list[Issue]:
    ok = math.isfinite(value) and (value > 0 if positive else value >= 0) and value <= most
    if ok:
        return []
    bound = "> 0" if positive else ">= 0"
    return [Issue(obj, tag, f"{attr} = {value!r} must be a finite number {bound} and at most "
                            f"{most:g}; give a valid standard deviation", attr=attr)]


def processing_issues(project: m.Project) -> list[Issue]:
    """Every problem of ``project.processing`` (none when it is absent)."""
    p = project.processing
    if p is None:
        return []
    cal = p.calibration
    out = _choice(cal, "calibration", "mode", cal.mode, CALIBRATION_MODES)
    pre = cal.pre_calibration_error
    if pre is not None:
        for name in ("focal_px", "principal_point_px", "k1", "k2", "k3", "p1", "p2"):
            out += _sigma(pre, "pre-calibration-error", name.replace("_", "-"),
                          getattr(pre, name))
    out += _gcp_issues(project, p.gcps)
    prior = p.position_prior
    out += _choice(prior, "position-prior", "mode", prior.mode, PRIOR_MODES)
    for name in ("sigma_horizontal_m", "sigma_vertical_m"):
        value = getattr(prior, name)
        if value is not None:
            out += _sigma(prior, "position-prior", name.replace("_", "-"), value,
                          positive=True, most=1000)
    mt = p.matching
    out += _choice(mt, "matching", "pairs", mt.pairs, PAIRINGS)
    if not 100 <= mt.max_features <= 1_000_000:
        out.append(Issue(mt, "matching", f"max-features = {mt.max_features} must be 100 to "
                                         "1000000", attr="max-features"))
    if not 2 <= mt.min_track_length <= 100:
        out.append(Issue(mt, "matching", f"min-track-length = {mt.min_track_length} must be "
                                         "2 to 100 images", attr="min-track-length"))
    out += _choice(p, "processing", "dense", p.dense, DENSE_MODES)
    return out


def _gcp_issues(project: m.Project, g: m.GcpProcessing) -> list[Issue]:
    out = _choice(g, "gcps", "mode", g.mode, GCP_MODES)
    out += _sigma(g, "gcps", "marking-sigma-px", g.marking_sigma_px, most=50)
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
    if c.count is not None and not 1 <= c.count <= len(ids):
        out.append(Issue(c, "control", f"count = {c.count} but the scene has {len(ids)} "
                                       f"targets; choose 1 to {len(ids)}", attr="count"))
    if c.spread not in ("even", "random"):
        out += _choice(c, "control", "spread", c.spread, ("even", "random"))
    n = len(c.ids) if c.ids else (c.count or 0)
    if g.mode == "similarity" and 0 < n < MIN_SIMILARITY_CONTROL:
        out.append(Issue(c, "control", f"{n} control point(s): a similarity needs at least "
                                       f"{MIN_SIMILARITY_CONTROL}; add control points or use "
                                       "mode=\"bundle\"", attr="ids" if c.ids else "count"))
    return out
