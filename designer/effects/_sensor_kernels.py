"""Compiled (numba) kernels of the sensor model: counter-based random numbers, noise, ADC.

Random numbers are counter based: the draw number ``n`` of element ``i`` of a frame is
SplitMix64(key + (i·64 + n)·γ), γ = 0x9E3779B97F4A7C15, with ``key`` a 64-bit word
derived from (seed, frame, stream) by NumPy's SeedSequence. An element's numbers thus
depend only on the key and its position: the image is the same on any number of
threads, and rows can be processed in any order. (SplitMix64 over a Weyl sequence is the
generator Java's SplittableRandom uses; it passes BigCrush.)

* uniform: the top 53 bits / 2⁵³ + 2⁻⁵⁴, in (0, 1), never 0 or 1;
* normal: the inverse normal CDF of a uniform (Acklam's rational approximation, relative
  error < 1.2e-9; |z| ≤ 8.3 since the uniform stays 2⁻⁵⁴ away from 0 and 1);
* Poisson: inversion for λ < 10, Hörmann's PTRS transformed rejection for λ ≥ 10
  (W. Hörmann, "The transformed rejection method for generating Poisson random
  variables", Insurance: Mathematics and Economics 12, 1993), both exact.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit, prange

from designer.effects._pixel_kernels import code_from_encoded, code_of, encode_value

_GAMMA = np.uint64(0x9E3779B97F4A7C15)
_M1 = np.uint64(0xBF58476D1CE4E5B9)
_M2 = np.uint64(0x94D049BB133111EB)
#: draws an element may use (its counters are i·64 … i·64 + 63)
DRAWS_PER_ELEMENT = 64


@njit(cache=True, inline="always")
def _mix(z: np.uint64) -> np.uint64:
    z = (z ^ (z >> np.uint64(30))) * _M1
    z = (z ^ (z >> np.uint64(27))) * _M2
    return z ^ (z >> np.uint64(31))


@njit(cache=True, inline="always")
def uniform(key: np.uint64, element: np.uint64, draw: np.uint64) -> float:
    """The uniform number in (0, 1) of draw ``draw`` of element ``element``."""
    counter = element * np.uint64(DRAWS_PER_ELEMENT) + draw
    bits = _mix(key + counter * _GAMMA) >> np.uint64(11)
    return (float(np.int64(bits)) + 0.5) * (1.0 / 9007199254740992.0)


# Acklam's inverse normal CDF coefficients
_A = (-3.969683028665376e+01, 2.209460984245205e+02, -2.759285104469687e+02,
      1.383577518672690e+02, -3.066479806614716e+01, 2.506628277459239e+00)
_B = (-5.447609879822406e+01, 1.615858368580409e+02, -1.556989798598866e+02,
      6.680131188771972e+01, -1.328068155288572e+01)
_C = (-7.784894002430293e-03, -3.223964580411365e-01, -2.400758277161838e+00,
      -2.549732539343734e+00, 4.374664141464968e+00, 2.938163982698783e+00)
_D = (7.784695709041462e-03, 3.224671290700398e-01, 2.445134137142996e+00,
      3.754408661907416e+00)
_P_LOW = 0.02425


@njit(cache=True, inline="always")
def normal_from_uniform(p: float) -> float:
    """Standard normal quantile of p in (0, 1)."""
    if p < _P_LOW:
        q = math.sqrt(-2.0 * math.log(p))
        x = ((((((_C[0] * q + _C[1]) * q + _C[2]) * q + _C[3]) * q + _C[4]) * q + _C[5])
             / ((((_D[0] * q + _D[1]) * q + _D[2]) * q + _D[3]) * q + 1.0))
    elif p <= 1.0 - _P_LOW:
        q = p - 0.5
        r = q * q
        x = ((((((_A[0] * r + _A[1]) * r + _A[2]) * r + _A[3]) * r + _A[4]) * r + _A[5]) * q
             / (((((_B[0] * r + _B[1]) * r + _B[2]) * r + _B[3]) * r + _B[4]) * r + 1.0))
    else:
        q = math.sqrt(-2.0 * math.log(1.0 - p))
        x = -((((((_C[0] * q + _C[1]) * q + _C[2]) * q + _C[3]) * q + _C[4]) * q + _C[5])
              / ((((_D[0] * q + _D[1]) * q + _D[2]) * q + _D[3]) * q + 1.0))
    return x


# Ziggurat of 128 layers for the standard normal (Marsaglia & Tsang 2000, "The
# Ziggurat Method for Generating Random Variables", J. Stat. Softw. 5(8), in the layout
# of Doornik 2005, "An Improved Ziggurat Method to Generate Normal Random Samples"):
# X[0] = V / f(R) is the base layer's equivalent width, X[1] = R the tail start,
# X[128] = 0; R_RATIO[i] = X[i+1] / X[i].
_ZIG_LAYERS = 128
_ZIG_R = 3.442619855899
_ZIG_V = 9.91256303526217e-3


def _ziggurat_tables() -> tuple[np.ndarray, np.ndarray]:
    x = np.empty(_ZIG_LAYERS + 1)
    f = math.exp(-0.5 * _ZIG_R * _ZIG_R)
    x[0] = _ZIG_V / f
    x[1] = _ZIG_R
    x[_ZIG_LAYERS] = 0.0
    for i in range(2, _ZIG_LAYERS):
        x[i] = math.sqrt(-2.0 * math.log(_ZIG_V / x[i - 1] + f))
        f = math.exp(-0.5 * x[i] * x[i])
    return x, x[1:] / x[:-1]


_ZIG_X, _ZIG_RATIO = _ziggurat_tables()


@njit(cache=True, inline="always")
def normal(key: np.uint64, element: np.uint64, first_draw: int) -> float:
    """A standard normal draw (ziggurat) from the element's counters first_draw, … ;
    one counter in ~99 % of cases (inlined), a few more otherwise."""
    counter = element * np.uint64(DRAWS_PER_ELEMENT) + np.uint64(first_draw)
    bits = _mix(key + counter * _GAMMA)
    i = int(bits & np.uint64(_ZIG_LAYERS - 1))
    # top 53 bits → (−1, 1); via int64, whose conversion to float is one instruction
    u = (float(np.int64(bits >> np.uint64(11))) + 0.5) * (2.0 / 9007199254740992.0) - 1.0
    if abs(u) < _ZIG_RATIO[i]:
        return u * _ZIG_X[i]
    return _normal_rejected(key, element, first_draw, i, u)


@njit(cache=True)
def _normal_rejected(key: np.uint64, element: np.uint64, first_draw: int, i: int,
                     u: float) -> float:
    """The ziggurat's rare branches, after the first draw (layer i, position u) missed
    its layer's rectangle."""
    draw = np.uint64(first_draw + 1)
    last = np.uint64(DRAWS_PER_ELEMENT - 1)
    while True:
        if i == 0:  # the tail beyond R (Marsaglia 1964)
            while draw + np.uint64(1) < last:
                xt = -math.log(uniform(key, element, draw)) / _ZIG_R
                yt = -math.log(uniform(key, element, draw + np.uint64(1)))
                draw += np.uint64(2)
                if yt + yt >= xt * xt:
                    return _ZIG_R + xt if u > 0.0 else -(_ZIG_R + xt)
            break
        x = u * _ZIG_X[i]
        f0 = math.exp(-0.5 * (_ZIG_X[i] * _ZIG_X[i] - x * x))
        f1 = math.exp(-0.5 * (_ZIG_X[i + 1] * _ZIG_X[i + 1] - x * x))
        if f1 + uniform(key, element, draw) * (f0 - f1) < 1.0:
            return x
        draw += np.uint64(1)
        if draw >= last:
            break
        counter = element * np.uint64(DRAWS_PER_ELEMENT) + draw
        bits = _mix(key + counter * _GAMMA)
        draw += np.uint64(1)
        i = int(bits & np.uint64(_ZIG_LAYERS - 1))
        u = (float(np.int64(bits >> np.uint64(11))) + 0.5) * (2.0 / 9007199254740992.0) - 1.0
        if abs(u) < _ZIG_RATIO[i]:
            return u * _ZIG_X[i]
    # more than 60 rejections in a row (never observed): the inverse CDF of the last one
    return normal_from_uniform(uniform(key, element, last))


@njit(cache=True)
def poisson(lam: float, key: np.uint64, element: np.uint64, first_draw: int) -> float:
    """An exact Poisson(λ) draw from the element's counters first_draw, first_draw + 1 …"""
    if lam <= 0.0:
        return 0.0
    draw = np.uint64(first_draw)
    if lam < 10.0:  # inversion: sequential search of the CDF
        u = uniform(key, element, draw)
        p = math.exp(-lam)
        cdf = p
        k = 0
        while u > cdf and k < 200:
            k += 1
            p *= lam / k
            cdf += p
        return float(k)
    # PTRS (Hörmann 1993)
    slam = math.sqrt(lam)
    loglam = math.log(lam)
    b = 0.931 + 2.53 * slam
    a = -0.059 + 0.02483 * b
    inv_alpha = 1.1239 + 1.1328 / (b - 3.4)
    v_r = 0.9277 - 3.6224 / (b - 2.0)
    last = np.uint64(first_draw + 31)
    while draw < last:
        u = uniform(key, element, draw) - 0.5
        v = uniform(key, element, draw + np.uint64(1))
        draw += np.uint64(2)
        us = 0.5 - abs(u)
        k = math.floor((2.0 * a / us + b) * u + lam + 0.43)
        if us >= 0.07 and v <= v_r:
            return k
        if k < 0.0 or (us < 0.013 and v > us):
            continue
        if (math.log(v) + math.log(inv_alpha) - math.log(a / (us * us) + b)
                <= -lam + k * loglam - math.lgamma(k + 1.0)):
            return k
    # 15 rejections in a row (probability < 1e-15): the normal approximation
    return max(0.0, math.floor(lam + slam * normal_from_uniform(uniform(key, element, last))
                               + 0.5))


@njit(cache=True, inline="always")
def _sensor_value(light: float, g: float, key: np.uint64, element: np.uint64,
                  electrons_per_unit: float, full_well_e: float, dark_e: float,
                  read_noise_e: float, levels: float, inv_levels: float, shot_noise: bool,
                  gaussian_above_e: float) -> float:
    """One value through the sensor (see ``sensor``): linear light out, 0 … 1."""
    lam = max(light * g, 0.0) * electrons_per_unit + dark_e
    if shot_noise and lam < gaussian_above_e:
        e = poisson(lam, key, element, 0)
        if read_noise_e > 0.0:
            e += read_noise_e * normal(key, element, 32)
    else:  # one normal for shot and read noise together
        var = read_noise_e * read_noise_e + (lam if shot_noise else 0.0)
        e = lam + math.sqrt(var) * normal(key, element, 32) if var > 0.0 else lam
    v = min(max(e, 0.0), full_well_e) / full_well_e
    if levels > 0.0:
        v = np.rint(v * levels) * inv_levels
    return v


@njit(cache=True, parallel=True)
def sensor(linear: np.ndarray, gain: np.ndarray, key: np.uint64, electrons_per_unit: float,
           full_well_e: float, dark_e: float, read_noise_e: float, levels: float,
           shot_noise: bool, gaussian_above_e: float, thresholds: np.ndarray,
           first: np.ndarray, encode_table: np.ndarray, out: np.ndarray) -> None:
    """Linear light (H, W, C) float32 → ``out`` (H, W, C) after the sensor.

    ``gain`` (H, W) float32 multiplies the light first (vignetting; ones for none).
    Electrons: λ = max(V·gain, 0)·electrons_per_unit + dark_e. Shot noise and dark
    current draw Poisson(λ) (their sum is Poisson); where λ ≥ gaussian_above_e the draw
    is λ + √λ·z instead (the same mean and variance; Poisson's skewness 1/√λ is then
    below 1/√gaussian_above_e). Read noise adds N(0, read_noise_e²). Then clip to
    0 … full_well_e, and with levels > 0 quantise to round(e / full_well_e · levels) /
    levels; levels = 0 keeps e / full_well_e unquantised.
    With empty ``thresholds`` ``out`` (float32) receives that linear value (with a
    non-empty ``encode_table``: its sRGB-encoded value, ``encode_value``); otherwise
    ``out`` (uint8/uint16) receives its code (``code_of`` with thresholds and first).
    """
    h, w, c = linear.shape
    inv_levels = 1.0 / levels if levels > 0.0 else 0.0
    to_codes = thresholds.size > 0
    encode = encode_table.size > 0
    for i in prange(h):
        for j in range(w):
            g = float(gain[i, j])
            for ch in range(c):
                element = np.uint64((i * w + j) * c + ch)
                v = _sensor_value(float(linear[i, j, ch]), g, key, element,
                                  electrons_per_unit, full_well_e, dark_e, read_noise_e,
                                  levels, inv_levels, shot_noise, gaussian_above_e)
                if to_codes:
                    out[i, j, ch] = code_of(v, thresholds, first)
                elif encode:
                    out[i, j, ch] = encode_value(v, encode_table)
                else:
                    out[i, j, ch] = v


@njit(cache=True, parallel=True)
def sensor_dn_codes(linear: np.ndarray, gain: np.ndarray, key: np.uint64,
                    electrons_per_unit: float, full_well_e: float, dark_e: float,
                    read_noise_e: float, levels: float, shot_noise: bool,
                    gaussian_above_e: float, encode_table: np.ndarray, dn_sigma: float,
                    dn_key: np.uint64, top: int, out: np.ndarray) -> None:
    """``sensor``, then N(0, dn_sigma²) from ``dn_key`` added to the encoded value and the
    codes 0 … top written to ``out``: ``add_normal_codes`` in the same pass, the same
    numbers."""
    h, w, c = linear.shape
    inv_levels = 1.0 / levels if levels > 0.0 else 0.0
    for i in prange(h):
        for j in range(w):
            g = float(gain[i, j])
            for ch in range(c):
                element = np.uint64((i * w + j) * c + ch)
                v = _sensor_value(float(linear[i, j, ch]), g, key, element,
                                  electrons_per_unit, full_well_e, dark_e, read_noise_e,
                                  levels, inv_levels, shot_noise, gaussian_above_e)
                x = np.float32(np.float32(encode_value(v, encode_table))
                               + np.float32(dn_sigma * normal(dn_key, element, 0)))
                out[i, j, ch] = code_from_encoded(float(x), top)


@njit(cache=True, parallel=True)
def add_normal(image: np.ndarray, key: np.uint64, sigma: float) -> np.ndarray:
    """image + N(0, σ²) per element (float32 in and out, any shape)."""
    flat = image.ravel()
    out = np.empty_like(flat)
    n = flat.size
    block = 1 << 16
    for b in prange((n + block - 1) // block):
        for k in range(b * block, min(n, (b + 1) * block)):
            out[k] = flat[k] + sigma * normal(key, np.uint64(k), 0)
    return out.reshape(image.shape)


@njit(cache=True, parallel=True)
def add_normal_codes(image: np.ndarray, key: np.uint64, sigma: float, top: int,
                     out: np.ndarray) -> None:
    """out = the codes of image + N(0, σ²) (``add_normal`` then rounding and clipping to
    0 … top, in one pass; the same numbers)."""
    flat = image.ravel()
    dst = out.ravel()
    n = flat.size
    block = 1 << 16
    for b in prange((n + block - 1) // block):
        for k in range(b * block, min(n, (b + 1) * block)):
            x = np.float32(flat[k] + np.float32(sigma * normal(key, np.uint64(k), 0)))
            dst[k] = code_from_encoded(float(x), top)
