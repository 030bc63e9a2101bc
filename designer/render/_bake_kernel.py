"""Compiled (numba) kernel of the texture bake (:mod:`designer.render.texture_bake`).

Rows are spread over the threads; every texel is computed alone, so the result does not
depend on the number of threads.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit, prange


@njit(cache=True, inline="always")
def _sample(image, u, v, wrap, closest, out):
    """``image`` (H, W, C) float32 at (u, v) as Blender samples it: texel (i, j) centred at
    u = (j + 0.5) / W, v = 1 − (i + 0.5) / H; ``wrap`` repeats, else edge texels extend."""
    H, W, C = image.shape
    x = u * W - 0.5
    y = (1.0 - v) * H - 0.5
    if closest:
        j = math.floor(x + 0.5)
        i = math.floor(y + 0.5)
        if wrap:
            j, i = j % W, i % H
        else:
            j, i = min(max(j, 0), W - 1), min(max(i, 0), H - 1)
        for c in range(C):
            out[c] = image[i, j, c]
        return
    x0, y0 = math.floor(x), math.floor(y)
    fx, fy = x - x0, y - y0
    j0, i0 = int(x0), int(y0)
    if wrap:
        j0, i0 = j0 % W, i0 % H
        j1, i1 = (j0 + 1) % W, (i0 + 1) % H
    else:
        j1, i1 = min(max(j0 + 1, 0), W - 1), min(max(i0 + 1, 0), H - 1)
        j0, i0 = min(max(j0, 0), W - 1), min(max(i0, 0), H - 1)
    for c in range(C):
        top = image[i0, j0, c] * (1.0 - fx) + image[i0, j1, c] * fx
        bottom = image[i1, j0, c] * (1.0 - fx) + image[i1, j1, c] * fx
        out[c] = top * (1.0 - fy) + bottom * fy


@njit(cache=True, inline="always")
def _decode(value, table):
    """sRGB-encoded value on 0 … 1 → linear light, from ``table`` (the decode at
    len(table) evenly spaced codes 0 … 1) by linear interpolation."""
    n = table.size - 1
    t = min(max(value, 0.0), 1.0) * n
    k = min(int(t), n - 1)
    f = t - k
    return table[k] * (1.0 - f) + table[k + 1] * f


@njit(cache=True, parallel=True)
def bake(codes, shading, warp, bound_uv, tiles, offsets, closest, table, full, corner, out):
    """out (h, w, 3) uint16 ← the blend of the three texture lookups (see the module
    docstring of designer.render.texture_bake) × 65535, for the window of a bake of
    ``full`` (H, W) texels whose top left texel is ``corner`` (row, column) of it; rows
    and columns past the bake's edges repeat its edge texels (Blender's EXTEND)."""
    H, W = full[0], full[1]
    tx, ty = tiles[0], tiles[1]
    for r in prange(out.shape[0]):
        i = min(max(r + corner[0], 0), H - 1)
        w = np.empty(3)
        planes = np.empty(3)
        t = np.empty(3)
        colour = np.empty(3)
        v = 1.0 - (i + 0.5) / H
        for col in range(out.shape[1]):
            j = min(max(col + corner[1], 0), W - 1)
            u = (j + 0.5) / W
            _sample(warp, u, v, False, False, w)
            lu = u + (w[0] * (2.0 * bound_uv) - bound_uv)
            lv = v + (w[1] * (2.0 * bound_uv) - bound_uv)
            _sample(shading, u, v, False, False, planes)
            _sample(codes, lu * tx, lv * ty, True, closest, t)
            for c in range(3):
                colour[c] = _decode(t[c], table)
            for k in range(2):
                sx = -tx if k == 0 else tx
                sy = ty if k == 0 else -ty
                _sample(codes, lu * sx + offsets[k, 0], lv * sy + offsets[k, 1], True,
                        closest, t)
                f = planes[k + 1]
                for c in range(3):
                    colour[c] = colour[c] * (1.0 - f) + _decode(t[c], table) * f
            for c in range(3):
                value = colour[c] * planes[0] * 65535.0
                out[r, col, c] = np.uint16(min(max(math.floor(value + 0.5), 0.0), 65535.0))


@njit(cache=True, parallel=True)
def fold_light_bgr(baked, light, out):
    """out (h, w, 3) uint16 BGR ← ``baked`` (h, w, 3) uint16 RGB times ``light`` (h, w)
    float32, rounded half to even and clipped to 0 … 65535: the float32 product
    ``baked.astype(float32) * light[..., None]`` texel by texel, in the channel order
    OpenCV writes."""
    for r in prange(baked.shape[0]):
        for col in range(baked.shape[1]):
            f = light[r, col]
            for c in range(3):
                p = np.rint(np.float32(baked[r, col, c]) * f)
                out[r, col, 2 - c] = np.uint16(min(max(p, np.float32(0.0)),
                                                   np.float32(65535.0)))
