import cv2
import numpy as np
import pytest

from designer.errors import DesignerError
from designer.scene.texture import (
    checkerboard_texture,
    load_texture,
    procedural_texture,
    texel_ground_size_m,
    write_texture_png,
)


def grey(img):
    return cv2.cvtColor(img, cv2.COLOR_RGB2GRAY).astype(np.float64)


def seam_steps(g):
    """Mean |step| across every vertical seam, column k to k+1; the last is the wrap."""
    return np.abs(np.roll(g, -1, axis=1) - g).mean(axis=0)


@pytest.mark.parametrize("kind", ["grass", "soil"])
def test_texture_is_seamless(kind):
    img = procedural_texture(1024, seed=21, kind=kind)
    for g in (grey(img), grey(img).T):  # east-west and north-south borders
        steps = seam_steps(g)
        wrap, inner = steps[-1], steps[:-1]
        # The border is statistically just another seam: inside the interior's range.
        assert inner.min() <= wrap <= inner.max()
        assert 0.8 < wrap / np.median(inner) < 1.25


def test_seam_test_detects_a_non_tileable_crop():
    # Control for the test above: a window of a larger texture does not wrap.
    crop = procedural_texture(2048, seed=21, kind="grass")[300:1324, 500:1524]
    for g in (grey(crop), grey(crop).T):
        steps = seam_steps(g)
        assert steps[-1] > steps[:-1].max()
        assert steps[-1] / np.median(steps[:-1]) > 1.4


@pytest.mark.parametrize("kind", ["grass", "soil"])
def test_sift_finds_dense_uniform_features_at_every_scale(kind):
    sift = cv2.SIFT_create()
    tex = procedural_texture(2048, seed=5, kind=kind)
    # Seen from 1x, 2x and 4x the height: 1024² px of the (tiled) texture shrunk with
    # area averaging, each time split into 16 different 256² crops.
    views = {1: tex[:1024, :1024], 2: tex, 4: np.tile(tex, (2, 2, 1))}
    for factor, view in views.items():
        small = cv2.resize(view, (1024, 1024), interpolation=cv2.INTER_AREA)
        g = cv2.cvtColor(small, cv2.COLOR_RGB2GRAY)
        counts = np.array([[len(sift.detect(g[i:i + 256, j:j + 256], None))
                            for j in range(0, 1024, 256)] for i in range(0, 1024, 256)])
        assert counts.min() >= 250, (factor, counts)
        assert counts.min() >= 0.5 * counts.max(), (factor, counts)


def test_sift_keypoints_span_many_octaves():
    g = cv2.cvtColor(procedural_texture(1024, seed=6, kind="grass"), cv2.COLOR_RGB2GRAY)
    sizes = np.array([k.size for k in cv2.SIFT_create().detect(g, None)])
    per_octave = np.histogram(sizes, bins=[0, 4, 8, 16, 32, 1e9])[0]
    assert np.all(per_octave >= 20), per_octave


def test_texture_colours_look_like_grass_and_soil():
    grass = procedural_texture(256, seed=1, kind="grass").reshape(-1, 3).mean(axis=0)
    soil = procedural_texture(256, seed=1, kind="soil").reshape(-1, 3).mean(axis=0)
    assert grass[1] > grass[0] > grass[2]  # green
    assert soil[0] > soil[1] > soil[2]  # brown
    assert 40 < soil.mean() < 160 and 40 < grass.mean() < 160  # neither dark nor washed out


def test_texture_is_deterministic_per_seed():
    a = procedural_texture(256, seed=3)
    b = procedural_texture(256, seed=3)
    c = procedural_texture(256, seed=4)
    assert a.dtype == np.uint8 and a.shape == (256, 256, 3)
    np.testing.assert_array_equal(a, b)
    assert np.abs(a.astype(int) - c.astype(int)).mean() > 10


def test_non_square_texture_is_width_by_height():
    img = procedural_texture((320, 200), seed=1, kind="soil")
    assert img.shape == (200, 320, 3)


def test_bad_texture_arguments():
    with pytest.raises(DesignerError, match="unknown texture kind 'snow'"):
        procedural_texture(64, seed=1, kind="snow")
    with pytest.raises(DesignerError, match="at least 16 x 16"):
        procedural_texture(8, seed=1)


# --------------------------------------------------------------------------- texel size
def test_texel_ground_size_arithmetic():
    extent = (500000.0, 500100.0, 5000000.0, 5000050.0)
    assert texel_ground_size_m(4096, extent) == (100 / 4096, 50 / 4096)
    assert texel_ground_size_m((2000, 1000), extent, tiles=(5, 2)) == (0.01, 0.025)
    assert texel_ground_size_m(1000, (0, 100, 0, 100), tiles=(10, 10)) == (0.01, 0.01)
    with pytest.raises(DesignerError, match="is empty"):
        texel_ground_size_m(1024, (0, 0, 0, 1))
    with pytest.raises(DesignerError, match="tiles must be > 0"):
        texel_ground_size_m(1024, (0, 1, 0, 1), tiles=(0, 1))


# --------------------------------------------------------------------------- checkerboard
def test_checkerboard_is_exact():
    img = checkerboard_texture((4, 3), 5)
    assert img.shape == (15, 20, 3) and img.dtype == np.uint8
    assert set(np.unique(img)) == {0, 255}
    assert np.all(img[:5, :5] == 0)  # top-left black
    assert np.all(img[:5, 5:10] == 255)
    assert np.all(img[5:10, :5] == 255)
    assert np.all(img[10:15, 15:20] == 255)  # row 2 + column 3 is odd
    assert np.all(img[..., 0] == img[..., 2])


def test_even_checkerboard_tiles():
    img = checkerboard_texture(4, 8)
    tiled = np.tile(img, (2, 2, 1))
    np.testing.assert_array_equal(tiled, checkerboard_texture(8, 8))


# --------------------------------------------------------------------------- files
def test_png_round_trip_keeps_rgb_order(tmp_path):
    img = procedural_texture(64, seed=2)
    img[0, 0] = (255, 0, 0)  # red stays red, not blue
    path = tmp_path / "tex.png"
    write_texture_png(img, path)
    np.testing.assert_array_equal(load_texture(path), img)
    assert cv2.imread(str(path))[0, 0].tolist() == [0, 0, 255]  # OpenCV sees BGR
    assert list(tmp_path.iterdir()) == [path]


def test_grey_rgba_and_16_bit_images_load_as_rgb8(tmp_path):
    g = np.arange(256, dtype=np.uint8).reshape(16, 16)
    cv2.imwrite(str(tmp_path / "g.png"), g)
    np.testing.assert_array_equal(load_texture(tmp_path / "g.png"),
                                  np.repeat(g[:, :, None], 3, axis=2))
    bgra = np.zeros((4, 4, 4), np.uint8)
    bgra[..., 0], bgra[..., 3] = 200, 17
    cv2.imwrite(str(tmp_path / "a.png"), bgra)
    assert load_texture(tmp_path / "a.png")[0, 0].tolist() == [0, 0, 200]
    deep = np.full((4, 4), 65535, np.uint16)
    cv2.imwrite(str(tmp_path / "d.png"), deep)
    assert np.all(load_texture(tmp_path / "d.png") == 255)


@pytest.mark.parametrize(
    ("name", "content", "message"),
    [
        ("missing.png", None, "does not exist"),
        ("empty.png", b"", "is empty"),
        ("notes.png", b"this is text, not pixels", "is not an image OpenCV can read"),
    ],
)
def test_bad_texture_files(tmp_path, name, content, message):
    path = tmp_path / name
    if content is not None:
        path.write_bytes(content)
    with pytest.raises(DesignerError) as info:
        load_texture(path)
    assert name in str(info.value) and message in str(info.value)
    assert "\n" not in str(info.value)


def test_write_refuses_non_images(tmp_path):
    with pytest.raises(DesignerError, match="must be"):
        write_texture_png(np.zeros((4, 4, 3)), tmp_path / "f.png")


def test_a_tile_too_large_is_named_in_the_texture_panels_words_and_metres(tmp_path):
    import dataclasses

    from designer.project import template
    from designer.scene.build import build_texture

    p = template("survey").project  # 100 x 100 m, repeat 5 x 5, 0.025 m texels
    e = p.scene.terrain.extent
    terrain = dataclasses.replace(p.scene.terrain,
                                  extent=dataclasses.replace(e, max_X=e.min_X + 1100))
    texture = dataclasses.replace(p.scene.texture, repeat_X=1, repeat_Y=1,
                                  source=dataclasses.replace(p.scene.texture.source,
                                                             texel_size_m=0.125))
    with pytest.raises(DesignerError) as error:
        build_texture(texture, terrain, tmp_path)
    said = str(error.value)
    assert ("texel size 0.125 m makes a tile (1100 × 100 m: the extent 1100 × 100 m over "
            "repeat X 1, repeat Y 1) 8800 × 800 texels, more than 8192; raise the texel size "
            "or repeat X/Y") in said, said
    assert "texel-size-m" not in said and " px" not in said, said
