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


# --------------------------------------------------------------------------- CRS, extent
UTM33 = "EPSG:32633 (WGS 84 / UTM zone 33N)"


def test_geographic_dem_is_reprojected_to_the_project_utm_zone(sample_site):
    from designer.scene import sample_site as site

    utm = load_dem(sample_site["dem"], UTM33)
    geo = load_dem(sample_site["dem_wgs84"], UTM33, extent_m=(533010, 5213010, 533110, 5213080))
    assert geo.dx_m == geo.dy_m and 0.3 < geo.dx_m < 0.7
    # Compare on the smooth ground away from the building blocks and the road cut's
    # shoulders (steps that bilinear interpolation rounds off on either grid).
    rng = np.random.default_rng(5)
    E = rng.uniform(533015, 533105, 4000)
    N = rng.uniform(5213015, 5213075, 4000)
    smooth = np.abs(np.abs(site.road_offset_m(E, N)) - 5.25) > 2.5
    for e0, n0, e1, n1, _ in site.BLOCKS:
        smooth &= ~((E > e0 - 1.5) & (E < e1 + 1.5) & (N > n0 - 1.5) & (N < n1 + 1.5))
    E, N = E[smooth], N[smooth]
    truth = site.height_m(E, N)
    err_geo = geo.height_at(E, N) - truth
    err_utm = utm.height_at(E, N) - truth
    print(f"reprojected geographic DEM: RMS {np.sqrt(np.mean(err_geo ** 2)) * 1000:.2f} mm, "
          f"max {np.abs(err_geo).max() * 1000:.2f} mm; UTM DEM max "
          f"{np.abs(err_utm).max() * 1000:.2f} mm ({len(E)} points)")
    assert np.abs(err_utm).max() < 0.02
    assert np.abs(err_geo).max() < 0.03
    assert np.abs(geo.height_at(E, N) - utm.height_at(E, N)).max() < 0.03
    # Read in its own degrees, the grid would be nowhere near: the reprojection happened.
    assert geo.extent_m[0] > 500000


def test_dem_in_another_utm_zone_is_reprojected(tmp_path):
    from pyproj import Transformer

    # A tilted plane z = 300 + 0.01 E' + 0.02 N' in zone-33 coordinates, stored in zone 32.
    to32 = Transformer.from_crs(32633, 32632, always_xy=True)
    X32, Y32 = to32.transform(533000.0, 5213000.0)
    west, north = float(np.floor(X32)) - 40, float(np.floor(Y32)) + 40
    cols, rows = 160, 160
    E32 = west + (np.arange(cols) + 0.5) * 0.5
    N32 = north - (np.arange(rows) + 0.5) * 0.5
    EE, NN = np.meshgrid(E32, N32)
    to33 = Transformer.from_crs(32632, 32633, always_xy=True)
    E33, N33 = to33.transform(EE, NN)
    z = 300 + 0.01 * (E33 - 533000) + 0.02 * (N33 - 5213000)
    path = write_geotiff(tmp_path / "z32.tif", z, transform=from_origin(west, north, 0.5, 0.5),
                         crs="EPSG:32632")
    hf = load_dem(path, UTM33, extent_m=(532990, 5212990, 533010, 5213010))
    E, N = np.meshgrid(np.linspace(532991, 533009, 7), np.linspace(5212991, 5213009, 7))
    expected = 300 + 0.01 * (E - 533000) + 0.02 * (N - 5213000)
    np.testing.assert_allclose(hf.height_at(E, N), expected, atol=1e-4)


def test_geographic_dem_in_a_local_project_is_refused(sample_site):
    with pytest.raises(DesignerError, match=r"is in geographic coordinates .*give the project "
                       r"a projected <crs>"):
        load_dem(sample_site["dem_wgs84"], "local engineering frame (m)")


def test_dem_without_crs_in_a_utm_project_is_refused(tmp_path):
    path = write_geotiff(tmp_path / "bare.tif", np.zeros((4, 4)), crs=None)
    with pytest.raises(DesignerError, match=r"bare\.tif has no coordinate system, the "
                       r"project is in EPSG:32633.*gdal_edit\.py -a_srs") as info:
        load_dem(path, UTM33)
    assert "\n" not in str(info.value)
    # In a local frame the bare grid is taken as metres, as before.
    assert load_dem(path, "local engineering frame (m)").dx_m == PIXEL


def test_dem_is_cropped_to_the_extent_and_holes_outside_it_do_not_matter(tmp_path):
    z = np.arange(20 * 30, dtype=float).reshape(20, 30)
    z[0, :] = np.nan  # the northernmost file row: outside the extent below
    z[5, 29] = -9999.0
    path = write_geotiff(tmp_path / "holes.tif", z, nodata=-9999.0)
    extent = (WEST + 2.2, NORTH - 8.0, WEST + 9.1, NORTH - 3.1)
    hf = load_dem(path, UTM33, extent_m=extent)
    x0, x1, y0, y1 = hf.extent_m
    assert x0 <= extent[0] < x0 + PIXEL and x1 - PIXEL < extent[2] <= x1
    assert y0 <= extent[1] < y0 + PIXEL and y1 - PIXEL < extent[3] <= y1
    # Node (row i, column j) still carries the file's cell-centre value.
    assert hf.height_at(x0, y1) == z[round((NORTH - y1) / PIXEL - 0.5), round((x0 - WEST)
                                                                                / PIXEL - 0.5)]


def test_dem_hole_inside_the_extent_is_refused_with_its_place(tmp_path):
    z = np.full((20, 30), 50.0)
    z[10, 8] = -9999.0  # cell centre X = WEST + 4.25, Y = NORTH - 5.25
    path = write_geotiff(tmp_path / "void.tif", z, nodata=-9999.0)
    with pytest.raises(DesignerError, match=r"void\.tif has 1 nodata/NaN cells inside the "
                       r"terrain extent \(first at X 500004\.25, Y 4999994\.75\); fill the "
                       r"voids .*or shrink <extent>"):
        load_dem(path, UTM33, extent_m=(WEST + 1, NORTH - 9, WEST + 9, NORTH - 1))


def test_extent_beyond_the_dem_is_refused(tmp_path):
    path = write_geotiff(tmp_path / "small.tif", np.zeros((10, 10)))
    with pytest.raises(DesignerError, match=r"small\.tif covers X 500000\.000\.\.500005\.000, "
                       r"Y 4999995\.000\.\.5000000\.000, not the whole terrain extent"):
        load_dem(path, UTM33, extent_m=(WEST, NORTH - 5, WEST + 6, NORTH))
