"""Control points in a bundle adjustment, shared by both adjustments.

A control point is a free 3D point held by a prior on its surveyed coordinates (σ per
axis, at least ``min_sigma_m``) and observed by its marks in the images (a reprojection
error with σ = the marking σ). :func:`control_in_block` selects them and their marks;
:func:`add_control_points` adds them to a Ceres problem, the marks projected as the
caller says (COLMAP's cost on the image's pose, designer.sfm.adjustment); the
vectorised rolling-shutter solver (designer.sfm.rolling_adjustment) takes them as arrays.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class ControlInBlock:
    """A control point with at least one mark in the adjustment: surveyed position
    (local m), σ per axis (m, at least the minimum) and its marks (image name, uv px)."""

    gcp_id: str
    surveyed_local: np.ndarray
    sigma_m: np.ndarray
    marks: tuple[tuple[str, np.ndarray], ...]


def control_in_block(control, observed: Callable[[str], bool], min_sigma_m: float
                     ) -> list[ControlInBlock]:
    """The control points (designer.sfm.adjustment.ControlPoint) marked in an image for
    which ``observed(name)`` is true, with only those marks."""
    out = []
    for cp in control:
        marks = tuple((name, np.asarray(uv, float)) for name, uv in cp.marks if observed(name))
        if marks:
            out.append(ControlInBlock(
                cp.gcp_id, np.array(cp.surveyed_local, float),
                np.maximum(np.asarray(cp.sigma_m, float), min_sigma_m), marks))
    return out


def add_control_points(problem, control, observed: Callable[[str], bool],
                       add_mark: Callable[[np.ndarray, str, np.ndarray, np.ndarray], None],
                       sigma_mark_px: float, min_sigma_m: float, keep: list
                       ) -> dict[str, np.ndarray]:
    """Add each control point (designer.sfm.adjustment.ControlPoint) marked in an image
    for which ``observed(name)`` is true: its 3D parameter block, the surveyed prior and
    ``add_mark(xyz, image name, uv px, 2×2 covariance px²)`` per mark. ``keep`` holds the
    blocks' arrays alive as long as the problem. Returns the blocks by GCP id (they hold
    the adjusted coordinates after the solve)."""
    from pycolmap import cost_functions as cf

    identity = np.array([0, 0, 0, 1, 0, 0, 0, 0], float)  # Sim3d: quat xyzw, t, log scale
    xyz_by_id: dict[str, np.ndarray] = {}
    cov_uv = np.eye(2) * sigma_mark_px ** 2
    for cp in control_in_block(control, observed, min_sigma_m):
        xyz = cp.surveyed_local.copy()
        keep.append(xyz)
        xyz_by_id[cp.gcp_id] = xyz
        problem.add_residual_block(
            cf.Point3DAlignmentCost(np.diag(cp.sigma_m ** 2), cp.surveyed_local),
            None, [xyz, identity])
        for name, uv in cp.marks:
            add_mark(xyz, name, uv, cov_uv)
    if xyz_by_id:
        keep.append(identity)
        problem.set_parameter_block_constant(identity)
    return xyz_by_id
