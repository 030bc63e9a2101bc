"""The exact sRGB transfer function (IEC 61966-2-1), between stored codes and linear light.

Blender's 'Standard' view transform writes sRGB-encoded PNG/TIFF files; every effect
whose physics is about light (warps, blur, vignetting, photon noise) must undo it first.

* decode: V = c / 12.92 for c <= 0.04045, else ((c + 0.055) / 1.055) ** 2.4
* encode: c = 12.92 V for V <= 0.0031308, else 1.055 V ** (1 / 2.4) − 0.055

with c the encoded value on 0 … 1 (code / largest code) and V linear light on 0 … 1.
The same curve applies to every channel, so channel order does not matter here.
Round trip code → linear (float32) → code is exact for every uint8 and uint16 code.
"""

from __future__ import annotations

import functools

import numpy as np

from designer.effects._pixel_kernels import look_up, quantise_codes, search_codes, srgb_encode

_DECODE_KNEE = 0.04045
_ENCODE_KNEE = 0.0031308


def srgb_to_linear(encoded: np.ndarray) -> np.ndarray:
    """sRGB-encoded values on 0 … 1 → linear light (float64 for float64 input, else float32)."""
    c = _float(encoded)
    return np.where(c <= _DECODE_KNEE, c / 12.92,
                    np.power((np.maximum(c, _DECODE_KNEE) + 0.055) / 1.055, 2.4)).astype(c.dtype)


def linear_to_srgb(linear: np.ndarray) -> np.ndarray:
    """Linear light on 0 … 1 → sRGB-encoded values on 0 … 1 (inputs are clipped to 0 … 1)."""
    if isinstance(linear, np.ndarray) and linear.dtype == np.float32 and linear.size > 4096:
        return srgb_encode(np.ascontiguousarray(linear), encode_table())  # all cores, ≤ 1e-7
    v = np.clip(_float(linear), 0.0, 1.0)
    return np.where(v <= _ENCODE_KNEE, 12.92 * v,
                    1.055 * np.power(np.maximum(v, _ENCODE_KNEE), 1.0 / 2.4) - 0.055
                    ).astype(v.dtype)


def _float(a: np.ndarray) -> np.ndarray:
    """float64 stays float64 (for reference values), everything else computes in float32."""
    a = np.asarray(a)
    return a if a.dtype in (np.float32, np.float64) else a.astype(np.float32)


@functools.lru_cache(maxsize=2)
def _decode_table(bits: int) -> np.ndarray:
    codes = np.arange(2**bits, dtype=np.float64) / (2**bits - 1)  # exact in float64
    table = srgb_to_linear(codes).astype(np.float32)
    table.flags.writeable = False
    return table


def max_code(dtype: np.dtype) -> int:
    """Largest code value of an unsigned integer image type (255, 65535)."""
    dtype = np.dtype(dtype)
    if dtype not in (np.uint8, np.uint16):
        raise TypeError(f"images must be uint8 or uint16, got {dtype}")
    return int(np.iinfo(dtype).max)


@functools.lru_cache(maxsize=2)
def code_thresholds(bits: int) -> tuple[np.ndarray, np.ndarray]:
    """(thresholds, first): the linear light half-way (in encoded value) between
    consecutive codes (float64), and for 2^(bits + 4) equal bins of 0 … 1 the number of
    thresholds below each bin's start (no bin holds more than one threshold, the
    narrowest gap being 1 / (12.92 · (2^bits − 1)))."""
    top = 2**bits - 1
    thresholds = srgb_to_linear((np.arange(top, dtype=np.float64) + 0.5) / top)
    n_bins = 2 ** (bits + 4)
    first = np.searchsorted(thresholds, np.arange(n_bins) / n_bins, side="left")
    first = first.astype(np.int32)
    thresholds.flags.writeable = False
    first.flags.writeable = False
    return thresholds, first


@functools.lru_cache(maxsize=1)
def encode_table() -> np.ndarray:
    """The encoding curve at 2^16 + 1 equally spaced linear values of 0 … 1 (float64), for
    the compiled kernels' interpolation (within 1e-7 of the curve)."""
    table = linear_to_srgb(np.linspace(0.0, 1.0, 2**16 + 1))
    table.flags.writeable = False
    return table


def decode_image(image: np.ndarray) -> np.ndarray:
    """uint8/uint16 sRGB image → float32 linear light on 0 … 1 (table look-up, exact)."""
    bits = 8 if max_code(image.dtype) == 255 else 16
    return look_up(np.ascontiguousarray(image), _decode_table(bits))


def encode_image(linear: np.ndarray, dtype: np.dtype) -> np.ndarray:
    """Linear light → sRGB-encoded uint8/uint16: the nearest code, clipped to the range.

    Exact: the code is found among the linear values half-way between codes (computed
    in float64), not through a float32 power function.
    """
    dtype = np.dtype(dtype)
    bits = 8 if max_code(dtype) == 255 else 16
    values = np.ascontiguousarray(linear, dtype=np.float32)
    out = np.empty(values.shape, dtype=dtype)
    search_codes(values, *code_thresholds(bits), out)
    return out


def quantise(encoded: np.ndarray, dtype: np.dtype) -> np.ndarray:
    """Encoded values on 0 … 1 → codes of ``dtype``, rounded half to even and clipped."""
    top = max_code(dtype)
    values = np.ascontiguousarray(encoded, dtype=np.float32)
    out = np.empty(values.shape, dtype=dtype)
    quantise_codes(values, top, out)
    return out
