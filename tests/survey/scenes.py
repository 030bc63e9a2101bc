"""Geometry checks shared by the survey tests (the scenes are in tests/synthetic.py)."""

import numpy as np

from designer.core.heightfield import Heightfield


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
