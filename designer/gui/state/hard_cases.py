"""``designer check``'s hard-case warnings (designer.checks.hard_cases) over what the
window has already computed, for the Flight panel (Qt-free).

The lens of each camera is weighed as it is edited (a millisecond, kept per camera); the
control GCPs' spread is measured on the targets drawn (an SVD of a few points); the
texture's texel is weighed against the finest GSD the flight's analysis measured in its
thread (:attr:`designer.gui.state.plan_figures.PlanFigures.finest_gsd_m`), and the
network's warnings come with that analysis (without one, on a terrain mesh, they are
weighed on the stations drawn: a count of images and lines). So asking after every edit
costs well under a millisecond once the lens is known.
"""

from __future__ import annotations

import functools

import numpy as np

from designer.checks.hard_cases import (
    HardCaseWarning,
    coarse_gsd_warning,
    collinear_control_warning,
    distortion_warning,
    network_warnings,
    texture_warnings,
    wide_lens_warning,
)
from designer.errors import DesignerError
from designer.project import model as m


@functools.lru_cache(maxsize=64)
def _lens_warning(camera: m.Camera, resolution_scale: float) -> HardCaseWarning | None:
    """The lens warning of ``camera``; None for a camera no interior orientation can
    describe (pixels not square, a scale giving part pixels): the Camera panel and the
    Problems list say what is wrong with it, and the lens is weighed once it is fixed."""
    try:
        return distortion_warning(camera, resolution_scale)
    except DesignerError:
        return None


@functools.lru_cache(maxsize=64)
def _wide_lens(camera: m.Camera) -> HardCaseWarning | None:
    """A pinhole camera wider than any survey camera (kept per camera, as the lens)."""
    return wide_lens_warning(camera)


def hard_case_lines(project: m.Project, targets, plan, stations=None) -> list[str]:
    """The warnings, one line each with its fix in the window's words: the lenses close
    to their fold, pinhole lenses wider and a flight coarser than any survey's, nearly
    collinear control (``targets``: a
    designer.gui.state.derived.TargetsResult, their surveyed coordinates, on any terrain:
    a height field or a mesh), the texture against the finest GSD (``plan``: PlanFigures
    or None). The network's warnings are in ``plan.warnings``; without a plan (a terrain
    mesh, or before the analysis) they are weighed on ``stations`` (a StationsResult or
    None: its images and lines). As ``designer check``: the texture needs the finest GSD,
    which the flight's analysis measures by casting rays on a height field, so on a
    terrain mesh it is not warned of."""
    out = [w for cam in project.cameras
           if (w := _lens_warning(cam, project.render.resolution_scale)) is not None]
    out += [w for cam in project.cameras if (w := _wide_lens(cam)) is not None]
    gsd = coarse_gsd_warning(project)
    out += [gsd] if gsd is not None else []
    if targets is not None:
        control = [k for k, role in enumerate(targets.roles) if role == "control"]
        w = collinear_control_warning([targets.ids[k] for k in control],
                                      np.asarray(targets.surveyed_xyz)[control])
        if w is not None:
            out.append(w)
    if plan is not None:
        out += texture_warnings(project, plan.finest_gsd_m)
    elif stations is not None:
        out += network_warnings(project, len(stations.image_names),
                                [s.line_index for s in stations.stations])
    return [f"{w.message}; {w.panel_fix or w.fix}" for w in out]
