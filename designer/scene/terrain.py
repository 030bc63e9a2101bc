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

from designer.core.heightfield import Heightfield
from designer.errors import ParameterError
from designer.scene.dem import load_dem
from designer.scene.mesh import TerrainMesh, heightfield_to_mesh, load_mesh, write_mesh_ply
from designer.scene.world_noise import octave_sum

__all__ = [
    "TerrainMesh",
    "heightfield_to_mesh",
    "load_dem",
    "load_mesh",
    "procedural_terrain",
    "terrain_heights",
    "write_mesh_ply",
]

#: relative tolerance for "size is a whole number of grid spacings"
_GRID_TOL = 1e-9


#: largest hills (m) of a procedural terrain that does not say (the example's extent)
DEFAULT_HILL_SIZE_M = 100.0
#: the band limit: no octave finer than this many grid spacings
FINEST_WAVELENGTH_SPACINGS = 4.0
#: the random stream of the terrain's noise (world_noise streams are per use)
TERRAIN_STREAM = 7


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
    hill_size_m: float = DEFAULT_HILL_SIZE_M,
) -> Heightfield:
    """Seeded smooth hills on a regular grid, fixed to the world, inside base ± relief.

    The grid covers ``[x0, x0 + size_x] × [y0, y0 + size_y]`` (metres, world frame) with
    nodes every ``spacing_m``; both sizes must be whole multiples of the spacing. The
    height at a node is a function of the world point, the seed and the settings only
    (:mod:`designer.scene.world_noise`): growing, cropping or shifting the grid by whole
    spacings keeps every node's height, so surroundings rendered around a terrain
    continue its hills without a seam.

    Heights are octaves of value noise from ``hill_size_m`` (the largest hills' wavelength)
    down to four grid spacings (finer bumps the grid could not resolve are left out), each
    octave's amplitude ``2^(−(β − 2)/2)`` times the last with ``β = 5 − 3·roughness``
    (the power spectrum ``f^−β``: roughness 0 → rolling hills, 1 → rugged ground). The
    sum ``s`` over its expected standard deviation ``σ`` is mapped to
    ``base + relief · tanh(s / σ)``: heights never leave ``base ± relief``, and over a
    terrain a few hill sizes across they reach about 90 % of it (±0.76 relief at one σ).
    The same seed and arguments give the same heights on every platform (integer hashes
    and float64 arithmetic).
    """
    for name, value in (("size_x_m", size_x_m), ("size_y_m", size_y_m),
                        ("spacing_m", spacing_m), ("hill_size_m", hill_size_m)):
        if not (np.isfinite(value) and value > 0):
            raise ParameterError(f"procedural terrain: {name} must be > 0, got {value}",
                                 name=name, value=value, unit="m", must="greater than 0 m")
    if not (np.isfinite(relief_m) and relief_m >= 0):
        raise ParameterError(f"procedural terrain: relief_m must be >= 0, got {relief_m}",
                             name="relief_m", value=relief_m, unit="m",
                             must="at least 0 m")
    if not 0.0 <= roughness <= 1.0:
        raise ParameterError(f"procedural terrain: roughness must be in [0, 1], got {roughness}",
                             name="roughness", value=roughness, must="from 0 to 1")
    nx = _cells(size_x_m, spacing_m, "size_x_m") + 1
    ny = _cells(size_y_m, spacing_m, "size_y_m") + 1
    x = float(x0_m) + np.arange(nx) * float(spacing_m)
    y = float(y0_m) + np.arange(ny) * float(spacing_m)
    heights = terrain_heights(x[None, :], y[:, None], spacing_m, relief_m, seed,
                              base_height_m=base_height_m, roughness=roughness,
                              hill_size_m=hill_size_m)
    return Heightfield(float(x0_m), float(y0_m), float(spacing_m), float(spacing_m),
                       np.ascontiguousarray(heights))


def terrain_heights(x_m: np.ndarray, y_m: np.ndarray, spacing_m: float, relief_m: float,
                    seed: int, *, base_height_m: float = 0.0, roughness: float = 0.3,
                    hill_size_m: float = DEFAULT_HILL_SIZE_M) -> np.ndarray:
    """The procedural terrain's height (world Z, m) at world points (x, y) (broadcast),
    as :func:`procedural_terrain` places at its nodes."""
    octaves = terrain_octaves(hill_size_m, spacing_m)
    if relief_m == 0:
        return np.full(np.broadcast(np.asarray(x_m), np.asarray(y_m)).shape,
                       float(base_height_m))
    beta = 5.0 - 3.0 * roughness
    total, std = octave_sum(seed, TERRAIN_STREAM, hill_size_m, octaves, x_m, y_m,
                            persistence=2.0 ** (-(beta - 2.0) / 2.0), rotate=True)
    return float(base_height_m) + float(relief_m) * np.tanh(total / std)


def terrain_octaves(hill_size_m: float, spacing_m: float) -> int:
    """Octaves from the hill size down to the band limit (four grid spacings), at least 1."""
    ratio = hill_size_m / (FINEST_WAVELENGTH_SPACINGS * spacing_m)
    return max(1, int(np.floor(np.log2(ratio) + 1e-9)) + 1) if ratio >= 1 else 1


def _cells(size_m: float, spacing_m: float, name: str) -> int:
    n = round(size_m / spacing_m)
    if n < 1 or abs(n * spacing_m - size_m) > _GRID_TOL * size_m:
        raise ParameterError(
            f"procedural terrain: {name}={size_m} is not a whole number of "
            f"spacing_m={spacing_m} cells; choose a spacing that divides the size",
            name=name, value=size_m, unit="m",
            must=f"a whole number of {spacing_m:g} m grid cells; choose a grid spacing that "
                 "divides it")
    return n
