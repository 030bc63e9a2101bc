"""Nearest-neighbour gridding of scattered points, for the error maps.

Local coordinates in metres: x grows east from the grid's west edge, y grows north and
is ≤ 0 inside the grid (0 at its north edge). Points are bucketed by grid cell (a
counting sort); each cell centre then searches rings of cells around its own, nearest
ring first, and stops once no point of a farther ring can beat the best found, so the
result is the exact nearest point within the gap. The loops are C (``csrc/grid.c``).
"""

from __future__ import annotations

import numpy as np

from designer.evaluate._native import ckernels, f8, threads


def nearest_point_grid(x, y, rows: int, cols: int, cell: float, gap: float) -> np.ndarray:
    """Index (rows·cols,) of the point nearest to each cell centre, −1 where no point
    is closer than ``gap`` (m); row-major, row 0 at the north edge."""
    x, y = f8(x), f8(y)
    if x.shape != y.shape or x.ndim != 1:
        raise ValueError("x and y must be (N,) arrays of the same length")
    out = np.empty(rows * cols, dtype=np.int64)
    ckernels().nearest_point_grid(x, y, len(x), rows, cols, float(cell), float(gap), out,
                                  threads())
    return out
