"""The three validations with real Cycles renders (small images, few of them)."""

from __future__ import annotations

import json
import subprocess
import sys
from dataclasses import replace

import numpy as np
import pytest

from designer.experiments.projection import IO_SETS, ProjectionConfig, run_projection
from designer.experiments.projection_report import write_projection_report
from designer.experiments.psf import PSFConfig, validate_psf
from designer.experiments.settings import RenderSettings, quality
from designer.experiments.texture import TextureConfig, validate_texture

pytestmark = pytest.mark.blender

SMALL = ProjectionConfig(n_images=6, size_px=(480, 320), io_sets=IO_SETS[:3], n_baseline=300,
                         settings=quality("metrology"), workers=1)


def criteria(summary: dict) -> dict[str, bool]:
    return {c.name: c.passed for c in summary["criteria"]}


def test_psf_validation_passes_and_wide_filters_leak(tmp_path):
    summary = validate_psf(PSFConfig(workers=1), tmp_path)
    assert summary["passed"], criteria(summary)
    renders = {r["name"].split(" (")[0].split(":")[0]: r for r in summary["renders"]}
    assert renders["no antialiasing"]["centre"] == 1.0
    assert renders["no antialiasing"]["elsewhere"] == 0.0
    assert renders["Blender's default filter"]["neighbours"] > 0.01
    assert (tmp_path / "report.md").is_file() and (tmp_path / "psf-pixels.png").is_file()
    assert json.loads((tmp_path / "summary.json").read_text())["passed"] is True


def test_texture_validation_passes_and_linear_smooths(tmp_path):
    summary = validate_texture(TextureConfig(settings=RenderSettings(samples=16), workers=1),
                               tmp_path)
    assert summary["passed"], criteria(summary)
    n = summary["numbers"]
    assert n["point_impure"] == 0 and n["aa_impure_off_edges"] == 0
    assert n["aa_edge_offset_max_px"] < 0.05
    assert n["linear_impure_off_edges"] > 0.5 * n["pixels"]


@pytest.mark.slow
def test_projection_passes_and_a_wrong_principal_point_fails(tmp_path):
    good = run_projection(SMALL, tmp_path / "good")
    assert good.passed, [c for c in good.criteria if not c.passed]
    assert good.corners.found.mean() > 0.95
    assert abs(good.overall["dx"].mean_px) < 0.02 and good.overall["dx"].std_px < 0.1
    summary = write_projection_report(good, tmp_path / "good-report")
    assert summary["passed"]
    for name in summary["figures"].values():
        assert (tmp_path / "good-report" / name).is_file()
    # Rendering with the principal point 0.3 px off (a camera-mapping bug) must fail:
    # the corners still match, but their mean error is 0.3 px. One image per camera (a
    # few dozen corners each) shows it; the detector baseline only enters the variance
    # test, not the means judged here
    bad = run_projection(replace(SMALL, render_pp_error_px=(0.3, 0.0), n_images=3,
                                 n_baseline=50), tmp_path / "bad")
    assert not bad.passed
    failed = {c.name for c in bad.criteria if not c.passed}
    assert "mean error 0 (all)" in failed and "mean error 0 (each camera)" in failed
    assert bad.overall["dx"].mean_px == pytest.approx(0.3, abs=0.03)


@pytest.mark.slow
def test_cli_exits_1_when_a_criterion_fails(tmp_path):
    cmd = [sys.executable, "-m", "designer", "validate", "projection", "-o", str(tmp_path),
           "--images", "5", "--size", "480x320", "--baseline", "100", "--workers", "1",
           "--inject-pp-error", "0,0.5"]
    out = subprocess.run(cmd, capture_output=True, text=True, timeout=900)
    assert out.returncode == 1, out.stderr
    assert "FAILED" in out.stdout and "[FAIL] mean error 0" in out.stdout
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert summary["passed"] is False
    assert np.isclose(summary["overall"]["dy"]["mean_px"], 0.5, atol=0.05)
    assert (tmp_path / "report.md").read_text().count("FAIL") >= 2
