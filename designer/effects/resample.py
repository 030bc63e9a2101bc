"""Resampling an image at arbitrary continuous pixel positions, to float64 precision.

Positions are continuous pixel coordinates (docs/conventions.md): array element
[k, l] has its centre at (u, v) = (l + 0.5, k + 0.5), so the array index sampled is
(v − 0.5, u − 0.5).

Why scipy.ndimage.map_coordinates and not cv2.remap: remap quantises every sub-pixel
position to 1/32 px (INTER_BITS = 5). Measured on a ramp whose value is the pixel's own
u coordinate, sampled at the positions of a real lens warp (barrel k1 = −0.3 and a 149°
fisheye, 800 × 600 px): cv2.remap INTER_LINEAR is off by up to 0.0157 px (RMS 0.0090),
INTER_CUBIC by up to 0.064 px (RMS 0.036), against the 0.001 px this project allows;
map_coordinates (float64 positions) by ≤ 5e-13 px bilinear and ≤ 5e-7 px cubic.
Cubic B-splines (order 3, prefiltered, so they interpolate) are the default: on warped
area-sampled checkerboards bilinear interpolation shifted corners systematically by up to
0.021 px (it blurs box-filtered edges asymmetrically at a fractional offset), cubic by
≤ 0.011 px. Cost for one 20 MP channel (33 MP source): remap 0.25 s, map_coordinates
order 1 ≈ 1 s, order 3 ≈ 2–3 s (prefilter 0.7 s); ndimage holds the GIL, so threads
do not help: parallelise over frames.
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage

#: how far (px) from the image edge a position must be for the interpolation to be exact:
#: bilinear reaches 1 px; the cubic B-spline reaches 2 px, and its prefilter's boundary
#: condition (edge repeated) disturbs values near the edge by a factor 0.268 per px
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

    Outside the image the nearest edge pixel is repeated (mode 'nearest').
    """
    check_order(order)
    coords = np.stack([v_px - 0.5, u_px - 0.5])
    src = np.asarray(image)
    if not np.issubdtype(src.dtype, np.floating):
        src = src.astype(np.float32)
    planes = [src] if src.ndim == 2 else [src[:, :, c] for c in range(src.shape[2])]
    out = [ndimage.map_coordinates(p, coords, order=order, mode="nearest", output=np.float32)
           for p in planes]
    return out[0] if src.ndim == 2 else np.stack(out, axis=-1)


def block_mean(image: np.ndarray, factor: int) -> np.ndarray:
    """Average ``factor`` × ``factor`` blocks: (H·f, W·f[, C]) → (H, W[, C]) (area sampling)."""
    if factor == 1:
        return image
    h, w = image.shape[0] // factor, image.shape[1] // factor
    blocks = image.reshape(h, factor, w, factor, *image.shape[2:])
    return blocks.mean(axis=(1, 3), dtype=np.float64).astype(image.dtype)
