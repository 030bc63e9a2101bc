"""Compiled (numba) per-pixel kernels: table look-up, code search, gain. Rows are spread
over the threads; every element is computed alone, so results do not depend on the
number of threads."""

from __future__ import annotations

import numpy as np
from numba import njit, prange

_BLOCK = 1 << 16


@njit(cache=True, parallel=True)
def look_up(codes: np.ndarray, table: np.ndarray) -> np.ndarray:
    """table[codes] for integer ``codes`` of any shape → float32 of that shape."""
    flat = codes.ravel()
    out = np.empty(flat.size, dtype=np.float32)
    n = flat.size
    for b in prange((n + _BLOCK - 1) // _BLOCK):
        for k in range(b * _BLOCK, min(n, (b + 1) * _BLOCK)):
            out[k] = table[flat[k]]
    return out.reshape(codes.shape)


@njit(cache=True, parallel=True)
def search_codes(values: np.ndarray, thresholds: np.ndarray, out: np.ndarray) -> None:
    """out[k] = the number of ``thresholds`` (ascending) ≤ values[k] (binary search).

    With thresholds[c] the value half-way between codes c and c + 1 this rounds each
    value to its nearest code, clipped to 0 … len(thresholds).
    """
    flat = values.ravel()
    dst = out.ravel()
    n = flat.size
    m = thresholds.size
    for b in prange((n + _BLOCK - 1) // _BLOCK):
        for k in range(b * _BLOCK, min(n, (b + 1) * _BLOCK)):
            v = flat[k]
            lo, hi = 0, m  # answer in [lo, hi]
            while lo < hi:
                mid = (lo + hi) >> 1
                if thresholds[mid] <= v:
                    lo = mid + 1
                else:
                    hi = mid
            dst[k] = lo


@njit(cache=True, parallel=True)
def times_gain(image: np.ndarray, gain: np.ndarray) -> np.ndarray:
    """(H, W, C) float32 × (H, W) float32 gain → new (H, W, C) float32."""
    h, w, c = image.shape
    out = np.empty_like(image)
    for i in prange(h):
        for j in range(w):
            g = gain[i, j]
            for ch in range(c):
                out[i, j, ch] = image[i, j, ch] * g
    return out
