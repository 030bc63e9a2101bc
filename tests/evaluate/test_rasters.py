"""DSM, true-surface raster, DoD and dome fit on synthetic data; GeoTIFF read back."""

from __future__ import annotations

import numpy as np
import pytest
import rasterio

from designer.errors import DesignerError
from designer.evaluate.raster_products import write_geotiff, write_raster_products
from designer.evaluate.rasters import (
    Raster,
    RasterGrid,
    dem_of_difference,
    dsm_from_points,
    fit_dome,
    surface_raster,
)

E0, N0 = 512_000.0, 5_406_000.0  # UTM-sized coordinates


def grid_mesh(f, x0, y0, size_m, n):
    """A triangulated height field z = f(x, y) with n x n nodes (counter-clockwise)."""
    x = np.linspace(x0, x0 + size_m, n)
    y = np.linspace(y0, y0 + size_m, n)
    X, Y = np.meshgrid(x, y)
    V = np.column_stack([X.ravel(), Y.ravel(), f(X.ravel(), Y.ravel())])
    idx = np.arange(n * n).reshape(n, n)
    a, b = idx[:-1, :-1].ravel(), idx[:-1, 1:].ravel()
    c, d = idx[1:, 1:].ravel(), idx[1:, :-1].ravel()
    F = np.vstack([np.column_stack([a, b, c]), np.column_stack([a, c, d])])
    return V, F


def tilted(x, y):
    return 250.0 + 0.05 * (x - E0) - 0.02 * (y - N0)


def test_dsm_of_a_tilted_plane_is_the_plane_at_utm_coordinates():
    rng = np.random.default_rng(1)
    xy = rng.uniform([E0, N0], [E0 + 40, N0 + 30], size=(200_000, 2))
    points = np.column_stack([xy, tilted(xy[:, 0], xy[:, 1])])
    dsm = dsm_from_points(points, 0.5, (E0, N0, E0 + 40, N0 + 30))
    assert dsm.grid.shape == (60, 80)
    X, Y = np.meshgrid(*dsm.grid.centres_world())
    # the median of a plane's points in a cell is the plane at the cell's median point:
    # within the plane's change across half a cell
    err = dsm.values - tilted(X, Y)
    assert np.isfinite(dsm.values).all()
    assert np.abs(err).max() < 0.5 * 0.5 * (0.05 + 0.02)
    assert abs(np.median(err)) < 1e-3


def test_median_dsm_ignores_blunders_that_max_does_not():
    rng = np.random.default_rng(2)
    xy = rng.uniform([E0, N0], [E0 + 10, N0 + 10], size=(40_000, 2))
    z = np.full(len(xy), 100.0) + rng.normal(0, 0.01, len(xy))
    z[::50] += 5.0  # 2 % blunders above the surface
    points = np.column_stack([xy, z])
    median = dsm_from_points(points, 1.0, (E0, N0, E0 + 10, N0 + 10))
    highest = dsm_from_points(points, 1.0, (E0, N0, E0 + 10, N0 + 10), statistic="max")
    assert np.abs(median.values - 100.0).max() < 0.01
    assert (highest.values > 104.0).all()


def test_surface_raster_equals_the_mesh_at_cell_centres():
    V, F = grid_mesh(lambda x, y: 250.0 + 3.0 * np.sin((x - E0) / 7.0) * np.cos((y - N0) / 5.0),
                     E0, N0, 30.0, 61)
    grid = RasterGrid.from_bounds((E0 - 2, N0 - 2, E0 + 32, N0 + 32), 0.25)
    surface = surface_raster(V, F, grid)
    X, Y = np.meshgrid(*grid.centres_world())
    inside = (X > E0) & (X < E0 + 30) & (Y > N0) & (Y < N0 + 30)
    assert np.isnan(surface.values[~inside]).all()
    assert np.isfinite(surface.values[inside]).all()
    # linear interpolation of the 0.5 m triangles: independent check by the mesh plane
    # of each centre's triangle is in test_dod_of_the_mesh_itself_is_zero; here against
    # the smooth function, within the triangles' interpolation error
    truth = 250.0 + 3.0 * np.sin((X - E0) / 7.0) * np.cos((Y - N0) / 5.0)
    assert np.abs(surface.values[inside] - truth[inside]).max() < 0.01


def test_surface_raster_takes_the_highest_of_stacked_triangles():
    ground = grid_mesh(lambda x, y: np.full_like(x, 10.0), E0, N0, 10.0, 3)
    roof = grid_mesh(lambda x, y: np.full_like(x, 14.0), E0 + 2, N0 + 2, 4.0, 2)
    V = np.vstack([ground[0], roof[0]])
    F = np.vstack([ground[1], roof[1] + len(ground[0])])
    grid = RasterGrid.from_bounds((E0, N0, E0 + 10, N0 + 10), 1.0)
    s = surface_raster(V, F, grid).values
    assert s[5, 3] == pytest.approx(14.0) and s[0, 0] == pytest.approx(10.0)
    assert np.count_nonzero(np.isclose(s, 14.0)) == 16


def test_dod_of_the_mesh_itself_is_zero():
    V, F = grid_mesh(tilted, E0, N0, 20.0, 11)
    grid = RasterGrid.from_bounds((E0, N0, E0 + 20, N0 + 20), 0.5)
    surface = surface_raster(V, F, grid)
    X, Y = np.meshgrid(*grid.centres_world())
    dsm = Raster(tilted(X, Y), grid)
    dod = dem_of_difference(dsm, surface)
    assert np.nanmax(np.abs(dod.values)) < 1e-9


@pytest.mark.parametrize("amplitude_m", [0.12, -0.05])
def test_a_paraboloid_dod_recovers_its_amplitude(amplitude_m):
    rng = np.random.default_rng(3)
    grid = RasterGrid.from_bounds((E0, N0, E0 + 80, N0 + 80), 0.5)
    X, Y = np.meshgrid(*grid.centres_world())
    R = 35.0
    rho2 = (X - (E0 + 42)) ** 2 + (Y - (N0 + 38)) ** 2
    values = amplitude_m * (1 - rho2 / R**2) + 0.01 + 0.002 * (X - E0) \
        + rng.normal(0, 0.01, X.shape)  # offset, tilt and noise are no dome
    values[rho2 > R**2] = np.nan  # a round valid area: its edge is where the paraboloid is 0
    fit = fit_dome(Raster(values, grid), gsd_m=0.02)
    assert fit.kind == ("dome" if amplitude_m > 0 else "bowl")
    assert fit.amplitude_m == pytest.approx(amplitude_m, abs=0.004)
    assert fit.amplitude_gsd == pytest.approx(fit.amplitude_m / 0.02)
    assert np.hypot(fit.peak_world[0] - (E0 + 42), fit.peak_world[1] - (N0 + 38)) < 1.5


def test_a_plane_dod_has_no_dome():
    grid = RasterGrid.from_bounds((E0, N0, E0 + 50, N0 + 50), 1.0)
    X, Y = np.meshgrid(*grid.centres_world())
    fit = fit_dome(Raster(0.03 + 0.001 * (X - E0) - 0.002 * (Y - N0), grid))
    assert abs(fit.amplitude_m) < 1e-9


def test_geotiff_georeferencing_reads_back(tmp_path):
    grid = RasterGrid.from_bounds((E0 + 0.3, N0 + 0.3, E0 + 20.1, N0 + 10.2), 0.25)
    values = np.arange(grid.rows * grid.cols, dtype=float).reshape(grid.shape) + 250.0
    values[0, 0] = np.nan
    path = write_geotiff(tmp_path / "a.tif", Raster(values, grid),
                         "EPSG:32632 (WGS 84 / UTM zone 32N)")
    with rasterio.open(path) as src:
        assert src.crs.to_epsg() == 32632
        assert src.transform.a == 0.25 and src.transform.e == -0.25
        assert (src.transform.c, src.transform.f) == (grid.x_min, grid.y_max)
        assert grid.x_min <= E0 + 0.3 and grid.y_max >= N0 + 10.2
        band = src.read(1)
    assert np.isnan(band[0, 0]) and np.array_equal(band[1:], values[1:])
    with rasterio.open(write_geotiff(tmp_path / "b.tif", Raster(values, grid), 25832)) as src:
        assert src.crs.to_epsg() == 25832


def test_raster_products_on_a_domed_cloud(tmp_path):
    rng = np.random.default_rng(4)
    V, F = grid_mesh(tilted, E0, N0, 60.0, 31)
    xy = rng.uniform([E0 + 5, N0 + 5], [E0 + 55, N0 + 55], size=(300_000, 2))
    rho2 = (xy[:, 0] - (E0 + 30)) ** 2 + (xy[:, 1] - (N0 + 30)) ** 2
    z = tilted(xy[:, 0], xy[:, 1]) + 0.08 * (1 - rho2 / 25.0**2) + rng.normal(0, 0.01, len(xy))
    summary = write_raster_products(tmp_path / "r", np.column_stack([xy, z]), (V, F),
                                    "EPSG:32632", 0.5, gsd_m=0.02)
    for name in ("dsm.tif", "surface.tif", "dod.tif", "dod.png", "dod_profile.png"):
        assert (tmp_path / "r" / name).stat().st_size > 1000
    # Peak-to-edge over the square valid area: the mean of rho² along the border of a
    # square of half-side L about the peak is L² + L²/3.
    half = 25.0
    expected = 0.08 * (half**2 + half**2 / 3) / 25.0**2
    assert summary["dome"]["kind"] == "dome"
    assert summary["dome"]["amplitude_m"] == pytest.approx(expected, rel=0.1)
    assert summary["dome"]["amplitude_gsd"] == pytest.approx(
        summary["dome"]["amplitude_m"] / 0.02)
    assert summary["dod"]["coverage"] > 0.99
    assert summary["dod"]["nmad_m"] > 0.01  # the dome widens the DoD distribution
    with rasterio.open(tmp_path / "r" / "dod.tif") as src:
        assert src.crs.to_epsg() == 32632 and src.dtypes[0] == "float32"


def test_all_nan_dsm_and_empty_clouds_are_clear_errors(tmp_path):
    grid = RasterGrid.from_bounds((E0, N0, E0 + 10, N0 + 10), 1.0)
    empty = Raster(np.full(grid.shape, np.nan), grid)
    with pytest.raises(DesignerError, match="all NaN"):
        dem_of_difference(empty, Raster(np.zeros(grid.shape), grid))
    with pytest.raises(DesignerError, match="valid cells"):
        fit_dome(empty)
    with pytest.raises(DesignerError, match="empty"):
        dsm_from_points(np.zeros((0, 3)), 1.0)
    V, F = grid_mesh(tilted, E0, N0, 10.0, 3)
    with pytest.raises(DesignerError, match="same coordinates"):
        write_raster_products(tmp_path / "x", np.array([[0.0, 0.0, 1.0], [1.0, 1.0, 1.0]]),
                              (V, F), "EPSG:32632", 0.5)
    with pytest.raises(DesignerError, match="EPSG code"):
        write_raster_products(tmp_path / "y", V, (V, F), "no such crs", 0.5)
    assert not (tmp_path / "x").exists() and not (tmp_path / "y").exists()


def test_the_dome_is_fitted_over_the_survey_area_not_the_cloud_beyond_it(tmp_path):
    """A flat cloud over the flown area whose edge, beyond the area, rises 5 cm — the
    few, narrow-baseline views at a block's edge, which reach farther for tilted images
    (docs/processing.md, "Doming: measured"): the dome over the survey area is nil,
    over the whole DoD it is the edge; a survey area too small to fit falls back."""
    rng = np.random.default_rng(5)
    V, F = grid_mesh(tilted, E0, N0, 100.0, 11)
    xy = rng.uniform([E0 + 2, N0 + 2], [E0 + 98, N0 + 98], size=(200_000, 2))
    beyond = np.maximum(np.abs(xy - [E0 + 50, N0 + 50]).max(axis=1) - 30.0, 0.0)
    z = tilted(xy[:, 0], xy[:, 1]) + 0.05 * (beyond / 18.0) ** 2 + rng.normal(0, 0.003, len(xy))
    area = np.array([[E0 + 20, N0 + 20], [E0 + 80, N0 + 20], [E0 + 80, N0 + 80],
                     [E0 + 20, N0 + 80]])
    summary = write_raster_products(tmp_path / "r", np.column_stack([xy, z]), (V, F),
                                    "EPSG:32632", 1.0, gsd_m=0.06, survey_area_world=area)
    assert summary["dome"]["area"] == "the survey area"
    assert abs(summary["dome"]["amplitude_m"]) < 0.003, summary["dome"]
    assert summary["dome_whole_dod"]["amplitude_m"] < -0.015, summary["dome_whole_dod"]
    assert summary["dome"]["cells"] == pytest.approx(60 * 60, rel=0.05)
    tiny = area[:1] + np.array([[0, 0], [3, 0], [3, 3], [0, 3]])
    fallback = write_raster_products(tmp_path / "s", np.column_stack([xy, z]), (V, F),
                                     "EPSG:32632", 1.0, gsd_m=0.06, survey_area_world=tiny)
    assert fallback["dome"]["area"] == "the whole DoD"
    assert fallback["dome"]["amplitude_m"] == fallback["dome_whole_dod"]["amplitude_m"]
