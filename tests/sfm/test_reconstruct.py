"""COLMAP (pycolmap) on a small real render: both modes, GCP residuals, bad inputs, the
global mapper (the two-camera rig: test_reconstruct_rig.py)."""

from __future__ import annotations

import json
import shutil
import subprocess
import sys

import numpy as np
import pytest
from plyfile import PlyData

from designer.errors import DesignerError
from designer.sfm.reconstruct import reconstruct
from designer.sfm.settings import resolve_processing

pytestmark = [pytest.mark.blender, pytest.mark.slow]

GSD_M = 0.06  # 30 m flying height, 10 um pixels, 5 mm lens


@pytest.mark.parametrize("mode", ["known-poses", "free"])
def test_reconstruction_registers_every_image_and_meets_the_gcps(survey, tmp_path, mode,
                                                                 survey_cache):
    # the run's shared cache (conftest.py): the global mapper below takes the free run's
    # features and matches and runs its own SfM (the mapper is part of the model's key)
    result = reconstruct(survey, tmp_path / mode, mode=mode, feature_cache=survey_cache)
    assert result.n_registered == result.n_images
    assert result.n_points > 1000
    rows = result.summary["gcps"]
    checks = [r for r in rows if r["role"] == "check"]
    assert len(checks) == 2
    for r in rows:
        horizontal = np.hypot(r["dx_m"], r["dy_m"])
        assert horizontal <= GSD_M and abs(r["dz_m"]) <= 1.5 * GSD_M, r
    cloud = PlyData.read(str(result.cloud_ply))["vertex"]
    assert cloud["x"].dtype == np.float64  # UTM-sized coordinates keep their precision
    assert 499970 < np.median(cloud["x"]) < 500030
    saved = json.loads((tmp_path / mode / "summary.json").read_text())
    assert saved["registered"] == result.n_registered


def test_a_folder_in_the_old_layout_still_reconstructs(survey, tmp_path):
    """Images at the folder's top level, as designer rendered them before images/."""
    old = tmp_path / "old"
    shutil.copytree(survey / "ground-truth", old / "ground-truth")
    names = sorted(p.name for p in (survey / "images").iterdir())
    for name in names:
        (old / name).symlink_to(survey / "images" / name)
    result = reconstruct(old, tmp_path / "r", mode="known-poses", log=lambda _: None)
    assert result.n_images == len(names) == result.n_registered
    assert result.n_points > 1000


def test_a_folder_without_ground_truth_is_a_clear_error(tmp_path):
    with pytest.raises(DesignerError, match="no ground truth"):
        reconstruct(tmp_path, tmp_path / "r")


def test_too_few_images_is_a_clear_error(survey, tmp_path):
    partial = tmp_path / "partial"
    shutil.copytree(survey / "ground-truth", partial / "ground-truth")
    (partial / "images").mkdir()
    for image in sorted((survey / "images").glob("IMG_*.png"))[:2]:
        shutil.copy(image, partial / "images" / image.name)
    out = subprocess.run([sys.executable, "-m", "designer", "reconstruct", str(partial)],
                         capture_output=True, text=True)
    assert out.returncode == 2
    assert "at least 3" in out.stderr and "Traceback" not in out.stderr


def test_images_without_overlap_are_a_clear_error(survey, tmp_path):
    # Three images of the flight's corners do not overlap: no reconstruction can start.
    apart = tmp_path / "apart"
    shutil.copytree(survey / "ground-truth", apart / "ground-truth")
    images = sorted((survey / "images").glob("IMG_*.png"))
    (apart / "images").mkdir()
    for image in (images[0], images[len(images) // 2 + 1], images[-1]):
        shutil.copy(image, apart / "images" / image.name)
    with pytest.raises(DesignerError, match="overlap"):
        reconstruct(apart, tmp_path / "r", mode="free")


def test_the_global_mapper_registers_every_image_and_meets_the_gcps(survey, tmp_path,
                                                                    survey_cache):
    """GLOMAP's global SfM (``--mapper global``, ``<sfm mapper="global"/>``) on the same
    survey: every image, GCPs within the GSD, and the summary says which mapper ran."""
    processing = resolve_processing(survey, mapper="global")
    assert processing.sfm.mapper == "global"
    result = reconstruct(survey, tmp_path / "global", mode="free", processing=processing,
                         feature_cache=survey_cache)
    assert result.summary["reused_from_cache"]["sfm"] is False  # the global mapper ran
    assert result.n_registered == result.n_images
    assert result.n_points > 1000
    for r in result.summary["gcps"]:
        assert np.hypot(r["dx_m"], r["dy_m"]) <= GSD_M and abs(r["dz_m"]) <= 1.5 * GSD_M, r
    assert result.summary["settings"]["sfm"]["mapper"] == "global"
