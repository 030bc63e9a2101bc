"""Terrain height fields: seeded procedural hills, plus the DEM and mesh entry points.

World frame: X east, Y north, Z up, metres. A terrain is a
:class:`~designer.core.heightfield.Heightfield` (node (row i, column j) at
``X = x0 + j·dx``, ``Y = y0 + i·dy``, rows go north, bilinear between nodes).

This module makes procedural terrain; reading DEMs lives in :mod:`designer.scene.dem`
and triangle meshes in :mod:`designer.scene.mesh`. Their public functions are
re-exported here so ``designer.scene.terrain`` is the one door for terrain.
"""

from __future__ import annotations

import numpy as np
import scipy.fft

from designer.core.heightfield import Heightfield
from designer.errors import DesignerError
from designer.scene.dem import load_dem
from designer.scene.mesh import TerrainMesh, heightfield_to_mesh, load_mesh, write_mesh_ply

__all__ = [
    "TerrainMesh",
    "heightfield_to_mesh",
    "load_dem",
    "load_mesh",
    "procedural_terrain",
    "write_mesh_ply",
]

#: relative tolerance for "size is a whole number of grid spacings"
_GRID_TOL = 1e-9


def procedural_terrain(
    size_x_m: float,
    size_y_m: float,
    spacing_m: float,
    relief_m: float,
    seed: int,
    *,
    x0_m: float = 0.0,
    y0_m: float = 0.0,
    base_height_m: float = 0.0,
    roughness: float = 0.3,
) -> Heightfield:
    """Seeded smooth hills on a regular grid, heights spanning exactly base ± relief.

    The grid covers ``[x0, x0 + size_x] × [y0, y0 + size_y]`` (metres, world frame) with
    nodes every ``spacing_m``; both sizes must be whole multiples of the spacing. Heights
    are band-limited Gaussian noise with power spectrum ``(f² + f0²)^(−β/2)``, where
    ``f0 = 1 / max(size)`` sets the largest hills and ``β = 5 − 3·roughness``
    (``roughness`` 0 → rolling hills, 1 → rugged ground); wavelengths below four grid
    spacings are filtered out so the grid resolves every bump. The noise is synthesised
    on a doubled, non-periodic domain, so opposite edges do not match. Finally heights
    are scaled so that min = ``base_height_m − relief_m`` and
    max = ``base_height_m + relief_m`` exactly.

    The spectrum is defined in cycles per metre, so the spacing changes the resolution of
    the hills, not their size. The same ``seed`` and arguments give the same terrain on
    every platform (numpy's PCG64 stream; FFT rounding aside, ~1e-12 m).
    """
    for name, value in (("size_x_m", size_x_m), ("size_y_m", size_y_m),
                        ("spacing_m", spacing_m)):
        if not (np.isfinite(value) and value > 0):
            raise DesignerError(f"procedural terrain: {name} must be > 0, got {value}")
    if not (np.isfinite(relief_m) and relief_m >= 0):
        raise DesignerError(f"procedural terrain: relief_m must be >= 0, got {relief_m}")
    if not 0.0 <= roughness <= 1.0:
        raise DesignerError(f"procedural terrain: roughness must be in [0, 1], got {roughness}")
    nx = _cells(size_x_m, spacing_m, "size_x_m") + 1
    ny = _cells(size_y_m, spacing_m, "size_y_m") + 1

    noise = _band_limited_noise(ny, nx, spacing_m, max(size_x_m, size_y_m),
                                beta=5.0 - 3.0 * roughness, seed=seed)
    lo, hi = float(noise.min()), float(noise.max())
    if hi > lo:
        # (n − lo)/(hi − lo) is exactly 0 and 1 at the extremes, so the range is exact.
        unit = 2.0 * ((noise - lo) / (hi - lo)) - 1.0
    else:
        unit = np.zeros_like(noise)
    heights = base_height_m + relief_m * unit
    return Heightfield(float(x0_m), float(y0_m), float(spacing_m), float(spacing_m), heights)


def _cells(size_m: float, spacing_m: float, name: str) -> int:
    n = round(size_m / spacing_m)
    if n < 1 or abs(n * spacing_m - size_m) > _GRID_TOL * size_m:
        raise DesignerError(
            f"procedural terrain: {name}={size_m} is not a whole number of "
            f"spacing_m={spacing_m} cells; choose a spacing that divides the size")
    return n


def _band_limited_noise(ny: int, nx: int, spacing_m: float, largest_m: float,
                        beta: float, seed: int) -> np.ndarray:
    """(ny, nx) float64 zero-mean noise with the power spectrum in the docstring above."""
    rng = np.random.default_rng(seed)
    # Twice the size (rounded to a fast FFT length): the periodic wrap of the synthesis
    # domain then falls outside the returned grid.
    py = scipy.fft.next_fast_len(2 * ny, real=True)
    px = scipy.fft.next_fast_len(2 * nx, real=True)
    fy = np.fft.fftfreq(py, d=spacing_m)[:, None]
    fx = np.fft.rfftfreq(px, d=spacing_m)[None, :]
    f2 = fx * fx + fy * fy
    f0 = 1.0 / largest_m
    f_cut = 1.0 / (4.0 * spacing_m)
    amplitude = (f2 + f0 * f0) ** (-beta / 4.0) * np.exp(-f2 / (f_cut * f_cut))
    amplitude[0, 0] = 0.0
    spectrum = rng.standard_normal((py, px // 2 + 1)) + 1j * rng.standard_normal(
        (py, px // 2 + 1))
    field = scipy.fft.irfft2(spectrum * amplitude, s=(py, px))
    return np.ascontiguousarray(field[:ny, :nx])
