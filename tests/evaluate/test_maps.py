import numpy as np
import pytest

from designer.errors import DesignerError
from designer.evaluate import (
    distance_statistics,
    grid_errors,
    write_error_map_geotiff,
    write_error_map_npy,
    write_error_map_png,
    write_histogram_png,
)
from tests.synthetic import ORIGIN_WORLD

UTM = ORIGIN_WORLD[:2]


def test_nearest_neighbour_gridding_is_north_up_and_exact():
    # one point per 1 m cell centre; the value tells the cell
    cols, rows = 6, 4
    jj, ii = np.meshgrid(np.arange(cols), np.arange(rows))
    xy = UTM + np.column_stack([jj.ravel() + 0.5, ii.ravel() + 0.5])
    values = (10 * ii + jj).ravel().astype(float)
    grid = grid_errors(xy, values, cell_m=1.0)
    assert grid.values.shape == (rows, cols)
    assert grid.x_min == UTM[0] and grid.y_max == UTM[1] + rows
    # row 0 is the northern edge: the points with the largest northing
    assert np.array_equal(grid.values, (10 * ii + jj)[::-1].astype(float))
    assert grid.extent == (UTM[0], UTM[0] + cols, UTM[1], UTM[1] + rows)


def test_cells_far_from_every_point_stay_empty_and_nan_is_ignored():
    xy = UTM + np.array([[0.5, 0.5], [9.5, 0.5], [5.0, 5.0]])
    grid = grid_errors(xy, np.array([1.0, 2.0, np.nan]), cell_m=1.0, max_gap_m=1.0)
    assert grid.values[-1, 0] == 1.0 and grid.values[-1, -1] == 2.0
    assert np.isnan(grid.values).sum() == grid.values.size - 2
    with pytest.raises(DesignerError, match="no finite"):
        grid_errors(xy, np.full(3, np.nan))


def test_auto_cell_size_holds_a_few_points_per_cell():
    rng = np.random.default_rng(0)
    xy = UTM + rng.uniform(0, 100, (20000, 2))
    grid = grid_errors(xy, rng.normal(size=20000))
    assert grid.cell_m in (1.0, 2.0, 2.5)
    assert np.isfinite(grid.values).mean() > 0.95


def test_written_maps(tmp_path):
    import cv2
    import rasterio

    rng = np.random.default_rng(1)
    xy = UTM + rng.uniform(0, 50, (5000, 2))
    d = 0.02 * np.sin(xy[:, 0] - UTM[0]) + rng.normal(0, 0.005, 5000)
    grid = grid_errors(xy, d, cell_m=1.0)
    png = write_error_map_png(tmp_path / "map.png", grid)
    image = cv2.imread(str(png))
    assert image is not None and image.shape[0] > 500 and image.std() > 10
    hist = write_histogram_png(tmp_path / "hist.png", distance_statistics(d))
    assert cv2.imread(str(hist)) is not None
    tif = write_error_map_geotiff(tmp_path / "map.tif", grid, "EPSG:32632")
    with rasterio.open(tif) as src:
        assert src.crs.to_epsg() == 32632
        assert src.transform.c == grid.x_min and src.transform.f == grid.y_max
        assert src.transform.a == 1.0 and src.transform.e == -1.0
        assert np.allclose(src.read(1), grid.values.astype(np.float32), equal_nan=True)
    # a free-text CRS still gives a georeferenced grid
    write_error_map_geotiff(tmp_path / "free.tif", grid, "my local grid")
    npy = write_error_map_npy(tmp_path / "map.npy", grid)
    assert np.array_equal(np.load(npy), grid.values, equal_nan=True)


@pytest.mark.parametrize("seed", range(3))
def test_ring_search_equals_brute_force_with_ties_gaps_and_points_outside(seed):
    from designer.evaluate._grid import nearest_point_grid

    rng = np.random.default_rng(seed)
    rows, cols, cell, gap = 23, 31, 1.0, 2.6
    # clusters, empty stretches, quarter-cell lattice points (many equal distances,
    # duplicates) and points beyond the grid, which are bucketed into its edge cells
    x = np.concatenate([rng.uniform(0, 8, 150), rng.uniform(20, 31, 100),
                        rng.integers(0, 4 * cols, 120) / 4.0, rng.uniform(-5, 36, 30)])
    y = -np.concatenate([rng.uniform(0, 23, 150), rng.uniform(10, 15, 100),
                         rng.integers(0, 4 * rows, 120) / 4.0, rng.uniform(-5, 28, 30)])
    got = nearest_point_grid(x, y, rows, cols, cell, gap)
    cy, cx = np.meshgrid(-(np.arange(rows) + 0.5) * cell, (np.arange(cols) + 0.5) * cell,
                         indexing="ij")
    d2 = (x[None, :] - cx.ravel()[:, None]) ** 2 + (y[None, :] - cy.ravel()[:, None]) ** 2
    expected = np.argmin(d2, axis=1)  # the first (lowest index) of equal distances
    expected[d2.min(axis=1) >= gap * gap] = -1
    assert np.array_equal(got, expected)
    assert (got == -1).any() and (got >= 0).any()
