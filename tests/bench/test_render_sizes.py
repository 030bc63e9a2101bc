"""designer bench render-sizes' grown example: the same texels whether its texture is the
example's procedural pattern or an image file holding it."""

from __future__ import annotations

import numpy as np

from designer.bench.render_sizes import TILE_M, grown_example
from designer.scene.build import build_texture


def test_the_image_texture_case_has_the_procedural_cases_texels(tmp_path):
    procedural = grown_example(500.0, 350.0)
    image = grown_example(500.0, 350.0, tmp_path / "texture.png")
    assert type(image.scene.texture.source).__name__ == "ImageTexture"
    assert image.scene.texture.repeat_X == procedural.scene.texture.repeat_X == 25
    assert image.scene.terrain == procedural.scene.terrain
    a = build_texture(procedural.scene.texture, procedural.scene.terrain, tmp_path)
    b = build_texture(image.scene.texture, image.scene.terrain, tmp_path)
    assert a.shape == b.shape == (round(TILE_M / 0.025),) * 2 + (3,)
    assert np.array_equal(a, b)
