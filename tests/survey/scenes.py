"""Synthetic scenes shared by the survey tests."""

import numpy as np

from designer.core.heightfield import Heightfield
from designer.core.interior import InteriorOrientation

UTM_EN = np.array([500000.0, 5000000.0])


def phantom4(**changes) -> InteriorOrientation:
    params = dict(focal_length_mm=8.8, sensor_width_mm=13.2, sensor_height_mm=8.8,
                  image_width_px=5472, image_height_px=3648)
    params.update(changes)
    return InteriorOrientation(**params)


def flat_terrain(x0=0.0, y0=0.0, size_m=600.0, spacing_m=5.0, height_m=50.0) -> Heightfield:
    n = round(size_m / spacing_m) + 1
    return Heightfield(x0, y0, spacing_m, spacing_m, np.full((n, n), height_m))


def hilly_terrain(x0=0.0, y0=0.0, size_m=400.0, spacing_m=2.0, relief_m=40.0) -> Heightfield:
    n = round(size_m / spacing_m) + 1
    x = np.linspace(0.0, size_m, n)
    X, Y = np.meshgrid(x, x)
    Z = 100.0 + relief_m * (0.6 * np.sin(X / 35.0) * np.cos(Y / 47.0)
                            + 0.4 * np.sin(X / 17.0 + Y / 23.0))
    return Heightfield(x0, y0, spacing_m, spacing_m, Z)


def refined(hf: Heightfield, factor: int) -> Heightfield:
    """The same bilinear surface on a grid ``factor`` times finer (a bilinear patch is
    bilinear on every sub-rectangle), so the core's half-cell marching steps finer."""
    ny, nx = hf.heights_m.shape
    x = hf.x0_m + np.arange((nx - 1) * factor + 1) * hf.dx_m / factor
    y = hf.y0_m + np.arange((ny - 1) * factor + 1) * hf.dy_m / factor
    X, Y = np.meshgrid(x, y)
    return Heightfield(hf.x0_m, hf.y0_m, hf.dx_m / factor, hf.dy_m / factor,
                       hf.height_at(X, Y))


def sight_clearance_deg(P, C, hf: Heightfield, tol_m: float, step_m: float = 0.005):
    """Smallest angle (deg) between each sight line P → C and the terrain below it,
    min over s ∈ [tol, |C − P|) of gap(s) / s, sampled every ``step_m``; < 0 = blocked."""
    out = []
    for p, c in zip(np.atleast_2d(P), np.atleast_2d(C), strict=True):
        d = c - p
        length = np.linalg.norm(d)
        s = np.arange(tol_m, length, step_m)
        q = p + s[:, None] * (d / length)
        gap = q[:, 2] - hf.height_at(q[:, 0], q[:, 1])
        out.append(np.degrees(np.nanmin(gap / s)))
    return np.array(out)
