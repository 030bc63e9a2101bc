import warnings

import numpy as np
import pytest

from designer.errors import DesignerError
from designer.scene.dem import load_dem

rasterio = pytest.importorskip("rasterio")
from rasterio.transform import Affine  # noqa: E402

WEST, NORTH, PIXEL = 500000.0, 5000000.0, 0.5


def from_origin(west, north, xsize, ysize):
    # rasterio.transform.from_origin multiplies Affines with `*`, which affine >= 3
    # reports as a PendingDeprecationWarning (an error in this test run).
    return Affine(xsize, 0.0, west, 0.0, -ysize, north)


def write_geotiff(path, heights, transform=None, crs="EPSG:32633", nodata=None,
                  dtype="float64"):
    rows, cols = heights.shape
    profile = dict(driver="GTiff", height=rows, width=cols, count=1, dtype=dtype,
                   transform=transform or from_origin(WEST, NORTH, PIXEL, PIXEL))
    if crs is not None:
        profile["crs"] = crs
    if nodata is not None:
        profile["nodata"] = nodata
    with rasterio.open(path, "w", **profile) as dst:
        dst.write(heights.astype(dtype), 1)
    return path


def file_heights(rng, rows=6, cols=9):
    # Distinct, unordered heights so any row/column mix-up shows.
    return 100.0 + rng.permutation(rows * cols).reshape(rows, cols) * 0.25


def test_geotiff_round_trip_utm_north_up(tmp_path):
    rng = np.random.default_rng(1)
    z = file_heights(rng)
    hf = load_dem(write_geotiff(tmp_path / "dem.tif", z))
    rows, cols = z.shape
    # Nodes are cell centres; rows of the height field go north (file rows go south).
    assert hf.dx_m == PIXEL and hf.dy_m == PIXEL
    assert hf.x0_m == WEST + PIXEL / 2
    assert hf.y0_m == NORTH - (rows - 0.5) * PIXEL
    np.testing.assert_array_equal(hf.heights_m, z[::-1])
    # The file's pixel (r, c) centre, in world coordinates, carries that pixel's height.
    for r, c in [(0, 0), (0, cols - 1), (rows - 1, 0), (2, 5)]:
        x = WEST + (c + 0.5) * PIXEL
        y = NORTH - (r + 0.5) * PIXEL
        assert hf.height_at(x, y) == pytest.approx(z[r, c], abs=1e-9)
    # Northernmost file row is the last height-field row.
    assert hf.extent_m[3] == NORTH - PIXEL / 2


def test_geotiff_south_up_gives_the_same_grid(tmp_path):
    rng = np.random.default_rng(2)
    z = file_heights(rng)
    rows = z.shape[0]
    south = NORTH - rows * PIXEL
    south_up = Affine(PIXEL, 0.0, WEST, 0.0, PIXEL, south)
    a = load_dem(write_geotiff(tmp_path / "n.tif", z))
    b = load_dem(write_geotiff(tmp_path / "s.tif", z[::-1], transform=south_up))
    assert (a.x0_m, a.y0_m, a.dx_m, a.dy_m) == (b.x0_m, b.y0_m, b.dx_m, b.dy_m)
    np.testing.assert_array_equal(a.heights_m, b.heights_m)


def test_geotiff_float32_and_non_square_pixels(tmp_path):
    z = np.arange(12, dtype=float).reshape(3, 4)
    hf = load_dem(write_geotiff(tmp_path / "d.tif", z,
                                transform=from_origin(WEST, NORTH, 2.0, 1.0), dtype="float32"))
    assert (hf.dx_m, hf.dy_m) == (2.0, 1.0)
    assert hf.heights_m.dtype == np.float64
    np.testing.assert_array_equal(hf.heights_m, z[::-1])


def test_geotiff_nodata_is_refused_with_the_file_name(tmp_path):
    z = np.full((4, 4), 50.0)
    z[1, 2] = -9999.0
    path = write_geotiff(tmp_path / "holes.tif", z, nodata=-9999.0)
    with pytest.raises(DesignerError, match=r"holes\.tif has 1 nodata/NaN cells") as info:
        load_dem(path)
    assert "\n" not in str(info.value)


def test_geotiff_nan_is_refused(tmp_path):
    z = np.full((4, 4), 50.0)
    z[0, 0] = np.nan
    with pytest.raises(DesignerError, match=r"nan\.tif has 1 nodata/NaN"):
        load_dem(write_geotiff(tmp_path / "nan.tif", z))


def test_geotiff_rotated_transform_is_refused(tmp_path):
    rotated = Affine(0.5, 0.1, WEST, 0.1, -0.5, NORTH)
    path = write_geotiff(tmp_path / "rot.tif", np.zeros((4, 4)), transform=rotated)
    with pytest.raises(DesignerError, match=r"rot\.tif has a rotated or sheared geotransform"):
        load_dem(path)


def test_geotiff_in_degrees_is_refused(tmp_path):
    path = write_geotiff(tmp_path / "geo.tif", np.zeros((4, 4)), crs="EPSG:4326",
                         transform=from_origin(11.0, 48.0, 1e-5, 1e-5))
    with pytest.raises(DesignerError, match=r"geo\.tif is in geographic coordinates"):
        load_dem(path)


def test_geotiff_in_feet_is_refused(tmp_path):
    path = write_geotiff(tmp_path / "feet.tif", np.zeros((4, 4)), crs="EPSG:2263")
    with pytest.raises(DesignerError, match=r"feet\.tif has horizontal units 'US survey foot'"):
        load_dem(path)


def test_geotiff_without_georeferencing_is_refused(tmp_path):
    path = tmp_path / "plain.tif"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", rasterio.errors.NotGeoreferencedWarning)
        with rasterio.open(path, "w", driver="GTiff", height=4, width=4, count=1,
                           dtype="float32") as dst:
            dst.write(np.zeros((4, 4), np.float32), 1)
    with pytest.raises(DesignerError, match=r"plain\.tif has no georeferencing"):
        load_dem(path)


def test_not_a_geotiff_is_refused(tmp_path):
    path = tmp_path / "fake.tif"
    path.write_bytes(b"this is not a tiff at all")
    with pytest.raises(DesignerError, match=r"fake\.tif is not a readable GeoTIFF") as info:
        load_dem(path)
    assert "\n" not in str(info.value)


def test_missing_and_unsupported_files(tmp_path):
    with pytest.raises(DesignerError, match=r"nope\.tif does not exist"):
        load_dem(tmp_path / "nope.tif")
    other = tmp_path / "dem.xyz"
    other.write_text("1 2 3\n")
    with pytest.raises(DesignerError, match=r"dem\.xyz: unsupported format '\.xyz'"):
        load_dem(other)


# --------------------------------------------------------------------------- ESRI ASCII
def write_asc(path, z, registration="corner", x=WEST, y=4999000.0, cell=0.5, nodata=None,
              extra=""):
    rows, cols = z.shape
    lines = [f"ncols {cols}", f"nrows {rows}",
             f"xll{registration} {x}", f"yll{registration} {y}", f"cellsize {cell}"]
    if nodata is not None:
        lines.append(f"NODATA_value {nodata}")
    lines += [" ".join(f"{v:.3f}" for v in row) for row in z]
    path.write_text("\n".join(lines) + "\n" + extra)
    return path


@pytest.mark.parametrize("registration", ["corner", "center"])
def test_esri_ascii_registration(tmp_path, registration):
    rng = np.random.default_rng(3)
    z = file_heights(rng, rows=5, cols=7)
    x_ll, y_ll, cell = 500000.0, 4999000.0, 0.5
    hf = load_dem(write_asc(tmp_path / "dem.asc", z, registration, x_ll, y_ll, cell))
    # Corner: the lower-left cell's centre is half a cell in from the given corner.
    half = cell / 2 if registration == "corner" else 0.0
    assert hf.x0_m == x_ll + half
    assert hf.y0_m == y_ll + half
    assert hf.dx_m == hf.dy_m == cell
    # The first data row in the file is the northernmost.
    np.testing.assert_array_equal(hf.heights_m, z[::-1])
    assert hf.height_at(x_ll + half, y_ll + half) == z[-1, 0]
    assert hf.height_at(x_ll + half + 6 * cell, y_ll + half + 4 * cell) == z[0, 6]


def test_esri_ascii_agrees_with_geotiff(tmp_path):
    rng = np.random.default_rng(4)
    z = file_heights(rng)
    rows = z.shape[0]
    a = load_dem(write_geotiff(tmp_path / "d.tif", z))
    b = load_dem(write_asc(tmp_path / "d.asc", z, "corner", WEST, NORTH - rows * PIXEL, PIXEL))
    assert (a.x0_m, a.y0_m, a.dx_m, a.dy_m) == (b.x0_m, b.y0_m, b.dx_m, b.dy_m)
    np.testing.assert_allclose(a.heights_m, b.heights_m, atol=1e-3)


def test_esri_ascii_header_is_case_insensitive_and_values_may_wrap(tmp_path):
    path = tmp_path / "wrap.asc"
    path.write_text("NCOLS 3\nNROWS 2\nXLLCENTER 10\nYLLCENTER 20\nCELLSIZE 2\n"
                    "1 2\n3 4 5\n6\n")
    hf = load_dem(path)
    np.testing.assert_array_equal(hf.heights_m, [[4, 5, 6], [1, 2, 3]])
    assert (hf.x0_m, hf.y0_m) == (10.0, 20.0)


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("ncols 2\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\nNODATA_value -9999\n"
         "1 2\n-9999 4\n", "has 1 nodata/NaN cells (first at X 0.50, Y 0.50)"),
        ("ncols 2\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\n1 2 3\n",
         "header says 2 x 2 = 4 values, the grid holds 3"),
        ("ncols 2\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\n1 2\nx 4\n",
         "not a number"),
        ("ncols 2\nxllcorner 0\nyllcorner 0\ncellsize 1\n1 2\n3 4\n", "has no 'nrows'"),
        ("ncols 2\nnrows 2\nxllcorner 0\nxllcenter 0\nyllcorner 0\ncellsize 1\n1 2\n3 4\n",
         "exactly one of xllcorner and xllcenter"),
        ("ncols 2\nnrows 2\nxllcorner 0\nyllcorner 0\n1 2\n3 4\n", "has no 'cellsize'"),
        ("ncols 2\nnrows 2\nxllcorner zero\nyllcorner 0\ncellsize 1\n1 2\n3 4\n",
         "'zero' is not a number"),
        ("GIF89a garbage", "has no 'ncols'"),
        ("ncols 2.5\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\n1 2\n3 4\n",
         "must be whole numbers >= 1, got 2.5 and 2"),
    ],
)
def test_esri_ascii_errors_name_the_file(tmp_path, text, message):
    path = tmp_path / "bad.asc"
    path.write_text(text)
    with pytest.raises(DesignerError) as info:
        load_dem(path)
    assert str(path) in str(info.value)
    assert message in str(info.value)
    assert "\n" not in str(info.value)


def test_binary_file_named_asc_is_refused(tmp_path):
    path = tmp_path / "binary.asc"
    path.write_bytes(bytes(range(256)))
    with pytest.raises(DesignerError, match=r"binary\.asc cannot be read as an ESRI ASCII"):
        load_dem(path)
