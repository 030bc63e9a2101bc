"""The tiled bake (designer.render.tiled_bake) is the whole bake cut into windows: each
tile holds the whole bake's texels, its texture coordinates put them where the whole
bake has them, every face lies inside its tile's stored image, and each frame's tiles
cover what it sees."""

from __future__ import annotations

import cv2
import numpy as np
import pytest

from designer.core.heightfield import Heightfield
from designer.core.interior import InteriorOrientation
from designer.project import model as m
from designer.render.texture_bake import bake_varied_texture
from designer.render.tiled_bake import (
    TileGrid,
    face_tiles,
    frame_tiles,
    light_window,
    slot_of,
    slot_shape,
    slots_to_show,
    swap_frames,
    tile_grid,
)
from designer.scene.terrain import heightfield_to_mesh
from designer.scene.texture_variation import variation_images

VARIATION = m.TextureVariation(seed=5, scale_m=20.0, strength=0.5)


def _inputs(rng):
    texture = rng.integers(0, 256, (24, 20, 3), dtype=np.uint8)
    return texture, (3.0, 2.0), variation_images(VARIATION, (0.0, 30.0, 0.0, 20.0))


def test_every_tile_is_a_window_of_the_whole_bake_with_its_edges_held():
    rng = np.random.default_rng(1)
    texture, tiles, variation = _inputs(rng)
    whole = bake_varied_texture(texture, tiles, variation)  # (48, 60)
    H, W = whole.shape[:2]
    grid = TileGrid((W, H), core_px=16, pad_px=3)
    assert (grid.columns, grid.rows) == (4, 3)
    for k in range(grid.count):
        r0, c0, h, w = grid.window(k)
        tile = bake_varied_texture(texture, tiles, variation, window=(r0, c0, h, w))
        rows = np.clip(np.arange(r0, r0 + h), 0, H - 1)
        cols = np.clip(np.arange(c0, c0 + w), 0, W - 1)
        np.testing.assert_array_equal(tile, whole[rows][:, cols])


def test_a_tiles_texture_coordinates_put_each_point_where_the_whole_bake_has_it():
    grid = TileGrid((1000, 700), core_px=256, pad_px=5)
    rng = np.random.default_rng(2)
    uv = rng.uniform(0, 1, (500, 2))
    k = grid.tile_of_uv(uv[:, 0], uv[:, 1])
    for point, tile in zip(uv, k, strict=True):
        (su, sv), (ou, ov) = grid.uv_transform(int(tile))
        r0, c0, h, w = grid.window(int(tile))
        ut, vt = point[0] * su + ou, point[1] * sv + ov
        # texel coordinates (x from the west, y from the north) in the tile and the whole
        assert ut * w == pytest.approx(point[0] * 1000 - c0, abs=1e-7)
        assert (1 - vt) * h == pytest.approx((1 - point[1]) * 700 - r0, abs=1e-7)
        # inside the core, a texel or more from the stored image's edges
        assert 5 - 1e-9 <= ut * w <= w - 5 + 1e-9 and 5 - 1e-9 <= (1 - vt) * h <= h - 5 + 1e-9


def test_every_face_lies_inside_its_tiles_stored_image():
    hf = Heightfield(0.0, 0.0, 0.5, 0.5, np.zeros((61, 81)))  # 40 × 30 m
    mesh = heightfield_to_mesh(hf)
    grid = tile_grid((2000, 1500), mesh.uv, mesh.faces, core_px=300)
    k = face_tiles(grid, mesh.uv, mesh.faces)
    assert len(np.unique(k)) == grid.count == 35
    for tile in range(grid.count):
        r0, c0, h, w = grid.window(tile)
        corners = mesh.uv[mesh.faces[k == tile]].reshape(-1, 2)
        x = corners[:, 0] * 2000 - c0
        y = (1 - corners[:, 1]) * 1500 - r0
        # a bilinear lookup reads the texel before and after: one texel to spare
        assert x.min() >= 1 and x.max() <= w - 1 and y.min() >= 1 and y.max() <= h - 1


def test_the_light_over_a_window_is_the_light_resized_to_the_bake():
    rng = np.random.default_rng(3)
    light = rng.uniform(0, 1, (37, 53)).astype(np.float32)
    whole = cv2.resize(light, (400, 300), interpolation=cv2.INTER_LINEAR)
    np.testing.assert_allclose(light_window(light, (400, 300), (0, 0, 300, 400)), whole,
                               atol=1e-4)
    part = light_window(light, (400, 300), (-4, 390, 20, 20))
    np.testing.assert_allclose(part, whole[np.clip(np.arange(-4, 16), 0, 299)][:, np.clip(
        np.arange(390, 410), 0, 399)], atol=1e-4)


def test_a_nadir_frame_loads_the_tiles_under_its_footprint_and_no_other():
    hf = Heightfield(0.0, 0.0, 20.0, 20.0, np.zeros((11, 11)))  # 200 × 200 m
    grid = TileGrid((8000, 8000), core_px=1000, pad_px=4)  # tiles of 25 m
    interior = InteriorOrientation(8.8, 13.2, 8.8, 660, 440)
    (tiles,) = frame_tiles(grid, hf.extent_m, hf, np.array([[55.0, 140.0, 50.0]]),
                           np.eye(3)[None], [interior])
    # 75 × 50 m centred at (55, 140), grown 5 %: X 13.75 … 96.25 (columns 0 … 3), Y 112.5
    # … 167.5 (rows from the north 1 … 3)
    cols = sorted({t % 8 for t in tiles})
    rows = sorted({t // 8 for t in tiles})
    assert cols == [0, 1, 2, 3] and rows == [1, 2, 3]


def test_the_tiles_one_frame_sees_have_slots_of_their_own():
    grid = TileGrid((10000, 8000), core_px=1000, pad_px=4)  # 10 × 8 tiles
    seen = [grid.tiles_in(0.05, 0.25, 0.6, 0.75), grid.tiles_in(0.5, 0.62, 0.1, 0.3), ()]
    slots = slot_shape(grid, seen, spare=0)
    assert slots == (3, 3)  # at most three rows and three columns in one frame
    assert slot_shape(grid, seen) == (5, 5)  # and two spare rows and columns
    for tiles in seen:
        assert len(set(slot_of(grid, slots, list(tiles)).tolist())) == len(tiles)
    everything = slot_of(grid, slots, range(grid.count))
    assert set(everything.tolist()) == set(range(9))
    # a frame that sees the whole terrain: a slot per tile
    assert slot_shape(grid, [tuple(range(grid.count))]) == (8, 10)


def _line_of_frames(grid):
    """Frames along a line northwards over a 20 × 20 tile grid: each sees 3 columns and at
    most 2 rows of tiles, a tile row crossed every 4 frames."""
    frames = []
    for i in range(60):
        v1 = 0.95 - i * 0.0125
        frames.append(grid.tiles_in(0.31, 0.44, v1 - 0.06, v1))
    return frames


def _show_all(grid, slots, frames, look_ahead):
    shown, swaps = {}, 0
    for i, tiles in enumerate(frames):
        change = slots_to_show(grid, slots, shown, tiles, frames[i + 1:i + 1 + look_ahead])
        swaps += bool(change)
        shown.update(change)
        # every tile the frame sees is in its own slot
        assert all(shown[s] == k for s, k in zip(slot_of(grid, slots, list(tiles)).tolist(),
                                                 tiles, strict=True))
    return swaps


def test_a_swap_loads_the_next_frames_tiles_into_the_free_slots():
    grid = TileGrid((20000, 20000), core_px=1000, pad_px=4)
    frames = _line_of_frames(grid)
    spare = slot_shape(grid, frames)
    assert spare == (4, 5)
    without = _show_all(grid, slot_shape(grid, frames, spare=0), frames, 0)
    ahead = _show_all(grid, spare, frames, 20)
    # a row crossed every four frames: one swap per crossing without the free slots,
    # one per two (or fewer) crossings with them
    assert without >= 12
    assert ahead <= without / 2
    assert swap_frames(grid, spare, frames) == ahead


def test_a_frame_that_sees_its_slots_tiles_changes_nothing():
    grid = TileGrid((20000, 20000), core_px=1000, pad_px=4)
    slots = (5, 5)
    tiles = grid.tiles_in(0.31, 0.44, 0.5, 0.56)
    shown = slots_to_show(grid, slots, {}, tiles, [grid.tiles_in(0.31, 0.44, 0.4, 0.46)])
    assert set(tiles) <= set(shown.values()) and len(shown) > len(tiles)
    # the same frame again, with other frames to come: no change (no scene update)
    assert slots_to_show(grid, slots, shown, tiles, [grid.tiles_in(0.6, 0.7, 0.1, 0.2)]) == {}
