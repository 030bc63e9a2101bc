"""Processing settings on real renders: GCPs in the adjustment with a marking error,
RTK camera positions, self-calibration on a convergent network, and bad input."""

from __future__ import annotations

import shutil
import subprocess
import sys

import numpy as np
import pytest
from PIL import Image

from designer.errors import DesignerError
from designer.project import model as m
from designer.sfm.reconstruct import reconstruct
from designer.sfm.settings import check_processing, control_ids, resolve_processing

pytestmark = [pytest.mark.blender, pytest.mark.slow]

GSD_M = 0.06


def settings(features: int = 4096, **kw) -> m.Processing:
    gcps = m.GcpProcessing(kw.pop("gcps", "bundle"), kw.pop("marking", 0.0), seed=4)
    prior = m.PositionPrior(kw.pop("prior", "none"), seed=2)
    calibration = m.Calibration(kw.pop("calibration", "fixed"), kw.pop("pre", None))
    return m.Processing(calibration, gcps, prior, m.Matching(max_features=features))


@pytest.fixture(scope="module")
def cache(tmp_path_factory):
    """The feature cache of this file's runs of ``survey``: runs that differ only after
    matching or after SfM (marking error, GCP observations, priors) take the features,
    matches and mapper's model of the first (test_feature_cache.py shows a shared model
    gives the result a run of its own gives)."""
    return tmp_path_factory.mktemp("cache")


@pytest.fixture(scope="module")
def bundle_runs(survey, tmp_path_factory, cache):
    """GCPs weighted in the adjustment, ideal marking and a 1 px marking error: the same
    SfM model, adjusted with each."""
    out = tmp_path_factory.mktemp("bundle")
    runs = {sigma: reconstruct(survey, out / f"s{sigma}", mode="free", log=lambda _: None,
                               processing=settings(marking=sigma), feature_cache=cache
                               ).summary
            for sigma in (0.0, 1.0)}
    assert runs[1.0]["reused_from_cache"]["sfm"]
    return runs


def test_marking_error_shows_in_control_residuals_and_check_errors(bundle_runs):
    ideal, marked = bundle_runs[0.0], bundle_runs[1.0]
    for s in (ideal, marked):
        assert s["registered"] == s["images"]
        assert s["control"]["n"] == 5 and s["check"]["n"] == 2
        assert s["adjustment"]["termination"] == "CONVERGENCE"
    # Control points sit where their marks put them: image residuals of the order of
    # the marking error (1 px) with it, a small fraction of a pixel without.
    assert ideal["control"]["image_rmse_px"] < 0.3
    assert 0.3 < marked["control"]["image_rmse_px"] < 1.5
    # Check points inherit the marking error: not better than the ideal case, and still
    # within a GSD or two horizontally (1 px ≈ 6 cm on the ground, seen in 4+ images).
    assert marked["check"]["rmse_xyz_m"] > ideal["check"]["rmse_xyz_m"]
    assert ideal["check"]["rmse_xyz_m"] < 0.5 * GSD_M
    assert marked["check"]["rmse_xy_m"] < 2 * GSD_M and marked["check"]["rmse_z_m"] < 3 * GSD_M


def test_rtk_positions_georeference_without_gcps(survey, tmp_path, cache):
    s = reconstruct(survey, tmp_path / "rtk", mode="free", log=lambda _: None,
                    processing=settings(gcps="none", prior="rtk"), feature_cache=cache
                    ).summary
    assert s["similarity"] is None  # no GCP took part
    assert s["check"]["rmse_xyz_m"] < 0.05 and s["control"]["rmse_xyz_m"] < 0.05
    assert s["cameras"]["rmse_z_m"] < 0.05


def test_self_calibration_recovers_focal_length_and_k1_on_a_convergent_network(
        convergent_survey, tmp_path):
    pre = m.PreCalibrationError(focal_px=20.0, k1=0.03, seed=1)
    s = reconstruct(convergent_survey, tmp_path / "cal", mode="free", log=lambda _: None,
                    processing=settings(2048, calibration="radial", pre=pre,
                                                        marking=0.3)).summary
    i = s["intrinsics"]
    start_df = i["start"]["fx"] - i["true"]["fx"]
    start_dk1 = i["start"]["k1"] - i["true"]["k1"]
    assert abs(start_df) > 5 and abs(start_dk1) > 0.01  # the start is really off
    assert abs(i["delta_f_px"]) < 2.0  # of f = 500 px
    assert abs(i["delta_k1"]) < 0.01  # of k1 = -0.08
    assert i["radial_difference_px"]["max_abs_px"] < 1.0
    assert s["check"]["rmse_xyz_m"] < GSD_M


def test_control_selection_even_spread_takes_the_corners_first():
    from designer.core.truth import GroundControlPoint

    xy = [(-14, -14), (0, -12), (14, -14), (-14, 14), (0, 12), (14, 14), (0, 0)]
    gcps = [GroundControlPoint(f"G{k}", "check", [x, y, 0.0], [x, y, 0.0], [0, 0, 0])
            for k, (x, y) in enumerate(xy)]
    chosen = control_ids(gcps, m.ControlSelection(count=4, spread="even"))
    assert chosen == {"G0", "G2", "G3", "G5"}
    random = control_ids(gcps, m.ControlSelection(count=3, spread="random", seed=5))
    assert len(random) == 3 and random == control_ids(
        gcps, m.ControlSelection(count=3, spread="random", seed=5))
    with pytest.raises(DesignerError, match="unknown GCP id 'G9'"):
        control_ids(gcps, m.ControlSelection(ids=("G1", "G9")))


def _designer(*args) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "designer", *map(str, args)],
                          capture_output=True, text=True)


@pytest.mark.parametrize("args, message", [
    (["--marking-sigma-px", "-1"], "marking error of 0"),
    (["--control", "G0,G9"], "unknown GCP id 'G9'"),
])
def test_bad_settings_are_one_line_errors(survey, tmp_path, args, message):
    out = _designer("reconstruct", survey, "-o", tmp_path / "r", "--mode", "free", *args)
    assert out.returncode == 2
    assert message in out.stderr and "Traceback" not in out.stderr
    assert len(out.stderr.strip().splitlines()) == 1
    assert not (tmp_path / "r" / "summary.json").exists()


def test_a_prior_sigma_of_zero_is_refused():
    with pytest.raises(DesignerError, match="greater than 0"):
        check_processing(m.Processing(position_prior=m.PositionPrior("rtk", 0.0, 0.03)))


def test_all_black_images_are_a_clear_error(survey, tmp_path):
    black = tmp_path / "black"
    shutil.copytree(survey / "ground-truth", black / "ground-truth")
    (black / "images").mkdir()
    for image in sorted((survey / "images").glob("IMG_*.png")):
        with Image.open(image) as im:
            size = im.size
        Image.new("RGB", size).save(black / "images" / image.name)
    with pytest.raises(DesignerError, match="overlap enough or show too little texture"):
        reconstruct(black, tmp_path / "r", mode="free", log=lambda _: None,
                    processing=settings(gcps="similarity"))


def test_gcps_seen_by_fewer_than_two_images_are_reported(survey, tmp_path, cache):
    folder = tmp_path / "few"
    shutil.copytree(survey, folder, ignore=shutil.ignore_patterns("reconstruction*"))
    path = folder / "ground-truth" / "gcp_observations.csv"
    lines = path.read_text().splitlines()
    kept, seen = [], set()
    for line in lines:
        gcp = line.split(",")[0]
        if gcp in ("G1", "G6") and not line.startswith("#"):  # one mark each, no more
            if gcp in seen:
                continue
            seen.add(gcp)
        kept.append(line)
    path.write_text("\n".join(kept) + "\n")
    s = reconstruct(folder, tmp_path / "r", mode="free", log=lambda _: None,
                    processing=settings(gcps="bundle"), feature_cache=cache).summary
    assert {g["id"]: g["images"] for g in s["gcps_not_triangulated"]} == {"G1": 1, "G6": 1}
    assert {r["id"] for r in s["gcps"]} == {"G0", "G2", "G3", "G4", "G5"}
    assert s["control"]["n"] == 4 and s["check"]["n"] == 1


def test_settings_come_from_the_project_and_options_override_them(survey):
    p = resolve_processing(survey, calibration="full", marking_sigma_px=0.5)
    assert p.calibration.mode == "full" and p.gcps.marking_sigma_px == 0.5
    assert p.matching.pairs == "footprint" and p.position_prior.mode == "none"
    assert np.allclose(m.PositionPrior("gnss").sigmas_m, (2.5, 5.0))
