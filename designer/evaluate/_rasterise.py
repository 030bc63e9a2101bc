"""Highest triangle under each cell centre of a north-up grid.

Coordinates are local to the grid's top-left corner (x = easting − x_min,
y = y_max − northing, both growing into the grid), float64 metres. A vertical ray cast
down at a cell centre first hits the highest triangle whose footprint contains the
centre; that height is what :func:`highest_surface` stores (NaN where none does).
Triangles seen edge-on from above (walls) have no footprint and are skipped; a centre
on an edge shared by two triangles counts for both, which gives the same height. The
loop is C (``csrc/grid.c``).
"""

from __future__ import annotations

import numpy as np

from designer.evaluate._native import ckernels, f8, i8


def highest_surface(xy_local, z, faces, cell_m: float, rows: int, cols: int) -> np.ndarray:
    """Heights (rows, cols) of the highest triangle over each cell centre."""
    xy_local, z, faces = f8(xy_local).reshape(-1, 2), f8(z), i8(faces).reshape(-1, 3)
    if len(z) != len(xy_local):
        raise ValueError("xy_local and z must have one row per vertex")
    if len(faces) and (faces.min() < 0 or faces.max() >= len(z)):
        raise ValueError(f"faces must index vertices 0..{len(z) - 1}")
    out = np.full((rows, cols), np.nan)
    ckernels().highest_surface(xy_local, z, len(z), faces, len(faces), float(cell_m), rows,
                               cols, out)
    return out
