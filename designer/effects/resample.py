"""Resampling an image at arbitrary continuous pixel positions, to float64 precision.

Positions are continuous pixel coordinates (docs/conventions.md): array element
[k, l] has its centre at (u, v) = (l + 0.5, k + 0.5).

The kernels (designer/effects/_resample_kernels.py, numba, all cores) take positions as
float64, so a sub-pixel position is used as it is. Why not cv2.remap: it quantises every
sub-pixel position to 1/32 px (INTER_BITS = 5). Measured on a ramp whose value is the
pixel's own u coordinate, sampled at the positions of a real lens warp (barrel
k1 = −0.3 and a 149° fisheye, 800 × 600 px): cv2.remap INTER_LINEAR is off by up to
0.0157 px (RMS 0.0090), INTER_CUBIC by up to 0.064 px (RMS 0.036), against the 0.001 px
this project allows; these kernels take positions exactly (float64 fractions) and sum
in float32, ~2e-7 of full scale (tests/effects/test_resample.py).
Cubic B-splines (order 3, prefiltered, so they interpolate) are the default: on warped
area-sampled checkerboards bilinear interpolation shifted corners systematically by up to
0.021 px (it blurs box-filtered edges asymmetrically at a fractional offset), cubic by
≤ 0.011 px. They agree with scipy.ndimage.map_coordinates (order 3) to 2e-7 of the
values away from the edges; the prefilter's mirror boundary differs from scipy's there.
Cost: `designer bench effects`.
"""

from __future__ import annotations

import numpy as np

from designer.effects._pixel_kernels import times_gain
from designer.effects._resample_kernels import (
    bspline_coefficients,
    sample_cubic,
    sample_cubic_rgb,
    sample_linear,
)

#: how far (px) from the image edge a position must be for the interpolation to be exact:
#: bilinear reaches 1 px; the cubic B-spline reaches 2 px, and its prefilter's boundary
#: condition (mirror) disturbs values near the edge by a factor 0.268 per px
#: (a linear ramp is off by 1.2e-3 px 4 px from the edge, < 1e-5 px at 8 px)
SUPPORT_PX = {1: 1.0, 3: 8.0}


def check_order(order: int) -> int:
    if order not in SUPPORT_PX:
        raise ValueError(f"interpolation order {order!r} must be 1 (bilinear) or 3 (cubic)")
    return order


def sample_image(image: np.ndarray, u_px: np.ndarray, v_px: np.ndarray, order: int = 3
                 ) -> np.ndarray:
    """Sample ``image`` (H, W) or (H, W, C) at continuous positions ``u_px``, ``v_px``
    (same shape S, float64) → float32 (S) or (S + (C,)).

    Beyond the centres of the edge pixels the image is mirrored (cubic) or the edge
    value repeated (bilinear).
    """
    u = np.asarray(u_px, dtype=np.float64)
    v = np.asarray(v_px, dtype=np.float64)
    if u.shape != v.shape:
        raise ValueError(f"u_px {u.shape} and v_px {v.shape} must have the same shape")
    out = warp_image(image, u.reshape(1, -1), v.reshape(1, -1), order)
    return out.reshape(u.shape + np.shape(image)[2:])


def warp_image(image: np.ndarray, u_px: np.ndarray, v_px: np.ndarray, order: int = 3,
               oversample: int = 1, gain: np.ndarray | None = None) -> np.ndarray:
    """Resample ``image`` (H_s, W_s[, C]) at the positions (u_px, v_px), two (H·oversample,
    W·oversample) float64 maps, averaging oversample × oversample samples per output
    pixel → float32 (H, W[, C]); then multiply by ``gain`` (H, W) float32 if given (in
    the same pass where the kernel allows)."""
    check_order(order)
    if u_px.shape != v_px.shape or u_px.ndim != 2:
        raise ValueError("u_px and v_px must be 2-D maps of the same shape")
    if u_px.shape[0] % oversample or u_px.shape[1] % oversample:
        raise ValueError(f"the maps {u_px.shape} are not a multiple of oversample = "
                         f"{oversample}")
    src = np.asarray(image)
    planes = src[:, :, None] if src.ndim == 2 else src
    planes = np.ascontiguousarray(planes, dtype=np.float32)
    u = np.ascontiguousarray(u_px, dtype=np.float64)
    v = np.ascontiguousarray(v_px, dtype=np.float64)
    if gain is not None:
        gain = np.ascontiguousarray(gain, dtype=np.float32)
        if gain.shape != (u.shape[0] // oversample, u.shape[1] // oversample):
            raise ValueError(f"gain {gain.shape} does not fit the output")
    if order == 3 and oversample == 1 and planes.shape[2] == 3:
        no_gain = np.empty((0, 0), np.float32)
        out = sample_cubic_rgb(bspline_coefficients(planes), u, v,
                               no_gain if gain is None else gain)
        gain = None
    elif order == 3:
        out = sample_cubic(bspline_coefficients(planes), u, v, oversample)
    else:
        out = sample_linear(planes, u, v, oversample)
    if gain is not None:
        out = times_gain(out, gain)
    return out[:, :, 0] if src.ndim == 2 else out


def block_mean(image: np.ndarray, factor: int) -> np.ndarray:
    """Average ``factor`` × ``factor`` blocks: (H·f, W·f[, C]) → (H, W[, C]) (area sampling)."""
    if factor == 1:
        return image
    h, w = image.shape[0] // factor, image.shape[1] // factor
    blocks = image.reshape(h, factor, w, factor, *image.shape[2:])
    return blocks.mean(axis=(1, 3), dtype=np.float64).astype(image.dtype)
