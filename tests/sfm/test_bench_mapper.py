"""designer bench mapper: the incremental mapper at each global-adjustment growth ratio on
a rendered survey, and the similarity it measures the cameras with."""

from __future__ import annotations

import shutil
import subprocess
import sys

import numpy as np
import pytest

from designer.bench import mapper


def _rotation(angle_rad: float) -> np.ndarray:
    c, s = np.cos(angle_rad), np.sin(angle_rad)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def test_a_similar_network_has_no_centre_error():
    rng = np.random.default_rng(1)
    true = rng.uniform(-50, 50, (30, 3)) + [500_000.0, 5_000_000.0, 100.0]
    est = 0.37 * (true - true.mean(0)) @ _rotation(0.8).T + [3.0, -2.0, 7.0]
    xy, z = mapper.centre_rms(est, true)
    assert xy < 1e-6 and z < 1e-6


def test_a_height_error_shows_in_z_only():
    rng = np.random.default_rng(2)
    true = rng.uniform(-50, 50, (400, 3))
    dz = rng.choice([-0.1, 0.1], 400)  # ±10 cm, mean zero, uncorrelated with position
    est = (true + np.c_[np.zeros((400, 2)), dz]) @ _rotation(-1.1).T * 2.0
    xy, z = mapper.centre_rms(est, true)
    assert z == pytest.approx(0.1, abs=0.01) and xy < 0.01


def test_the_bench_maps_a_survey_at_each_ratio(survey, tmp_path):
    copy = tmp_path / "block" / "survey"
    shutil.copytree(survey, copy)
    rows = mapper.run(survey=copy)
    assert [r["ratio"] for r in rows] == list(mapper.RATIOS)
    for r in rows:
        assert r["registered"] == r["images"] >= 10
        assert r["cpu_s"] > 0 and r["wall_s"] > 0
        assert r["centre_rms_xy_m"] < 0.06 and r["centre_rms_z_m"] < 0.06  # under a GSD
    assert (tmp_path / "block" / "feature-cache").is_dir()  # kept for the next run
    table = mapper.format_table(rows)
    assert "1.10" in table and "1.40" in table


def test_without_a_survey_it_says_what_to_give():
    done = subprocess.run([sys.executable, "-m", "designer", "bench", "mapper"],
                          capture_output=True, text=True, timeout=120)
    assert done.returncode != 0
    assert "--survey" in done.stderr and "Traceback" not in done.stderr
