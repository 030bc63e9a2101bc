"""Compiled (numba) kernels of the resampler: cubic B-spline prefilter and sampling.

Images here are float32 (H, W, C) C-contiguous; positions are float64 continuous pixel
coordinates (u, v) (docs/conventions.md): element [k, l] has its centre at
(l + 0.5, k + 0.5). Rows are spread over
the threads (``prange``); every output element is computed by one thread from the same
inputs, so results do not depend on the number of threads.

The prefilter turns samples into cubic B-spline coefficients (two first-order recursive
filters per axis, pole z = √3 − 2, gain 6; Unser 1999, "Splines: a perfect fit for signal
and image processing"), with mirror-symmetric boundaries. Interpolating the coefficients
with the cubic B-spline then reproduces every sample exactly and is exact for cubic
polynomials away from the edges.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit, prange

_POLE = math.sqrt(3.0) - 2.0
_GAIN = 6.0
#: terms of the causal initial sum: |z|^k < 1e-9 beyond this
_HORIZON = min(64, math.ceil(math.log(1e-9) / math.log(abs(_POLE))))


@njit(cache=True, parallel=True, fastmath=True)
def bspline_coefficients(image: np.ndarray) -> np.ndarray:
    """(H, W, C) float32 samples → (H, W, C) float32 cubic B-spline coefficients.

    Both passes run along memory rows: the x pass filters each image row (its C channels
    together), the y pass filters a band of whole columns at once, row after row.
    """
    h, w, c = image.shape
    out = np.empty_like(image)
    z = np.float32(_POLE)
    # both passes' gains, applied in the first: 6 per axis longer than one sample
    gain = np.float32((_GAIN if w > 1 else 1.0) * (_GAIN if h > 1 else 1.0))
    end = np.float32(_POLE / (_POLE * _POLE - 1.0))
    horizon = min(_HORIZON, w)
    for i in prange(h):
        src = image[i]
        row = out[i]
        if w == 1:
            for ch in range(c):
                row[0, ch] = src[0, ch] * gain
            continue
        for ch in range(c):  # causal init, mirror boundary
            acc = np.float32(0.0)
            zk = np.float32(1.0)
            for k in range(horizon):
                acc += zk * src[k, ch]
                zk *= z
            row[0, ch] = acc
        if c == 3:  # the values carried in registers, not reloaded from memory
            p0, p1, p2 = row[0, 0], row[0, 1], row[0, 2]
            for k in range(1, w):
                p0 = src[k, 0] + z * p0
                p1 = src[k, 1] + z * p1
                p2 = src[k, 2] + z * p2
                row[k, 0] = p0
                row[k, 1] = p1
                row[k, 2] = p2
        else:
            for k in range(1, w):
                for ch in range(c):
                    row[k, ch] = src[k, ch] + z * row[k - 1, ch]
        # anticausal sweep, the gains applied as each value is written
        following = np.empty(c, dtype=np.float32)
        for ch in range(c):
            following[ch] = end * (row[w - 1, ch] + z * row[w - 2, ch])
            row[w - 1, ch] = gain * following[ch]
        if c == 3:
            f0, f1, f2 = following[0], following[1], following[2]
            for k in range(w - 2, -1, -1):
                f0 = z * (f0 - row[k, 0])
                f1 = z * (f1 - row[k, 1])
                f2 = z * (f2 - row[k, 2])
                row[k, 0] = gain * f0
                row[k, 1] = gain * f1
                row[k, 2] = gain * f2
        else:
            for k in range(w - 2, -1, -1):
                for ch in range(c):
                    following[ch] = z * (following[ch] - row[k, ch])
                    row[k, ch] = gain * following[ch]
    if h > 1:
        flat = out.reshape(h, w * c)  # a column band of the image is a band of this
        horizon = min(_HORIZON, h)
        n_bands = 32
        width = w * c
        band = (width + n_bands - 1) // n_bands
        for b in prange(n_bands):
            j0 = b * band
            j1 = min(width, j0 + band)
            zk = z
            for k in range(1, horizon):
                for j in range(j0, j1):
                    flat[0, j] += zk * flat[k, j]
                zk *= z
            for i in range(1, h):
                for j in range(j0, j1):
                    flat[i, j] += z * flat[i - 1, j]
            for j in range(j0, j1):
                flat[h - 1, j] = end * (flat[h - 1, j] + z * flat[h - 2, j])
            for i in range(h - 2, -1, -1):
                for j in range(j0, j1):
                    flat[i, j] = z * (flat[i + 1, j] - flat[i, j])
    return out


@njit(cache=True, inline="always")
def _bspline_weights(t: float) -> tuple[float, float, float, float]:
    """Cubic B-spline weights of the taps at −1, 0, +1, +2 for a fraction t in [0, 1)."""
    one = np.float32(1.0)
    sixth = np.float32(1.0 / 6.0)
    s = one - t
    t2 = t * t
    w0 = s * s * s * sixth
    w3 = t2 * t * sixth
    w1 = np.float32(2.0 / 3.0) - np.float32(0.5) * t2 * (np.float32(2.0) - t)
    w2 = one - w0 - w1 - w3
    return w0, w1, w2, w3


@njit(cache=True, inline="always")
def _clamp(k: int, n: int) -> int:
    return 0 if k < 0 else (n - 1 if k > n - 1 else k)


@njit(cache=True, inline="always")
def _mirror(k: int, n: int) -> int:
    """Index k reflected about the first and last element (…, 2, 1, 0, 1, 2, …), then
    clamped: the extension the mirror-boundary prefilter assumes."""
    if k < 0:
        k = -k
    if k > n - 1:
        k = 2 * (n - 1) - k
    return _clamp(k, n)


@njit(cache=True, parallel=True, fastmath=True)
def sample_cubic(coeffs: np.ndarray, u_px: np.ndarray, v_px: np.ndarray, factor: int
                 ) -> np.ndarray:
    """Cubic B-spline interpolation of ``coeffs`` (H_s, W_s, C) at the continuous pixel
    positions (u_px, v_px) (both (H·factor, W·factor) float64; element [k, l] has its
    centre at u = l + 0.5, v = k + 0.5), averaged over factor × factor blocks
    → (H, W, C) float32. Beyond the edges the image is mirrored about the edge pixels'
    centres (as the prefilter assumes), so every sample is reproduced exactly.

    The fraction of a position is taken in float64 (exact to 1e-12 px at any image size);
    weights and sums are float32 (relative error ~1e-7 of the values).
    """
    hs, ws, c = coeffs.shape
    ho, wo = u_px.shape[0] // factor, u_px.shape[1] // factor
    out = np.zeros((ho, wo, c), dtype=np.float32)
    norm = np.float32(1.0 / (factor * factor))
    for i in prange(ho):
        row_acc = np.zeros((wo, c), dtype=np.float32)
        for a in range(factor):
            for j in range(wo):
                for b in range(factor):
                    r = v_px[i * factor + a, j * factor + b] - 0.5
                    q = u_px[i * factor + a, j * factor + b] - 0.5
                    r0 = math.floor(r)
                    q0 = math.floor(q)
                    tr = np.float32(r - r0)
                    tq = np.float32(q - q0)
                    wr0, wr1, wr2, wr3 = _bspline_weights(tr)
                    wq0, wq1, wq2, wq3 = _bspline_weights(tq)
                    ir0, iq0 = int(r0) - 1, int(q0) - 1
                    inside = 0 <= ir0 and ir0 + 3 < hs and 0 <= iq0 and iq0 + 3 < ws
                    q_0 = iq0 if inside else _mirror(iq0, ws)
                    q_1 = iq0 + 1 if inside else _mirror(iq0 + 1, ws)
                    q_2 = iq0 + 2 if inside else _mirror(iq0 + 2, ws)
                    q_3 = iq0 + 3 if inside else _mirror(iq0 + 3, ws)
                    for dr in range(4):
                        rr = ir0 + dr if inside else _mirror(ir0 + dr, hs)
                        wr = wr0 if dr == 0 else (wr1 if dr == 1 else (wr2 if dr == 2 else wr3))
                        for ch in range(c):
                            row_acc[j, ch] += wr * (wq0 * coeffs[rr, q_0, ch]
                                                    + wq1 * coeffs[rr, q_1, ch]
                                                    + wq2 * coeffs[rr, q_2, ch]
                                                    + wq3 * coeffs[rr, q_3, ch])
        for j in range(wo):
            for ch in range(c):
                out[i, j, ch] = row_acc[j, ch] * norm
    return out


@njit(cache=True, inline="always")
def _cubic_at_edge(coeffs: np.ndarray, ir0: int, iq0: int, wr: tuple, wq: tuple,
                   ch: int) -> float:
    """One channel of the 4 × 4 cubic sum with mirrored indices (near the edges)."""
    hs, ws = coeffs.shape[0], coeffs.shape[1]
    total = np.float32(0.0)
    for dr in range(4):
        rr = _mirror(ir0 + dr, hs)
        row = np.float32(0.0)
        for dq in range(4):
            row += wq[dq] * coeffs[rr, _mirror(iq0 + dq, ws), ch]
        total += wr[dr] * row
    return total


@njit(cache=True, parallel=True, fastmath=True)
def sample_cubic_rgb(coeffs: np.ndarray, u_px: np.ndarray, v_px: np.ndarray,
                     gain: np.ndarray) -> np.ndarray:
    """``sample_cubic`` for three channels and one sample per output pixel, the common
    case, written out (scalar sums, no index checks inside the image): ~2× faster.
    A non-empty ``gain`` (H, W) float32 multiplies each output pixel."""
    hs, ws = coeffs.shape[0], coeffs.shape[1]
    ho, wo = u_px.shape
    out = np.empty((ho, wo, 3), dtype=np.float32)
    with_gain = gain.size > 0
    for i in prange(ho):
        for j in range(wo):
            r = v_px[i, j] - 0.5
            q = u_px[i, j] - 0.5
            r0 = math.floor(r)
            q0 = math.floor(q)
            wr = _bspline_weights(np.float32(r - r0))
            wq = _bspline_weights(np.float32(q - q0))
            ir0, iq0 = int(r0) - 1, int(q0) - 1
            if not (0 <= ir0 and ir0 + 3 < hs and 0 <= iq0 and iq0 + 3 < ws):
                for ch in range(3):
                    out[i, j, ch] = _cubic_at_edge(coeffs, ir0, iq0, wr, wq, ch)
                    if with_gain:
                        out[i, j, ch] *= gain[i, j]
                continue
            a0 = np.float32(0.0)
            a1 = np.float32(0.0)
            a2 = np.float32(0.0)
            for dr in range(4):
                rr = ir0 + dr
                w = wr[0] if dr == 0 else (wr[1] if dr == 1 else (wr[2] if dr == 2 else wr[3]))
                a0 += w * (wq[0] * coeffs[rr, iq0, 0] + wq[1] * coeffs[rr, iq0 + 1, 0]
                           + wq[2] * coeffs[rr, iq0 + 2, 0] + wq[3] * coeffs[rr, iq0 + 3, 0])
                a1 += w * (wq[0] * coeffs[rr, iq0, 1] + wq[1] * coeffs[rr, iq0 + 1, 1]
                           + wq[2] * coeffs[rr, iq0 + 2, 1] + wq[3] * coeffs[rr, iq0 + 3, 1])
                a2 += w * (wq[0] * coeffs[rr, iq0, 2] + wq[1] * coeffs[rr, iq0 + 1, 2]
                           + wq[2] * coeffs[rr, iq0 + 2, 2] + wq[3] * coeffs[rr, iq0 + 3, 2])
            if with_gain:
                g = gain[i, j]
                a0 *= g
                a1 *= g
                a2 *= g
            out[i, j, 0] = a0
            out[i, j, 1] = a1
            out[i, j, 2] = a2
    return out


@njit(cache=True, parallel=True)
def sample_linear(image: np.ndarray, u_px: np.ndarray, v_px: np.ndarray, factor: int
                  ) -> np.ndarray:
    """Bilinear interpolation of ``image`` at (u_px, v_px), block-averaged like
    ``sample_cubic``; beyond the edge pixels' centres the edge value is repeated."""
    hs, ws, c = image.shape
    ho, wo = u_px.shape[0] // factor, u_px.shape[1] // factor
    out = np.empty((ho, wo, c), dtype=np.float32)
    norm = 1.0 / (factor * factor)
    for i in prange(ho):
        acc = np.empty(c)
        for j in range(wo):
            for ch in range(c):
                acc[ch] = 0.0
            for a in range(factor):
                for b in range(factor):
                    r = v_px[i * factor + a, j * factor + b] - 0.5
                    q = u_px[i * factor + a, j * factor + b] - 0.5
                    r0 = math.floor(r)
                    q0 = math.floor(q)
                    fr, fq = r - r0, q - q0
                    ir, iq = int(r0), int(q0)
                    ra, rb = _clamp(ir, hs), _clamp(ir + 1, hs)
                    qa, qb = _clamp(iq, ws), _clamp(iq + 1, ws)
                    for ch in range(c):
                        acc[ch] += ((1.0 - fr) * ((1.0 - fq) * image[ra, qa, ch]
                                                  + fq * image[ra, qb, ch])
                                    + fr * ((1.0 - fq) * image[rb, qa, ch]
                                            + fq * image[rb, qb, ch]))
            for ch in range(c):
                out[i, j, ch] = acc[ch] * norm
    return out
