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


@njit(cache=True, inline="always")
def code_of(v: float, thresholds: np.ndarray, first: np.ndarray) -> int:
    """The number of ``thresholds`` (ascending, on 0 … 1) that are ≤ v.

    ``first[b]`` is the number of thresholds below b / len(first): the search starts
    there, in v's bin, and steps past the (at most few) thresholds inside the bin.
    NaN counts as 0.
    """
    n_bins = first.size
    if not v > 0.0:
        return 0
    b = int(v * n_bins)
    if b >= n_bins:
        b = n_bins - 1
    code = first[b]
    m = thresholds.size
    while code < m and thresholds[code] <= v:
        code += 1
    return code


@njit(cache=True, parallel=True)
def search_codes(values: np.ndarray, thresholds: np.ndarray, first: np.ndarray,
                 out: np.ndarray) -> None:
    """out[k] = code_of(values[k]): with thresholds[c] the value half-way between codes
    c and c + 1 this rounds each value to its nearest code, clipped to the range."""
    flat = values.ravel()
    dst = out.ravel()
    n = flat.size
    for b in prange((n + _BLOCK - 1) // _BLOCK):
        for k in range(b * _BLOCK, min(n, (b + 1) * _BLOCK)):
            dst[k] = code_of(flat[k], thresholds, first)


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


@njit(cache=True, inline="always")
def encode_value(v: float, table: np.ndarray) -> float:
    """The sRGB curve of one linear value, clipped to 0 … 1: linear interpolation in
    ``table``, the curve at n + 1 equally spaced points of 0 … 1 (with 2^16 intervals
    within 1e-7 of the curve: its second derivative is at most ~2.4e3 above the knee;
    the interval holding the knee is computed exactly)."""
    if not v > 0.0:
        return 0.0
    if v >= 1.0:
        return 1.0
    if v <= 0.0031308:
        return 12.92 * v
    n = table.size - 1
    x = v * n
    i = int(x)
    if i <= 0.0031308 * n:  # the interval holding the knee, where the slope jumps
        return 1.055 * v ** (1.0 / 2.4) - 0.055
    t = x - i
    return table[i] + t * (table[i + 1] - table[i])


@njit(cache=True, inline="always")
def code_from_encoded(x: float, top: int) -> int:
    """clip(rint(x · top), 0, top), half to even."""
    r = np.rint(x * top)
    if not r > 0.0:
        return 0
    if r > top:
        return top
    return int(r)


@njit(cache=True, parallel=True)
def srgb_encode(linear: np.ndarray, table: np.ndarray) -> np.ndarray:
    """float32 linear light (any shape) → float32 sRGB-encoded values, clipped to 0 … 1
    (``encode_value``)."""
    flat = linear.ravel()
    out = np.empty(flat.size, dtype=np.float32)
    n = flat.size
    for b in prange((n + _BLOCK - 1) // _BLOCK):
        for k in range(b * _BLOCK, min(n, (b + 1) * _BLOCK)):
            out[k] = encode_value(float(flat[k]), table)
    return out.reshape(linear.shape)


@njit(cache=True, parallel=True)
def quantise_codes(encoded: np.ndarray, top: int, out: np.ndarray) -> None:
    """out = clip(rint(encoded · top), 0, top) (half to even), any shape."""
    flat = encoded.ravel()
    dst = out.ravel()
    n = flat.size
    for b in prange((n + _BLOCK - 1) // _BLOCK):
        for k in range(b * _BLOCK, min(n, (b + 1) * _BLOCK)):
            dst[k] = code_from_encoded(float(flat[k]), top)
