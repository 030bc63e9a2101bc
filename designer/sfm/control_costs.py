"""Control points in a Ceres bundle adjustment problem, shared by both adjustments.

A control point is a free 3D point held by a prior on its surveyed coordinates (σ per
axis, at least ``min_sigma_m``) and observed by its marks in the images (a reprojection
error with σ = the marking σ). How a mark is projected is the caller's: COLMAP's cost on
the image's pose (designer.sfm.adjustment) or the rolling-shutter cost with the image's
velocity (designer.sfm.rolling_adjustment).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np


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
    for cp in control:
        marks = [(name, uv) for name, uv in cp.marks if observed(name)]
        if not marks:
            continue
        xyz = np.array(cp.surveyed_local, float)
        keep.append(xyz)
        xyz_by_id[cp.gcp_id] = xyz
        sigma = np.maximum(np.asarray(cp.sigma_m, float), min_sigma_m)
        problem.add_residual_block(
            cf.Point3DAlignmentCost(np.diag(sigma ** 2), np.asarray(cp.surveyed_local, float)),
            None, [xyz, identity])
        for name, uv in marks:
            add_mark(xyz, name, np.asarray(uv, float), cov_uv)
    if xyz_by_id:
        keep.append(identity)
        problem.set_parameter_block_constant(identity)
    return xyz_by_id
