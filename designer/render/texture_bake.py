"""The varied ground texture baked into one image: one texture lookup per render sample.

The texture variation (:mod:`designer.scene.texture_variation`) is, per shading point
of the terrain: warp the lookup, look the tiled texture up three times (itself and two
mirrored, shifted copies), blend them by two variation weights and scale by the gain.
In Cycles that is five image lookups and a dozen nodes per sample, which more than
doubled the render time of the example survey (``designer bench render``,
docs/benchmarks.md). The renderer therefore reads this bake instead: the same blend
evaluated once per texel of a grid over the terrain's UV square at the detail
texture's own texel spacing, stored as linear light in a 16-bit image that the
renderer samples bilinearly (a half-float image in Blender).

What changes: where the warp moves the lookup by a fraction of a texel, the baked value
is already an interpolation, so the finest detail (one texel, 2.5 cm in the example) is
softened slightly more than by the renderer's own bilinear lookup; the blend happens in
linear light as before. Geometry is untouched: every GCP, surface and camera is where
it was, so the projection accuracy (docs/validation.md) holds. A project without a
variation, or with an orthophoto, renders as before byte for byte.

Conventions (Blender's): texture coordinate u runs west → east, v south → north over
the UV square; an image's texel (i, j) (row i from the top of the file) has its centre
at u = (j + 0.5) / W, v = 1 − (i + 0.5) / H; a ``REPEAT`` lookup wraps, ``EXTEND`` holds
the edge texels. Texture values are sRGB-encoded: bilinear interpolation of the codes,
then decoding to linear light (as Cycles does for an 8-bit sRGB image).
"""

from __future__ import annotations

import numpy as np

from designer.effects.srgb import srgb_to_linear
from designer.project import scene_limits
from designer.scene.texture_variation import GAIN_ENCODING, MIRROR_OFFSETS, VariationImages

#: the largest side of a bake (px); beyond it the renderer bakes in tiles
#: (designer.render.tiled_bake; a 4096² half-float image is 128 MB per render worker)
MAX_BAKE_PX = scene_limits.MAX_BAKE_PX
#: entries of the sRGB decode table the bake interpolates
DECODE_TABLE_SIZE = 1 << 16


def bake_size_px(texture_shape: tuple[int, ...], tiles: tuple[float, float]) -> tuple[int, int]:
    """(width, height) of the bake: the detail texture's texel spacing over the UV square."""
    h, w = texture_shape[:2]
    return round(w * tiles[0]), round(h * tiles[1])


def can_bake(texture_shape: tuple[int, ...], tiles: tuple[float, float]) -> bool:
    """True if the bake of such a texture fits :data:`MAX_BAKE_PX`."""
    w, h = bake_size_px(texture_shape, tiles)
    return 0 < w <= MAX_BAKE_PX and 0 < h <= MAX_BAKE_PX


def bake_varied_texture(texture_rgb: np.ndarray, tiles: tuple[float, float],
                        variation: VariationImages, interpolation: str = "linear",
                        window: tuple[int, int, int, int] | None = None) -> np.ndarray:
    """The varied texture over the UV square, (H, W, 3) uint16 linear light × 65535,
    divided by ``GAIN_ENCODING`` like the variation image (the material's strength holds
    the factor): row 0 north, column 0 west.

    ``texture_rgb``: the detail texture (uint8 sRGB codes, row 0 at the top), tiled
    ``tiles`` times over the square; ``interpolation`` 'linear' or 'closest', as the
    renderer looks it up; ``window`` (row, column, rows, columns): only that window of
    the bake, its rows and columns past the bake's edges holding the edge texels (one
    tile of a tiled bake, :mod:`designer.render.tiled_bake`: the same texels as the
    whole bake's).
    """
    texture = np.asarray(texture_rgb)
    if texture.dtype != np.uint8 or texture.ndim != 3 or texture.shape[2] != 3:
        raise ValueError(f"the detail texture must be (H, W, 3) uint8, got "
                         f"{texture.dtype} {texture.shape}")
    from designer.render._bake_kernel import bake

    W, H = bake_size_px(texture.shape, tiles)
    row, col, rows, cols = window if window is not None else (0, 0, H, W)
    out = np.empty((rows, cols, 3), np.uint16)
    bake(texture.astype(np.float32) / np.float32(255.0),
         variation.shading.astype(np.float32) / np.float32(65535.0),
         variation.warp.astype(np.float32) / np.float32(65535.0),
         float(variation.warp_bound_uv), np.asarray(tiles, np.float64),
         np.asarray(MIRROR_OFFSETS, np.float64), interpolation.lower() == "closest",
         _decode_table(), np.array([H, W], np.int64), np.array([row, col], np.int64), out)
    return out


def _decode_table() -> np.ndarray:
    """The sRGB decode at DECODE_TABLE_SIZE evenly spaced values 0 … 1 (float64): read
    with linear interpolation it is within 1e-8 of the formula."""
    return srgb_to_linear(np.linspace(0.0, 1.0, DECODE_TABLE_SIZE))


__all__ = ["GAIN_ENCODING", "MAX_BAKE_PX", "bake_size_px", "bake_varied_texture", "can_bake"]
