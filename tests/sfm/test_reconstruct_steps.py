"""The steps of designer.sfm.reconstruct one at a time, without a render: the survey
folder's errors, the image pairs, the mapper's refinements, the tie-point filters and the
cameras as processing calibrates them (the whole pipeline: test_reconstruct.py)."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

pytest.importorskip("pycolmap")

from designer.bench.synthetic_rolling import BlockSpec, rolling_block
from designer.errors import DesignerError
from designer.project import model as m
from designer.sfm.features import image_pairs
from designer.sfm.inputs import SurveyCamera, pre_error, read_inputs
from designer.sfm.mapping import largest_model, mapper_refines, tied_images
from designer.sfm.results import calibrated_sensors
from designer.sfm.tie_points import (
    drop_outliers,
    drop_short_tracks,
    mean_reprojection_error_px,
)


def test_inputs_name_a_wrong_mode_and_a_folder_without_ground_truth(tmp_path):
    with pytest.raises(DesignerError, match="--mode 'nope': use one of known-poses, free"):
        read_inputs(tmp_path, "nope", m.Processing(), None, print)
    with pytest.raises(DesignerError, match="no ground truth"):
        read_inputs(tmp_path, "free", m.Processing(), None, print)


def test_each_camera_draws_its_own_pre_calibration_error():
    assert pre_error(None, 1) is None  # no error: every camera starts from the truth
    pre = m.PreCalibrationError(seed=5)
    assert pre_error(pre, 0) is pre  # camera 1 as a one-camera survey draws it
    assert pre_error(pre, 2) == dataclasses.replace(pre, seed=7)


def test_exhaustive_pairs_pair_every_image_once():
    names = ["a", "b", "c", "d"]
    flight_C = {n: np.array([i * 10.0, 0.0, 40.0]) for i, n in enumerate(names)}
    pairs = image_pairs("exhaustive", names, None, flight_C, {}, [], np.zeros(3))
    assert sorted(tuple(sorted(p)) for p in pairs) == [
        ("a", "b"), ("a", "c"), ("a", "d"), ("b", "c"), ("b", "d"), ("c", "d")]


def test_the_mapper_refines_at_most_the_focal_length():
    assert mapper_refines("fixed") == (False, False, False)
    for mode in ("focal", "focal-principal-point", "radial", "full"):
        assert mapper_refines(mode) == (True, False, False)


def test_the_tie_point_filters_drop_short_tracks_and_outliers():
    rec, *_ = rolling_block(BlockSpec(strips=2, per_strip=4, points=300), seed=1)
    lengths = [pt.track.length() for pt in rec.points3D.values()]
    before = rec.num_points3D()
    removed = drop_short_tracks(rec, 3)
    assert removed == sum(1 for n in lengths if n < 3)
    assert rec.num_points3D() == before - removed
    assert all(pt.track.length() >= 3 for pt in rec.points3D.values())
    # per-point errors given (rolling-shutter compensation): they alone decide
    errors = {pid: [0.1] for pid in rec.points3D}
    bad = next(iter(rec.points3D))
    errors[bad] = [9.0, 7.0]
    assert drop_outliers(rec, 4.0, errors) == 1 and bad not in rec.points3D
    assert mean_reprojection_error_px(rec, errors) == pytest.approx(0.1)
    assert tied_images(rec) <= {img.name for img in rec.images.values()}


def test_without_a_rig_each_camera_is_calibrated_as_it_is():
    params = np.arange(12.0)
    cams = [SurveyCamera(1, "nadir", None, params, ("a", "b")),
            SurveyCamera(2, "oblique", None, params, ("c",))]
    sensors = calibrated_sensors(cams, [params, params + 1], None)
    assert [(c.label, c.names) for c, _ in sensors] == [("nadir", ("a", "b")),
                                                        ("oblique", ("c",))]
    assert np.array_equal(sensors[1][1], params + 1)


def test_the_mapper_keeps_its_largest_model_and_says_when_it_has_none(tmp_path):
    import pycolmap

    rec, *_ = rolling_block(BlockSpec(strips=2, per_strip=3, points=200), seed=1)
    assert rec.num_reg_images() == 6
    assert largest_model({0: pycolmap.Reconstruction(), 1: rec}, tmp_path, "x") is rec
    with pytest.raises(DesignerError) as err:
        largest_model({}, tmp_path, "COLMAP could not start a reconstruction")
    assert str(err.value) == (f"{tmp_path}: COLMAP could not start a reconstruction: the "
                              "images do not overlap enough or show too little texture")
