"""The baked varied texture: Blender's lookup conventions and the blend of the node graph."""

from __future__ import annotations

import numpy as np
import pytest

from designer.effects.srgb import srgb_to_linear
from designer.render.texture_bake import (
    MAX_BAKE_PX,
    bake_size_px,
    bake_varied_texture,
    can_bake,
)
from designer.scene.texture_variation import GAIN_ENCODING, MIRROR_OFFSETS, VariationImages


def _texture(h=6, w=8, seed=0):
    return np.random.default_rng(seed).integers(0, 256, (h, w, 3), dtype=np.uint8)


def _variation(gain=1.0, mix_a=0.0, mix_b=0.0, warp_uv=(0.0, 0.0), bound=0.01, size=4):
    shading = np.empty((size, size, 3), np.uint16)
    for k, value in enumerate((gain / GAIN_ENCODING, mix_a, mix_b)):
        shading[..., k] = round(value * 65535)
    warp = np.zeros((size, size, 3), np.uint16)
    for k in range(2):
        warp[..., k] = round((0.5 + warp_uv[k] / (2 * bound)) * 65535)
    return VariationImages(shading, warp, bound)


def test_without_variation_the_bake_is_the_tiled_texture_in_linear_light():
    tex = _texture()
    baked = bake_varied_texture(tex, (3, 2), _variation(gain=1.0))
    assert baked.shape == (12, 24, 3)  # the texture's texels, 3 × 2 tiles
    expected = np.tile(srgb_to_linear(tex.astype(np.float64) / 255), (2, 3, 1)) / GAIN_ENCODING
    # the bake's texel centres are the texture's: each value is one texel, decoded
    assert np.max(np.abs(baked / 65535 - expected)) < 1e-4


def test_the_gain_scales_and_the_weights_blend_the_mirrored_copies():
    tex = _texture(seed=1)
    tiles = (2.0, 2.0)
    plain = bake_varied_texture(tex, tiles, _variation(gain=1.0)) / 65535
    brighter = bake_varied_texture(tex, tiles, _variation(gain=1.3)) / 65535
    assert brighter == pytest.approx(1.3 * plain, abs=2e-4)
    # mix_a = 1: the first mirrored copy alone: texture at (−tx u + du, ty v + dv)
    mirrored = bake_varied_texture(tex, tiles, _variation(mix_a=1.0)) / 65535
    H, W = mirrored.shape[:2]
    du, dv = MIRROR_OFFSETS[0]
    codes = tex.astype(np.float64) / 255
    h, w = tex.shape[:2]
    for i, j in ((0, 0), (3, 5), (H - 1, W - 1)):
        u, v = (j + 0.5) / W, 1 - (i + 0.5) / H
        x = ((-tiles[0] * u + du) * w - 0.5) % w
        y = ((1 - (tiles[1] * v + dv)) * h - 0.5) % h
        j0, i0 = int(np.floor(x)), int(np.floor(y))
        fx, fy = x - j0, y - i0
        c = codes
        value = ((1 - fy) * ((1 - fx) * c[i0, j0] + fx * c[i0, (j0 + 1) % w])
                 + fy * ((1 - fx) * c[(i0 + 1) % h, j0] + fx * c[(i0 + 1) % h, (j0 + 1) % w]))
        # the codes are interpolated, then decoded (as Cycles reads an 8-bit sRGB image)
        assert mirrored[i, j] == pytest.approx(srgb_to_linear(value) / GAIN_ENCODING, abs=1e-4)


def test_a_warp_of_one_texel_shifts_the_bake_by_one_texel():
    tex = _texture(seed=2)
    tiles = (1.0, 1.0)
    w = tex.shape[1]
    plain = bake_varied_texture(tex, tiles, _variation(bound=0.5))
    shifted = bake_varied_texture(tex, tiles, _variation(warp_uv=(1.0 / w, 0.0), bound=0.5))
    # looking up one texel further east shows the next texel's value (to the 16-bit warp
    # image's resolution)
    assert np.max(np.abs(shifted[:, :-1].astype(int) - plain[:, 1:].astype(int))) <= 8


def test_size_and_limit():
    assert bake_size_px((800, 800, 3), (5, 5)) == (4000, 4000)
    assert can_bake((800, 800, 3), (5, 5))
    assert not can_bake((800, 800, 3), (MAX_BAKE_PX // 800 + 1, 1))
    with pytest.raises(ValueError, match="uint8"):
        bake_varied_texture(np.zeros((4, 4, 3), np.uint16), (1, 1), _variation())


def test_the_light_fold_is_the_float32_product_rounded_to_even_in_opencvs_order():
    """The lit bake (the light map multiplied into the texture, render.job_terrain): texel
    by texel the float32 product, rounded half to even, clipped to 16 bits, written in
    OpenCV's BGR order; the halves and the overflow included."""
    from designer.render._bake_kernel import fold_light_bgr

    rng = np.random.default_rng(3)
    baked = rng.integers(0, 65536, (37, 53, 3), dtype=np.uint16)
    light = rng.uniform(0.0, 1.3, (37, 53)).astype(np.float32)
    baked[0, :3] = (1, 3, 5)
    light[0, :3] = 0.5  # 0.5, 1.5, 2.5 → 0, 2, 2
    out = np.empty_like(baked)
    fold_light_bgr(baked, light, out)
    expected = np.clip(np.rint(baked.astype(np.float32) * light[..., None]), 0, 65535)
    assert np.array_equal(out, expected.astype(np.uint16)[..., ::-1])
    assert list(out[0, 0, ::-1]) == [0, 2, 2]
    assert (out == 65535).any()  # light over 1 saturates
