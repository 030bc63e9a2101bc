import numpy as np
import pytest

from designer.errors import DesignerError
from designer.scene.terrain import procedural_terrain


def test_heights_stay_inside_base_plus_minus_relief_and_use_most_of_it():
    hf = procedural_terrain(100.0, 100.0, 0.5, 10.0, seed=4)
    assert hf.heights_m.shape == (201, 201)
    assert -10.0 < hf.heights_m.min() and hf.heights_m.max() < 10.0
    # a terrain a few hill sizes across reaches most of the declared range
    wide = procedural_terrain(400.0, 400.0, 2.0, 10.0, seed=4)
    assert np.ptp(wide.heights_m) > 0.8 * 20.0
    assert hf.extent_m == (0.0, 100.0, 0.0, 100.0)


def test_base_height_origin_and_rectangular_grid():
    hf = procedural_terrain(60.0, 40.0, 2.0, 3.5, seed=1, x0_m=500000.0, y0_m=5000000.0,
                            base_height_m=250.0)
    assert hf.heights_m.shape == (21, 31)
    assert hf.extent_m == (500000.0, 500060.0, 5000000.0, 5000040.0)
    assert 250.0 - 3.5 < hf.heights_m.min() < hf.heights_m.max() < 250.0 + 3.5


@pytest.mark.parametrize(("E0", "N0"), [(0.0, 0.0), (512000.0, 5406000.0),
                                        (830000.0, 9999000.0)])
def test_growing_or_cropping_the_extent_keeps_every_height(E0, N0):
    """Heights are fixed to the world: two overlapping extents agree in the overlap."""
    small = procedural_terrain(100.0, 60.0, 0.5, 10.0, seed=7, x0_m=E0, y0_m=N0,
                               base_height_m=3.0, roughness=0.4)
    grown = procedural_terrain(300.0, 260.0, 0.5, 10.0, seed=7, x0_m=E0 - 120.0,
                               y0_m=N0 - 80.0, base_height_m=3.0, roughness=0.4)
    overlap = grown.heights_m[160:281, 240:441]
    assert overlap.shape == small.heights_m.shape
    np.testing.assert_allclose(overlap, small.heights_m, rtol=0, atol=1e-6)
    # a shifted, partly overlapping extent agrees too
    shifted = procedural_terrain(100.0, 60.0, 0.5, 10.0, seed=7, x0_m=E0 + 50.0,
                                 y0_m=N0 + 20.0, base_height_m=3.0, roughness=0.4)
    np.testing.assert_allclose(shifted.heights_m[:81, :101], small.heights_m[40:, 100:],
                               rtol=0, atol=1e-6)


def test_hill_size_sets_the_largest_hills():
    big = procedural_terrain(400.0, 400.0, 2.0, 10.0, seed=3, hill_size_m=400.0)
    small = procedural_terrain(400.0, 400.0, 2.0, 10.0, seed=3, hill_size_m=25.0)

    def correlation_at(z, lag):
        a, b = z[:, :-lag] - z.mean(), z[:, lag:] - z.mean()
        return float((a * b).mean() / z.var())

    # 50 m apart (25 nodes): still on the same big hill, but on other small ones
    assert correlation_at(big.heights_m, 25) > 0.6
    assert correlation_at(small.heights_m, 25) < 0.3


def test_same_seed_same_terrain_other_seed_other_terrain():
    a = procedural_terrain(100.0, 100.0, 1.0, 10.0, seed=7)
    b = procedural_terrain(100.0, 100.0, 1.0, 10.0, seed=7)
    c = procedural_terrain(100.0, 100.0, 1.0, 10.0, seed=8)
    np.testing.assert_array_equal(a.heights_m, b.heights_m)
    assert np.abs(a.heights_m - c.heights_m).mean() > 1.0


def test_terrain_is_smooth_hills_not_noise():
    hf = procedural_terrain(100.0, 100.0, 0.5, 10.0, seed=3, roughness=0.0)
    # Smooth: neighbouring nodes differ by a small fraction of the relief.
    step = np.abs(np.diff(hf.heights_m, axis=1)).max()
    assert step < 0.5
    # Hills, not a single tilted plane: the surface turns over inside the grid.
    assert np.ptp(hf.heights_m - _plane_fit(hf.heights_m)) > 5.0


def test_roughness_adds_small_scale_relief():
    smooth = procedural_terrain(100.0, 100.0, 0.5, 10.0, seed=3, roughness=0.0)
    rough = procedural_terrain(100.0, 100.0, 0.5, 10.0, seed=3, roughness=1.0)

    def curvature(z):
        return np.abs(z[1:-1, 2:] + z[1:-1, :-2] + z[2:, 1:-1] + z[:-2, 1:-1]
                      - 4 * z[1:-1, 1:-1]).mean()

    assert curvature(rough.heights_m) > 3 * curvature(smooth.heights_m)


def test_edges_do_not_wrap_around():
    hf = procedural_terrain(100.0, 100.0, 0.5, 10.0, seed=11, hill_size_m=50.0)
    z = hf.heights_m
    edge_jump = np.abs(z[:, 0] - z[:, -1]).mean()
    neighbour = np.abs(np.diff(z, axis=1)).mean()
    assert edge_jump > 10 * neighbour


def test_zero_relief_is_flat_at_base():
    hf = procedural_terrain(10.0, 10.0, 1.0, 0.0, seed=1, base_height_m=12.5)
    assert np.all(hf.heights_m == 12.5)


@pytest.mark.parametrize(
    ("args", "kwargs", "message"),
    [
        ((100.0, 100.0, 0.3, 10.0, 1), {}, "size_x_m=100.0 is not a whole number"),
        ((100.0, 100.0, 0.0, 10.0, 1), {}, "spacing_m must be > 0"),
        ((-5.0, 100.0, 1.0, 10.0, 1), {}, "size_x_m must be > 0"),
        ((100.0, 100.0, 1.0, -1.0, 1), {}, "relief_m must be >= 0"),
        ((100.0, 100.0, 1.0, 1.0, 1), {"roughness": 2.0}, "roughness must be in [0, 1]"),
    ],
)
def test_bad_arguments_are_designer_errors(args, kwargs, message):
    with pytest.raises(DesignerError) as info:
        procedural_terrain(*args, **kwargs)
    assert message in str(info.value)
    assert "\n" not in str(info.value)


def _plane_fit(z):
    ny, nx = z.shape
    jj, ii = np.meshgrid(np.arange(nx), np.arange(ny))
    A = np.column_stack([np.ones(z.size), jj.ravel(), ii.ravel()])
    coef, *_ = np.linalg.lstsq(A, z.ravel(), rcond=None)
    return (A @ coef).reshape(z.shape)
