import numpy as np
import pytest

from designer.core.bounds import column_bounds


def test_column_bounds_equal_the_axis_reduction_at_utm_size():
    rng = np.random.default_rng(3)
    a = rng.normal(0.0, 50.0, (10_001, 3)) + [500_000.0, 5_000_000.0, 300.0]
    lo, hi = column_bounds(a)
    np.testing.assert_array_equal(lo, a.min(axis=0))
    np.testing.assert_array_equal(hi, a.max(axis=0))
    assert lo.dtype == np.float64 and lo.shape == (3,)


def test_column_bounds_of_a_strided_view_and_nan():
    a = np.arange(24, dtype=float).reshape(6, 4)[:, 1:3]  # not contiguous
    lo, hi = column_bounds(a)
    np.testing.assert_array_equal(lo, [1.0, 2.0])
    np.testing.assert_array_equal(hi, [21.0, 22.0])
    a = a.copy()
    a[2, 0] = np.nan
    lo, hi = column_bounds(a)
    assert np.isnan(lo[0]) and np.isnan(hi[0]) and hi[1] == 22.0


def test_column_bounds_refuses_what_the_reduction_refuses():
    with pytest.raises(ValueError):
        column_bounds(np.zeros((0, 3)))
    with pytest.raises(ValueError):
        column_bounds(np.zeros(5))
