"""The lenses and checkerboard scenes of the distortion-warp tests (used by
tests/effects/test_distortion_render.py and tests/effects/measure_warp.py)."""

from __future__ import annotations

import math

import numpy as np

from designer.core.distortion import BrownConrady, FisheyeEquidistant
from tests.effects.synthetic import AngularChecker, PlanarChecker, project_opencv
from tests.synthetic import pixel_camera

W, H = 800, 600
PP = (7.3, -4.1)
FISHEYE = FisheyeEquidistant(k1=0.03, k2=-0.01, k3=0.002, k4=-0.0005)
LENSES = {
    "barrel": pixel_camera(W, H, 800.0, BrownConrady(k1=-0.3), PP),
    "pincushion": pixel_camera(W, H, 800.0, BrownConrady(k1=0.2), PP),
    "tangential": pixel_camera(W, H, 800.0, BrownConrady(p1=0.002, p2=-0.0015), PP),
    # θ reaches 74.6° at the farthest corner: a 149° field
    "fisheye150": pixel_camera(W, H, 376.0, FISHEYE, (3.2, -2.5)),
}


def board():
    """(pattern, n): a tilted planar checkerboard of 0.35 m squares about 10 m ahead."""
    e1 = np.array([math.cos(0.3), 0.0, math.sin(0.3)])
    e2 = np.array([0.1, 1.0, 0.2])
    e2 -= e1 * (e1 @ e2)
    return PlanarChecker([0.3, -0.2, 10.0], e1, e2 / np.linalg.norm(e2), 0.35), 40


def scene(name):
    """(pattern, n): a tilted planar checkerboard for Brown lenses, an angular one (squares
    of ~28 px out to the edge) for the fisheye."""
    if name.startswith("fisheye"):
        return AngularChecker(28 / 376, 10.0, (0.3, 0.2)), 30
    return board()


def expected_corners(interior, pattern, n):
    """True corner positions (designer px) and their 4 grid neighbours, NaN where not seen."""
    pts = pattern.corners(n)
    uv = project_opencv(interior, pts)
    visible = pts[:, 2] > 0
    lens = interior.distortion
    if isinstance(lens, BrownConrady):  # beyond the fold OpenCV projects back into the image
        with np.errstate(divide="ignore", invalid="ignore"):
            r = np.hypot(pts[:, 0], pts[:, 1]) / pts[:, 2]
        visible &= r < lens.max_monotone_radius()
    uv[~visible] = np.nan
    grid = np.full((2 * n + 3, 2 * n + 3, 2), np.nan)
    grid[1:-1, 1:-1] = uv.reshape(2 * n + 1, 2 * n + 1, 2)
    nb = np.stack([grid[:-2, 1:-1], grid[2:, 1:-1], grid[1:-1, :-2], grid[1:-1, 2:]], axis=2)
    return uv, nb.reshape(-1, 4, 2)
