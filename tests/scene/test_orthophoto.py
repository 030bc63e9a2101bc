"""Orthophoto textures: texture coordinates from the geotransform, crops, CRSs, errors."""

import warnings

import numpy as np
import pytest

from designer.errors import DesignerError
from designer.scene.orthophoto import MARGIN_PX, load_orthophoto, orthophoto_uv

rasterio = pytest.importorskip("rasterio")
from rasterio.transform import Affine  # noqa: E402

UTM33 = "EPSG:32633 (WGS 84 / UTM zone 33N)"


def write_ortho(path, rgb, transform, crs="EPSG:32633"):
    rows, cols = rgb.shape[:2]
    profile = dict(driver="GTiff", height=rows, width=cols, count=3, dtype="uint8",
                   transform=transform)
    if crs is not None:
        profile["crs"] = crs
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", rasterio.errors.NotGeoreferencedWarning)
        with rasterio.open(path, "w", **profile) as dst:
            dst.write(np.moveaxis(rgb, -1, 0))
    return path


def numbered_rgb(rows, cols):
    """Each pixel's (row, col) encoded in its colour, so a crop's offset can be read."""
    r, c = np.meshgrid(np.arange(rows), np.arange(cols), indexing="ij")
    return np.stack([r % 256, c % 256, (r // 256) * 16 + c // 256], axis=-1).astype(np.uint8)


def test_uv_is_the_inverse_geotransform_by_hand(tmp_path):
    # 0.05 m pixels, corner at (533000.013, 5213050.02): the pixel (col 37, row 12) has
    # its outer top-left corner at X = 533000.013 + 37 * 0.05, Y = 5213050.02 - 12 * 0.05.
    west, north, px = 533000.013, 5213050.02, 0.05
    rgb = numbered_rgb(400, 600)
    path = write_ortho(tmp_path / "o.tif", rgb, Affine(px, 0, west, 0, -px, north))
    extent = (west + 5.0, north - 15.0, west + 25.0, north - 2.0)
    ortho = load_orthophoto(path, UTM33, extent)
    # The crop starts on the file's pixel grid, at least MARGIN_PX before the extent;
    # its geotransform says where.
    a, b, c, d, e, f = ortho.transform
    assert (a, b, d, e) == (px, 0.0, 0.0, -px)
    col0, row0 = round((c - west) / px), round((north - f) / px)
    assert abs((c - west) / px - col0) < 1e-6 and abs((north - f) / px - row0) < 1e-6
    assert col0 <= 5.0 / px - MARGIN_PX and row0 <= 2.0 / px - MARGIN_PX
    assert col0 >= 5.0 / px - MARGIN_PX - 1 and row0 >= 2.0 / px - MARGIN_PX - 1
    np.testing.assert_array_equal(ortho.rgb[0, 0], rgb[row0, col0])
    H, W = ortho.rgb.shape[:2]
    # By hand: the outer corner of crop pixel (col 10, row 7) and the centre of (3, 20).
    pts = np.array([[c + 10 * px, f - 7 * px], [c + 3.5 * px, f - 20.5 * px]])
    uv = orthophoto_uv(ortho, pts, UTM33)
    np.testing.assert_allclose(uv, [[10 / W, 1 - 7 / H], [3.5 / W, 1 - 20.5 / H]],
                               rtol=0, atol=1e-9)  # 1e-9 of the image: < 1e-6 px
    # The texel under the second point is the one the file holds at that place.
    col, row = int(uv[1, 0] * W), int((1 - uv[1, 1]) * H)
    np.testing.assert_array_equal(ortho.rgb[row, col], rgb[row0 + 20, col0 + 3])


def test_uv_through_another_utm_zone(tmp_path):
    # The same image registered in zone 33N, used by a project in zone 32N: a point's
    # uv must come from its zone-33 coordinates.
    from pyproj import Transformer

    west, north, px = 533000.0, 5213050.0, 0.1
    path = write_ortho(tmp_path / "o.tif", numbered_rgb(300, 300),
                       Affine(px, 0, west, 0, -px, north))
    to32 = Transformer.from_crs(32633, 32632, always_xy=True)
    corners33 = np.array([[west + 5, north - 25], [west + 25, north - 5]])
    X32, Y32 = to32.transform(corners33[:, 0], corners33[:, 1])
    extent32 = (X32.min() - 1, Y32.min() - 1, X32.max() + 1, Y32.max() + 1)
    label32 = "EPSG:32632 (WGS 84 / UTM zone 32N)"
    ortho = load_orthophoto(path, label32, extent32)
    target33 = np.array([[west + 12.34, north - 17.89]])
    X, Y = to32.transform(float(target33[0, 0]), float(target33[0, 1]))
    uv = orthophoto_uv(ortho, [[X, Y]], label32)
    H, W = ortho.rgb.shape[:2]
    a, _, c, _, e, f = ortho.transform
    expected = [((target33[0, 0] - c) / a) / W, 1 - ((target33[0, 1] - f) / e) / H]
    np.testing.assert_allclose(uv[0], expected, atol=1e-9)
    # ~1 km apart, the zones' grids are rotated against each other: a naive reading in
    # zone-32 coordinates would be metres off.
    assert abs(X - target33[0, 0]) > 1000


def test_orthophoto_that_does_not_cover_the_extent_is_refused(tmp_path):
    path = write_ortho(tmp_path / "small.tif", numbered_rgb(100, 100),
                       Affine(0.1, 0, 533000.0, 0, -0.1, 5213010.0))
    with pytest.raises(DesignerError, match=r"small\.tif covers X 533000\.000\.\.533010\.000"
                       r".*not the whole terrain extent.*shrink <extent>") as info:
        load_orthophoto(path, UTM33, (533001.0, 5213001.0, 533012.0, 5213009.0))
    assert "\n" not in str(info.value)


def test_orthophoto_without_crs_in_a_utm_project_is_refused(tmp_path):
    path = write_ortho(tmp_path / "nocrs.tif", numbered_rgb(50, 50),
                       Affine(0.1, 0, 533000.0, 0, -0.1, 5213005.0), crs=None)
    with pytest.raises(DesignerError, match=r"nocrs\.tif has no coordinate system.*gdal_edit"):
        load_orthophoto(path, UTM33, (533001.0, 5213001.0, 533004.0, 5213004.0))


def test_plain_tiff_is_refused_as_orthophoto(tmp_path):
    path = tmp_path / "plain.tif"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", rasterio.errors.NotGeoreferencedWarning)
        with rasterio.open(path, "w", driver="GTiff", height=8, width=8, count=3,
                           dtype="uint8") as dst:
            dst.write(np.zeros((3, 8, 8), np.uint8))
    with pytest.raises(DesignerError, match=r"plain\.tif has no georeferencing"):
        load_orthophoto(path, UTM33, (0.0, 0.0, 1.0, 1.0))
