import numpy as np
import pytest

from designer.errors import DesignerError
from designer.evaluate import distance_statistics
from designer.evaluate.statistics import format_statistics


def test_gaussian_sample_statistics_match_theory():
    rng = np.random.default_rng(1)
    d = rng.normal(0.01, 0.05, 200_000)
    s = distance_statistics(d)
    assert s["n"] == 200_000 and s["n_excluded"] == 0
    assert abs(s["mean"] - 0.01) < 5e-4 and abs(s["std"] - 0.05) < 5e-4
    assert abs(s["rmse"] - np.hypot(0.01, 0.05)) < 5e-4
    assert abs(s["median"] - 0.01) < 1e-3
    assert abs(s["nmad"] - 0.05) < 1e-3  # NMAD estimates sigma for normal errors
    assert s["asprs_vertical_95"] == pytest.approx(1.96 * s["rmse"])


def test_exact_values_on_a_small_sample():
    d = np.array([-0.03, -0.01, 0.0, 0.02, 0.1, np.nan])
    s = distance_statistics(d, tolerances=(0.01, 0.05))
    finite = d[:-1]
    assert s["n"] == 5 and s["n_excluded"] == 1
    assert s["mean"] == pytest.approx(finite.mean())
    assert s["std"] == pytest.approx(finite.std(ddof=1))
    assert s["rmse"] == pytest.approx(np.sqrt(np.mean(finite ** 2)))
    assert s["median"] == 0.0
    assert s["nmad"] == pytest.approx(1.4826 * 0.02)
    assert s["abs_q95"] == pytest.approx(np.quantile(np.abs(finite), 0.95))
    assert s["abs_q68_3"] == pytest.approx(np.quantile(np.abs(finite), 0.683))
    assert [t["share"] for t in s["within_tolerance"]] == [pytest.approx(0.4),
                                                          pytest.approx(0.8)]
    h = s["histogram"]
    assert sum(h["counts"]) + h["below"] + h["above"] == 5
    assert len(h["edges"]) == len(h["counts"]) + 1
    labels = [label for label, _ in format_statistics(s)]
    assert "NMAD" in labels and "beyond max distance (left out)" in labels


def test_outliers_do_not_squash_the_histogram():
    rng = np.random.default_rng(2)
    d = np.concatenate([rng.normal(0, 0.02, 10000), [50.0, -80.0]])
    h = distance_statistics(d)["histogram"]
    assert h["edges"][-1] < 1.0 and h["above"] >= 1 and h["below"] >= 1


def test_no_finite_value_is_an_error():
    with pytest.raises(DesignerError, match="no finite distances"):
        distance_statistics([np.nan, np.nan])
