"""``designer reconstruct --dense cpu``: the dense products of a reconstruction, end to end."""

from __future__ import annotations

import json
import subprocess
import sys

import laspy
import numpy as np
import pytest
import rasterio

pytestmark = [pytest.mark.slow, pytest.mark.blender]


def test_dense_products_from_the_command_line(survey, survey_cache, tmp_path):
    out = tmp_path / "rec"
    # the features, matches and SfM model of the run's other free reconstructions of the
    # survey (conftest.py), when one came first: the dense stage is under test
    run = subprocess.run([sys.executable, "-m", "designer", "reconstruct", str(survey),
                          "-o", str(out), "--mode", "free", "--gcps", "bundle",
                          "--dense", "cpu", "--feature-cache", str(survey_cache)],
                         capture_output=True, text=True, timeout=900)
    assert run.returncode == 0, run.stderr[-2000:]
    assert "dense cloud" in run.stdout and "dome amplitude" in run.stdout
    summary = json.loads((out / "summary.json").read_text())
    dense = summary["dense"]
    assert dense["status"] == "ok" and "sgbm" in dense["matcher"]
    assert dense["points"] >= 20 * summary["points"]
    for name in ("dense.ply", "dense.laz", "dsm.tif", "dod.tif", "dod.png"):
        assert (out / name).stat().st_size > 0, name
    # the DoD of a well-controlled block is flat to a few GSD, its median near zero
    gsd = dense["rasters"]["gsd_m"]
    assert 0.02 < gsd < 0.2
    assert abs(dense["rasters"]["dod"]["median_m"]) < gsd
    assert dense["dome_amplitude_m"] is None or abs(dense["dome_amplitude_m"]) < 5 * gsd
    with rasterio.open(out / "dod.tif") as dod:
        assert dod.crs.to_epsg() == 32632
        assert dod.res[0] == pytest.approx(dense["dsm_cell_m"])
    las = laspy.read(out / "dense.laz")
    assert len(las.points) == dense["points"]
    assert np.median(np.asarray(las.x)) > 499000  # world (UTM) coordinates kept
    assert summary["stage_seconds"]["dense_s"] > 0
    # the demo's report shows the DoD, every GCP with its role and the calibration
    from designer.demo import _processing_text

    text = _processing_text(summary)
    assert "reconstruction/dod.png" in text and "Calibration, estimated − true" in text
    for row in summary["gcps"]:
        assert f"| {row['id']} | {row['role']} | {row['images']} |" in text


def test_dense_max_image_px_below_64_is_refused(survey, tmp_path):
    run = subprocess.run([sys.executable, "-m", "designer", "reconstruct", str(survey),
                          "-o", str(tmp_path / "rec"), "--dense", "cpu",
                          "--dense-max-image-px", "10"], capture_output=True, text=True)
    assert run.returncode == 2 and "--dense-max-image-px 10" in run.stderr
    assert not (tmp_path / "rec").exists()
