"""The detector's own error: the same detector on exactly area-sampled synthetic corners.

Each synthetic image (64 × 64 px) shows a checkerboard under the local affine map — the
rotation, scale, skew and foreshortening — of one corner measured in the rendered cube
images (the derivative of its wall's projection at that corner, computed from the
camera model, not from the rendered pixels), moved by a random sub-pixel translation
so that the corner lands anywhere on the pixel grid. The image is what a perfect
renderer would write (:mod:`designer.experiments.synthetic`: exact pixel areas, sRGB,
8 bits), so its corner error is the detector's alone, for the same corner geometries as
the rendered ones. A variance test then asks whether the rendered error is larger.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from designer.core.interior import InteriorOrientation
from designer.core.projection import R_cv_from_world
from designer.experiments.corners import Detector
from designer.experiments.synthetic import render

SIZE_PX = 64


def local_affine(corner_xyz: np.ndarray, axis_a: np.ndarray, axis_b: np.ndarray,
                 square_m: float, C: np.ndarray, R: np.ndarray,
                 interior: InteriorOrientation) -> np.ndarray:
    """2 × 2 Jacobian d(u, v)/d(x, y) px per square of a wall's projection at a corner,
    (x, y) being steps of one square along the wall axes ``axis_a``, ``axis_b``."""
    Hm = interior.K_px @ R_cv_from_world(R) @ np.column_stack(
        [square_m * axis_a, square_m * axis_b, corner_xyz - C])
    uv = Hm[:2, 2] / Hm[2, 2]
    return (Hm[:2, :2] - np.outer(uv, Hm[2, :2])) / Hm[2, 2]


@dataclass(frozen=True)
class BaselineResult:
    """Detector errors (N, 2) px on ``n_images`` synthetic images, and how many it found."""

    errors_px: np.ndarray
    n_images: int
    n_found: int
    example: np.ndarray  # one synthetic image, for the report


def detector_baseline(jacobians: np.ndarray, n_images: int, rng: np.random.Generator,
                      detector: Detector | None = None) -> BaselineResult:
    """Measure ``n_images`` synthetic corners whose local maps are drawn (with replacement)
    from ``jacobians`` (K, 2, 2), each at a uniformly random sub-pixel position."""
    detector = detector or Detector()
    if len(jacobians) == 0:
        raise ValueError("no measured corners to take the synthetic corner geometry from")
    picks = rng.integers(0, len(jacobians), n_images)
    offsets = rng.uniform(-0.5, 0.5, (n_images, 2))
    errors = []
    example = None
    for k in range(n_images):
        H = np.eye(3)
        H[:2, :2] = jacobians[picks[k]]
        corner = np.array([SIZE_PX / 2, SIZE_PX / 2]) + offsets[k]
        H[:2, 2] = corner
        image = render(H, (SIZE_PX, SIZE_PX))
        if example is None:
            example = image
        found, uv = detector.measure(image, corner[None])
        if found[0]:
            errors.append(uv[0] - corner)
    err = np.array(errors).reshape(-1, 2)
    return BaselineResult(err, n_images, len(err), example)
