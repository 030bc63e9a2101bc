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


def _bench(*args):
    import subprocess
    import sys

    return subprocess.run([sys.executable, "-m", "designer", "bench", *args],
                          capture_output=True, text=True, timeout=120)


def test_the_render_sizes_options_are_refused_where_they_mean_nothing():
    done = _bench("core", "--frames", "3")
    assert done.returncode != 0 and "only 'designer bench render-sizes'" in done.stderr
    done = _bench("render-sizes", "--texture-sources", "photo")
    assert done.returncode != 0 and "procedural, image or both" in done.stderr
    done = _bench("render-sizes", "--frames", "0")
    assert done.returncode != 0 and "--frames 0" in done.stderr
    assert "Traceback" not in done.stderr


def test_the_command_line_gives_run_its_options():
    import argparse

    from designer.bench import render_sizes
    from designer.cli.bench import _render_sizes_options

    args = argparse.Namespace(name="render-sizes", frames=12, node_graph=False,
                              texture_sources="image, procedural")
    assert _render_sizes_options(args, render_sizes) == {
        "frames": 12, "node_graph": False, "sources": ("image", "procedural")}
    args = argparse.Namespace(name="render-sizes", frames=None, node_graph=None,
                              texture_sources=None)
    assert _render_sizes_options(args, render_sizes) == {}
