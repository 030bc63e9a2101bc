"""Highest triangle under each cell centre of a north-up grid (numba).

Coordinates are local to the grid's top-left corner (x = easting − x_min,
y = y_max − northing, both growing into the grid), float64 metres. A vertical ray cast
down at a cell centre first hits the highest triangle whose footprint contains the
centre; that height is what :func:`highest_surface` stores (NaN where none does).
Triangles seen edge-on from above (walls) have no footprint and are skipped; a centre
on an edge shared by two triangles counts for both, which gives the same height.
"""

from __future__ import annotations

import numpy as np
from numba import njit


@njit(cache=True)
def highest_surface(xy_local, z, faces, cell_m, rows, cols):
    """Heights (rows, cols) of the highest triangle over each cell centre."""
    out = np.full((rows, cols), np.nan)
    eps = 1e-12
    for f in range(faces.shape[0]):
        a, b, c = faces[f, 0], faces[f, 1], faces[f, 2]
        ax, ay, bx, by = xy_local[a, 0], xy_local[a, 1], xy_local[b, 0], xy_local[b, 1]
        cx, cy = xy_local[c, 0], xy_local[c, 1]
        det = (bx - ax) * (cy - ay) - (cx - ax) * (by - ay)
        scale = max(abs(bx - ax) + abs(cx - ax), abs(by - ay) + abs(cy - ay))
        if abs(det) <= 1e-12 * scale * scale or scale == 0.0:
            continue
        j0 = max(0, int(np.ceil(min(ax, bx, cx) / cell_m - 0.5)))
        j1 = min(cols - 1, int(np.floor(max(ax, bx, cx) / cell_m - 0.5)))
        i0 = max(0, int(np.ceil(min(ay, by, cy) / cell_m - 0.5)))
        i1 = min(rows - 1, int(np.floor(max(ay, by, cy) / cell_m - 0.5)))
        for i in range(i0, i1 + 1):
            py = (i + 0.5) * cell_m
            for j in range(j0, j1 + 1):
                px = (j + 0.5) * cell_m
                # barycentric weights of (px, py)
                wb = ((px - ax) * (cy - ay) - (cx - ax) * (py - ay)) / det
                wc = ((bx - ax) * (py - ay) - (px - ax) * (by - ay)) / det
                wa = 1.0 - wb - wc
                if wa < -eps or wb < -eps or wc < -eps:
                    continue
                h = wa * z[a] + wb * z[b] + wc * z[c]
                if not (out[i, j] >= h):  # NaN or lower
                    out[i, j] = h
    return out
