"""Nearest-neighbour gridding of scattered points (numba), for the error maps.

Local coordinates in metres: x grows east from the grid's west edge, y grows north and
is ≤ 0 inside the grid (0 at its north edge). Points are bucketed by grid cell (a
counting sort); each cell centre then searches rings of cells around its own, nearest
ring first, and stops once no point of a farther ring can beat the best found, so the
result is the exact nearest point within the gap.
"""

from __future__ import annotations

import numpy as np
from numba import njit, prange


@njit(cache=True, nogil=True, parallel=True)
def _cell_keys(x, y, rows, cols, cell):
    key = np.empty(x.shape[0], dtype=np.int64)
    for p in prange(x.shape[0]):
        j = min(cols - 1, max(0, int(np.floor(x[p] / cell))))
        i = min(rows - 1, max(0, int(np.floor(-y[p] / cell))))
        key[p] = i * cols + j
    return key


@njit(cache=True, nogil=True)
def _buckets(x, y, rows, cols, cell):
    """(start (rows·cols + 1,), order (N,)): the points of cell k are
    order[start[k]:start[k + 1]]; points beyond the grid go to its edge cells."""
    n = x.shape[0]
    key = _cell_keys(x, y, rows, cols, cell)
    start = np.zeros(rows * cols + 1, dtype=np.int64)
    for p in range(n):
        start[key[p] + 1] += 1
    for k in range(rows * cols):
        start[k + 1] += start[k]
    fill = start[:-1].copy()
    order = np.empty(n, dtype=np.int64)
    for p in range(n):
        order[fill[key[p]]] = p
        fill[key[p]] += 1
    return start, order


@njit(cache=True, nogil=True, parallel=True)
def nearest_point_grid(x, y, rows, cols, cell, gap):
    """Index (rows·cols,) of the point nearest to each cell centre, −1 where no point
    is closer than ``gap`` (m); row-major, row 0 at the north edge."""
    start, order = _buckets(x, y, rows, cols, cell)
    out = np.full(rows * cols, -1, dtype=np.int64)
    gap2 = gap * gap
    # a point r cells away (in rows or columns) is at least (r − 0.5) cells from a centre
    reach = int(np.ceil(gap / cell + 0.5))
    for i in prange(rows):
        cy = -(i + 0.5) * cell
        for j in range(cols):
            cx = (j + 0.5) * cell
            best, best_p = gap2, -1
            for r in range(reach + 1):
                if r >= 1 and (r - 0.5) * cell * ((r - 0.5) * cell) >= best:
                    break  # every point of this ring and beyond is farther
                for ii in range(max(0, i - r), min(rows, i + r + 1)):
                    ring_row = ii == i - r or ii == i + r
                    step = 1 if ring_row else 2 * r
                    jj = j - r if not ring_row else max(0, j - r)
                    while jj <= min(cols - 1, j + r):
                        if 0 <= jj:
                            k = ii * cols + jj
                            for s in range(start[k], start[k + 1]):
                                p = order[s]
                                dx, dy = x[p] - cx, y[p] - cy
                                d2 = dx * dx + dy * dy
                                if d2 < best or (d2 == best and best_p >= 0 and p < best_p):
                                    best, best_p = d2, p
                        jj += step
            out[i * cols + j] = best_p
    return out
