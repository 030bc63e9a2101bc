"""Error summaries, correlation tables and the variance test."""

from __future__ import annotations

import numpy as np
import pytest

from designer.experiments.stats import correlations, summarise, variance_test


def test_summary_has_the_t_interval_of_the_mean():
    rng = np.random.default_rng(0)
    s = summarise(rng.normal(0.01, 0.05, 400))
    assert s.n == 400
    assert s.mean_px == pytest.approx(0.01, abs=0.01)
    assert s.ci95_px == pytest.approx(1.966 * s.std_px / 20, rel=1e-3)
    assert np.isnan(summarise(np.array([])).mean_px)


def test_variance_test_finds_a_larger_spread_and_not_an_equal_one():
    rng = np.random.default_rng(1)
    b = rng.normal(0, 0.05, 4000)
    same = variance_test(rng.normal(0, 0.05, 1500), b)
    assert same.levene_p > 0.01 and same.f_p > 0.01
    assert same.ratio == pytest.approx(1.0, abs=0.06)
    wider = variance_test(rng.normal(0, 0.065, 1500), b)
    assert wider.levene_p < 1e-6 and wider.f_p < 1e-6
    assert wider.excess_std_px == pytest.approx(np.sqrt(0.065**2 - 0.05**2), abs=0.006)


def test_correlations_are_bonferroni_corrected_and_skip_constant_variables():
    rng = np.random.default_rng(2)
    x = rng.uniform(-300, 300, 2000)
    err = {"dx": 1e-4 * x + rng.normal(0, 0.05, 2000), "dy": rng.normal(0, 0.05, 2000)}
    table = correlations(err, {"x": x, "constant": np.ones(2000)}, "corner")
    assert {(c.error, c.variable) for c in table} == {("dx", "x"), ("dy", "x")}
    dx = next(c for c in table if c.error == "dx")
    assert dx.r > 0.25 and dx.p_bonferroni < 1e-10  # expected r = 0.33
    dy = next(c for c in table if c.error == "dy")
    assert dy.p_bonferroni == pytest.approx(min(1.0, 2 * dy.p))
