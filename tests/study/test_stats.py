"""The factor-effect table (statsmodels) on rows with known effects."""

import numpy as np
import pytest

from designer.study.stats import factor_effects


def _rows(design: str, seed: int = 0) -> list[dict]:
    """Rows of a study: altitude acts with slope 0.002 per metre, marking-sigma not at all;
    noise σ 0.001."""
    rng = np.random.default_rng(seed)
    altitudes, sigmas = (40, 60, 80, 100), ("0.5", "1.0", "2.0")
    if design == "full":
        combos = [(a, s) for a in altitudes for s in sigmas]
    else:  # one at a time around (60, 1.0)
        combos = [(a, "1.0") for a in altitudes] + [(60, s) for s in sigmas if s != "1.0"]
    rows = []
    for a, s in combos:
        for _ in range(3):
            rows.append({"status": "ok", "factor:altitude-m": str(a), "factor:marking-px": s,
                         "check_rmse_z_m": 0.01 + 0.002 * a + rng.normal(0, 0.001)})
    rows.append({"status": "failed: SfM", "factor:altitude-m": "40",
                 "factor:marking-px": "1.0", "check_rmse_z_m": 99.0})
    return rows


@pytest.mark.parametrize("design", ["full", "one-at-a-time"])
def test_the_factor_that_acts_is_found_and_its_slope_measured(design):
    table = factor_effects(["altitude-m", "marking-px"], _rows(design), ["check_rmse_z_m"])
    by = {r["factor"]: r for r in table}
    alt, mark = by["altitude-m"], by["marking-px"]
    assert alt["levels"] == 4 and alt["df"] == 3
    assert alt["p"] < 1e-6 and alt["eta2"] > 0.9
    assert mark["p"] > 0.01 and mark["eta2"] < 0.5
    assert alt["slope_low"] < 0.002 < alt["slope_high"]
    assert abs(alt["slope"] - 0.002) < 2e-4
    # the failed run (99 m) is left out
    assert alt["runs"] == len(_rows(design)) - 1


def test_without_replicates_no_test_is_claimed():
    rows = [{"status": "ok", "factor:a": str(v), "check_rmse_z_m": 0.1 * v} for v in (1, 2)]
    (row,) = factor_effects(["a"], rows, ["check_rmse_z_m"])
    assert row["F"] is None and row["p"] is None and row["slope"] is None
    assert row["levels"] == 2
