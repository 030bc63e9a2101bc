"""The rendered terrain grows beyond the declared one without moving a hill or a texel."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest

from designer.core.heightfield import Heightfield
from designer.errors import DesignerError
from designer.project import model as m
from designer.project.templates import template
from designer.scene.build import build_heightfield, build_scene
from designer.scene.surroundings import Growth, grow_terrain, grown_extent, surroundings_mode


def _example() -> m.Project:
    return template("survey").project


def test_the_default_is_auto_for_generated_terrain_and_none_for_files():
    p = _example()
    assert surroundings_mode(p.scene.terrain) == "auto"
    flat = dataclasses.replace(p.scene.terrain, source=m.FlatTerrain(0.0))
    assert surroundings_mode(flat) == "auto"
    dem = dataclasses.replace(p.scene.terrain, source=m.DemTerrain("dem.tif"))
    assert surroundings_mode(dem) == "none"
    assert surroundings_mode(dataclasses.replace(dem, surroundings="auto")) == "auto"


def test_procedural_terrain_grows_by_whole_tiles_and_keeps_every_declared_height():
    p = _example()
    declared = build_heightfield(p.scene.terrain, Path("."), p.crs)
    grown = grow_terrain(p, declared, Growth((3, 2, 1, 4)))
    hf = grown.heightfield
    # 20 m tiles (100 m over 5 repeats): 60 m west, 40 east, 20 south, 80 north
    assert hf.extent_m == pytest.approx((511890.0, 512090.0, 5405930.0, 5406130.0))
    assert (hf.dx_m, hf.dy_m) == (0.5, 0.5)
    inner = hf.heights_m[40:40 + 201, 120:120 + 201]
    np.testing.assert_allclose(inner, declared.heights_m, rtol=0, atol=1e-6)
    assert grown.texture_tiles((5, 5)) == (10, 10)
    # the hills continue: no step at the seam (neighbours differ as inside the extent)
    seam = np.abs(hf.heights_m[40:241, 120] - hf.heights_m[40:241, 119]).max()
    inside = np.abs(np.diff(declared.heights_m, axis=1)).max()
    assert seam <= 1.5 * inside


def test_a_dem_continues_at_its_edge_heights():
    p = _example()
    z = np.add.outer(np.arange(5.0), np.arange(7.0))
    declared = Heightfield(100.0, 200.0, 1.0, 1.0, z)
    dem = dataclasses.replace(p, scene=dataclasses.replace(p.scene, terrain=m.Terrain(
        m.Extent(100.0, 200.0, 106.0, 204.0), m.DemTerrain("dem.tif"), "auto"),
        texture=dataclasses.replace(p.scene.texture, source=m.OrthophotoTexture("o.tif"))))
    hf = grow_terrain(dem, declared, Growth((2, 1, 3, 0))).heightfield
    assert hf.extent_m == (98.0, 107.0, 197.0, 204.0)
    np.testing.assert_array_equal(hf.heights_m[3:, 2:9], z)
    np.testing.assert_array_equal(hf.heights_m[3:, 0], z[:, 0])     # west: the edge column
    np.testing.assert_array_equal(hf.heights_m[0], hf.heights_m[3])  # south: the edge row


def test_a_mesh_terrain_cannot_grow():
    p = _example()
    mesh = dataclasses.replace(p, scene=dataclasses.replace(p.scene, terrain=m.Terrain(
        p.scene.terrain.extent, m.MeshTerrain("t.ply"), "auto")))
    hf = Heightfield(0.0, 0.0, 1.0, 1.0, np.zeros((3, 3)))
    with pytest.raises(DesignerError, match="mesh terrain"):
        grow_terrain(mesh, hf, Growth((1, 0, 0, 0)))


def test_growth_covers_the_reach_with_a_margin_in_whole_steps():
    declared = (0.0, 100.0, 0.0, 100.0)
    grow = grown_extent(declared, (-41.5, 141.0, -10.0, 100.0), 20.0, 20.0, 0.5)
    assert grow == (3, 3, 1, 1)  # 41.5 m + 9.1 m margin → 3 tiles; 10 m + 9.1 → 1 tile
    assert grown_extent(declared, (10.0, 90.0, 10.0, 90.0), 20.0, 20.0, 0.5) == (0, 0, 0, 0)


def test_the_scene_keeps_the_texture_variation_fixed_to_the_ground():
    p = _example()
    plain = build_scene(p, Path("."))
    grown = build_scene(p, Path("."), Growth((1, 1, 1, 1)))
    assert grown.texture_tiles == (7, 7)
    assert np.array_equal(grown.texture_rgb, plain.texture_rgb)  # the same tile
    assert grown.declared_heightfield.extent_m == plain.heightfield.extent_m
    # the variation image's texels over the declared extent hold the same values
    a, b = plain.variation.shading, grown.variation.shading
    h, w = a.shape[:2]
    H, W = b.shape[:2]
    # texel centres over the declared extent, sampled in both images
    for fx, fy in ((0.1, 0.2), (0.5, 0.5), (0.9, 0.7)):
        ia, ja = int(fy * h), int(fx * w)
        x = (ja + 0.5) / w * 100.0 + 20.0  # metres from the grown extent's west edge
        y = (ia + 0.5) / h * 100.0 + 20.0  # from its north edge
        ib, jb = int(y / 140.0 * H), int(x / 140.0 * W)
        assert abs(int(a[ia, ja, 0]) - int(b[ib, jb, 0])) < 0.02 * 65535
