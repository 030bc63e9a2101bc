"""Non-repeating, seeded large-scale variation of a tiled ground texture.

A tiled detail texture repeats exactly every tile: two images whose footprints do not
overlap can show the same pixels, and feature matching pairs them. The variation breaks
the repeat with three smooth, seeded, non-periodic fields over the terrain (multi-octave
value noise at world X, Y in metres, float64, :mod:`designer.scene.world_noise`):

* ``gain``: brightness factor ``1 + strength · n`` (n in [-1, 1]), so 1 ± strength;
* ``mix_a``, ``mix_b``: weights (0..1) that blend the detail texture with two mirrored,
  shifted copies of itself — ``lerp(lerp(T, T_mirror_u, mix_a), T_mirror_v, mix_b)`` —
  so the texel content at one tile position changes from place to place, not only its
  brightness (SIFT descriptors are normalised: a smooth brightness change alone leaves
  them equal).

The fields are sampled at the texel centres of one image covering the terrain extent
(:func:`variation_image`, 16-bit RGB: gain / 2, mix_a, mix_b) that the renderer reads
with bilinear interpolation through the terrain's UV, which maps the extent's world X, Y
— so the variation has no seams at tile borders and is fixed to the ground.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from designer.errors import DesignerError
from designer.project import model as m
from designer.project.scene_limits import VARIATION_MAX_PX
from designer.scene.world_noise import octave_sum

#: texels per wavelength of the finest octave
TEXELS_PER_FINEST_WAVELENGTH = 8
#: amplitude ratio of successive octaves
PERSISTENCE = 0.5
#: half width of the mix weights' transition, in units of the (tanh-mapped) noise value
MIX_SOFTNESS = 1.0
#: the random stream of each field
STREAMS = {"gain": 0, "mix_a": 1, "mix_b": 2, "warp_x": 3, "warp_y": 4}
#: largest texture-coordinate warp per unit strength, as a fraction of scale-m (the warp
#: stretches the texture locally by about 0.6 × this × strength at one sigma)
WARP_PER_STRENGTH = 0.15
#: the image stores gain / GAIN_ENCODING (gain is at most 2)
GAIN_ENCODING = 2.0
#: texture-coordinate offsets of the two mirrored copies (fractions of a tile)
MIRROR_OFFSETS = ((0.371, 0.613), (0.719, 0.287))


def finest_wavelength_m(variation: m.TextureVariation) -> float:
    """Wavelength of the finest octave (m): scale-m / 2^(octaves − 1)."""
    return variation.scale_m / 2 ** (variation.octaves - 1)


def variation_size_px(variation: m.TextureVariation, width_m: float,
                      length_m: float) -> tuple[int, int]:
    """(width_px, height_px) of the variation image over a ``width_m × length_m`` extent."""
    texel_m = finest_wavelength_m(variation) / TEXELS_PER_FINEST_WAVELENGTH
    texel_m = max(texel_m, max(width_m, length_m) / VARIATION_MAX_PX)
    return (max(2, math.ceil(width_m / texel_m)), max(2, math.ceil(length_m / texel_m)))


def noise(seed: int, stream: int, scale_m: float, octaves: int,
          x_m: np.ndarray, y_m: np.ndarray) -> np.ndarray:
    """Multi-octave value noise in (-1, 1) at world (x, y) metres (float64).

    Octave k has lattice spacing ``scale_m / 2^k``, its own random lattice offset and
    amplitude ``PERSISTENCE^k``; lattice values are uniform in [-1, 1] from a hash of
    (seed, stream, octave, lattice index), so the field has no period and a point's value
    does not depend on which other points are asked for. The sum is divided by its
    expected standard deviation and passed through tanh: about ±0.76 at one standard
    deviation, never beyond ±1.
    """
    total, std = octave_sum(seed, stream, scale_m, octaves, x_m, y_m,
                            persistence=PERSISTENCE)
    return np.tanh(total / std)


def _smoothstep(x: np.ndarray, lo: float, hi: float) -> np.ndarray:
    t = np.clip((x - lo) / (hi - lo), 0.0, 1.0)
    return t * t * (3.0 - 2.0 * t)


def warp_bound_m(variation: m.TextureVariation) -> float:
    """Largest displacement of the texture lookup (m): strength × WARP_PER_STRENGTH ×
    scale-m (the warp fields stay inside ± this)."""
    return variation.strength * WARP_PER_STRENGTH * variation.scale_m


def variation_layers(variation: m.TextureVariation, x_m: np.ndarray,
                     y_m: np.ndarray) -> dict[str, np.ndarray]:
    """The fields at world (x, y) metres: ``gain``
    (1 ± strength), ``mix_a`` and ``mix_b`` (0..1), ``warp_x_m`` and ``warp_y_m``
    (displacement of the texture lookup, m, within ± :func:`warp_bound_m`)."""
    v = variation

    def field(name: str) -> np.ndarray:
        return noise(v.seed, STREAMS[name], v.scale_m, v.octaves, x_m, y_m)

    bound = warp_bound_m(v)
    return {"gain": 1.0 + v.strength * field("gain"),
            "mix_a": _smoothstep(field("mix_a"), -MIX_SOFTNESS, MIX_SOFTNESS),
            "mix_b": _smoothstep(field("mix_b"), -MIX_SOFTNESS, MIX_SOFTNESS),
            "warp_x_m": bound * field("warp_x"), "warp_y_m": bound * field("warp_y")}


@dataclass(frozen=True)
class VariationImages:
    """The variation over the terrain's UV square, as the renderer reads it.

    ``shading`` (H, W, 3) uint16: gain / GAIN_ENCODING, mix_a, mix_b; ``warp`` (H, W, 3)
    uint16: 0.5 + warp_u / (2 warp_bound_uv), the same for v, then 0 — the warp in UV
    units (1 = the extent); row 0 north, column 0 west, each texel the fields at its
    centre.
    """

    shading: np.ndarray
    warp: np.ndarray
    warp_bound_uv: float


def variation_images(variation: m.TextureVariation,
                     extent_m: tuple[float, float, float, float]) -> VariationImages:
    """The variation images over ``extent_m`` = (x_min, x_max, y_min, y_max), the world
    area the terrain's UV 0..1 spans."""
    x_min, x_max, y_min, y_max = (float(c) for c in extent_m)
    width_m, length_m = x_max - x_min, y_max - y_min
    if not (width_m > 0 and length_m > 0):
        raise DesignerError(f"terrain extent {extent_m} is empty; the texture variation "
                            "needs an extent with x_max > x_min and y_max > y_min")
    w_px, h_px = variation_size_px(variation, width_m, length_m)
    # at world X, Y: the variation is fixed to the ground, whatever the extent
    x = x_min + (np.arange(w_px) + 0.5) * (width_m / w_px)
    y = y_max - (np.arange(h_px) + 0.5) * (length_m / h_px)
    f = variation_layers(variation, x[None, :], y[:, None])
    bound_m = max(warp_bound_m(variation), 1e-9)
    bound_uv = bound_m / min(width_m, length_m)
    warp_u = f["warp_x_m"] / width_m / (2 * bound_uv) + 0.5
    warp_v = f["warp_y_m"] / length_m / (2 * bound_uv) + 0.5
    return VariationImages(
        shading=_pack16((f["gain"] / GAIN_ENCODING, f["mix_a"], f["mix_b"])),
        warp=_pack16((warp_u, warp_v, np.zeros_like(warp_u))), warp_bound_uv=bound_uv)


def _pack16(planes) -> np.ndarray:
    out = np.empty((*planes[0].shape, 3), dtype=np.uint16)
    for channel, value in enumerate(planes):
        out[:, :, channel] = np.clip(np.rint(value * 65535.0), 0, 65535)
    return out
