"""The texture variation's fields: bounded, seeded, not periodic, fixed to the ground."""

from __future__ import annotations

import numpy as np
import pytest

from designer.project import model as m
from designer.scene.texture_variation import (
    GAIN_ENCODING,
    noise,
    variation_images,
    variation_layers,
    warp_bound_m,
)

V = m.TextureVariation(seed=7, scale_m=40.0, strength=0.35, octaves=4)


def test_fields_stay_in_their_ranges():
    rng = np.random.default_rng(1)
    x, y = rng.uniform(0, 500, 20000), rng.uniform(0, 500, 20000)
    f = variation_layers(V, x, y)
    assert np.all(np.abs(f["gain"] - 1) <= V.strength)
    # the swing is used, not only bounded: about ±0.76 strength at one sigma
    assert 0.5 * V.strength < np.std(f["gain"]) < V.strength
    for name in ("mix_a", "mix_b"):
        assert f[name].min() >= 0 and f[name].max() <= 1 and np.ptp(f[name]) > 0.9
    bound = warp_bound_m(V)
    assert bound == pytest.approx(0.35 * 0.15 * 40)
    for name in ("warp_x_m", "warp_y_m"):
        assert np.all(np.abs(f[name]) <= bound) and np.std(f[name]) > 0.3 * bound


def test_same_seed_same_field_other_seed_other_field():
    x, y = np.meshgrid(np.linspace(0, 100, 50), np.linspace(0, 100, 50))
    a = noise(3, 0, 20.0, 4, x, y)
    assert np.array_equal(a, noise(3, 0, 20.0, 4, x, y))
    assert np.corrcoef(a.ravel(), noise(4, 0, 20.0, 4, x, y).ravel())[0, 1] < 0.5
    # a point's value does not depend on the other points asked for
    assert noise(3, 0, 20.0, 4, x[7, 9], y[7, 9]) == a[7, 9]


@pytest.mark.parametrize("period_m", [10.0, 20.0, 25.0])
def test_no_repeat_at_tile_periods(period_m):
    """A tiled texture is identical one tile on; the variation is not."""
    rng = np.random.default_rng(2)
    x, y = rng.uniform(0, 400, 5000), rng.uniform(0, 400, 5000)
    here, there = variation_layers(V, x, y), variation_layers(V, x + period_m, y)
    for name in ("gain", "mix_a", "warp_x_m"):
        r = np.corrcoef(here[name], there[name])[0, 1]
        assert r < 0.8, (name, r)
        # still smooth: a step far below the finest wavelength (5 m) changes little
    near = variation_layers(V, x + 0.1, y)
    assert np.corrcoef(here["gain"], near["gain"])[0, 1] > 0.99


def test_images_hold_the_fields_at_texel_centres():
    extent = (512000.0, 512100.0, 5406000.0, 5406060.0)
    img = variation_images(V, extent)
    h, w = img.shading.shape[:2]
    assert img.shading.dtype == np.uint16 and img.warp.shape == (h, w, 3)
    # 8 texels per finest wavelength (40 / 2^3 = 5 m): 0.625 m texels
    assert (w, h) == (160, 96)
    j, i = 10, 37  # row 10 from the north, column 37 from the west
    x = 512000.0 + (i + 0.5) * 100.0 / w
    y = 5406060.0 - (j + 0.5) * 60.0 / h
    f = variation_layers(V, np.array(x), np.array(y))
    assert img.shading[j, i, 0] / 65535 * GAIN_ENCODING == pytest.approx(f["gain"], abs=1e-4)
    assert img.shading[j, i, 1] / 65535 == pytest.approx(f["mix_a"], abs=1e-4)
    warp_u = (img.warp[j, i, 0] / 65535 - 0.5) * 2 * img.warp_bound_uv
    assert warp_u * 100.0 == pytest.approx(f["warp_x_m"], abs=1e-3)
    # the fields are fixed to the world: a larger extent holds the same texels where it
    # covers the same ground (its texel grid is the same one, 0.625 m, shifted by 20 texels)
    grown = variation_images(V, (extent[0] - 12.5, extent[1] + 12.5, extent[2] - 12.5,
                                 extent[3] + 12.5))
    assert grown.shading.shape[:2] == (h + 40, w + 40)
    np.testing.assert_allclose(grown.shading[20:20 + h, 20:20 + w].astype(float),
                               img.shading.astype(float), atol=1.0)
