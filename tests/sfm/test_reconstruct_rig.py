"""COLMAP (pycolmap) on a small real render by a two-camera rig: each camera keeps its own
calibration, the rig's relative orientation stays fixed, and a rig camera whose images
register to nothing is a clear error."""

from __future__ import annotations

import dataclasses
import shutil

import numpy as np
import pycolmap
import pytest
from PIL import Image

from designer.errors import DesignerError
from designer.project import model as m
from designer.project.load import load_project
from designer.sfm.reconstruct import reconstruct
from designer.sfm.rigs import processing_rigs
from designer.sfm.settings import resolve_processing

pytestmark = [pytest.mark.blender, pytest.mark.slow]

GSD_M = 0.06  # 30 m flying height, 10 um pixels, 5 mm lens


@pytest.mark.parametrize("mode", ["known-poses", "free"])
def test_a_rig_of_two_different_cameras_reconstructs_each_with_its_own_calibration(
        two_camera_survey, tmp_path, mode):
    """Nadir 5 mm and 20°-oblique 6 mm cameras: every image registers, each image keeps
    its own camera, and in free mode each camera's focal length and principal point are
    recovered from its own pre-calibration error (seed + camera index)."""
    pre = m.PreCalibrationError(focal_px=15.0, principal_point_px=4.0, seed=3)
    # 1024 SIFT features an image (not 8192): the rig's calibration, not the tie-point
    # density, is under test, and the free mapper takes half the time it takes with 2048
    # (each camera's focal length and principal point still within 0.3 px of the truth,
    # the check points within 1.1 cm, about 3800 tie points)
    p = resolve_processing(two_camera_survey, calibration="focal-principal-point",
                           max_features=1024)
    p = dataclasses.replace(p, calibration=dataclasses.replace(p.calibration,
                                                               pre_calibration_error=pre))
    result = reconstruct(two_camera_survey, tmp_path / mode, mode=mode, processing=p,
                         log=lambda _: None)
    assert result.n_registered == result.n_images == 24
    assert result.n_points > 1000
    per_camera = result.summary["intrinsics_by_camera"]
    assert list(per_camera) == ["nadir", "oblique"]
    assert [c["camera_id"] for c in per_camera.values()] == [1, 2]
    assert all(c["images"] == c["registered"] == 12 for c in per_camera.values())
    assert per_camera["oblique"]["true"]["fx"] == 600.0 and per_camera["nadir"]["true"][
        "fx"] == 500.0
    model = pycolmap.Reconstruction(str(tmp_path / mode / "model"))
    assert len(model.cameras) == 2
    for image in model.images.values():  # each image its own camera's size
        assert model.cameras[image.camera_id].width == (560 if "_F" in image.name else 640)
    for name, c in per_camera.items():
        start_error = abs(c["start"]["fx"] - c["true"]["fx"])
        if mode == "known-poses":
            assert c["delta_f_px"] == 0.0 and c["delta_cx_px"] == 0.0, name
        else:
            assert start_error > 5.0, name  # each camera started wrong ...
            assert abs(c["delta_f_px"]) < 2.0, (name, c["delta_f_px"])  # ... and recovered
            assert np.hypot(c["delta_cx_px"], c["delta_cy_px"]) < 2.0, name
    assert result.summary["intrinsics"]["delta_f_px"] == per_camera["nadir"]["delta_f_px"]
    check = result.summary["check"]
    assert check["n"] == 2 and check["rmse_xyz_m"] < GSD_M, check
    if mode == "known-poses":
        assert result.summary["rigs"] is None
        return
    # free: the rig of the project (found through the survey's manifest) is a COLMAP rig
    # whose relative orientation stays the project's after every adjustment
    assert result.summary["rigs"] == {"duo": {"stations": 12, "relative_orientation": "fixed",
                                              "stations_registered": 12}}
    (rig,) = processing_rigs(load_project(two_camera_survey.parent / "project.xml",
                                          check_files=False))
    assert len(model.frames) == 12 and len(model.rigs) == 1
    (colmap_rig,) = model.rigs.values()
    (sensor,) = colmap_rig.non_ref_sensors
    np.testing.assert_allclose(colmap_rig.sensor_from_rig(sensor).rotation.matrix(),
                               rig.sensors[1].R_cam_from_rig, atol=1e-12)
    for frame in model.frames.values():  # one pose per station: both images' centres
        centres = [model.images[i.id].projection_center() for i in frame.image_ids]
        np.testing.assert_allclose(centres[0], centres[1], atol=1e-9)


@pytest.fixture(scope="module")
def noise_cache(tmp_path_factory):
    """A feature cache both variants below share: their images, features and matches are
    the same (the noise is seeded), so the second takes them from the first; the mapper,
    whose rig layout differs, runs in each."""
    return tmp_path_factory.mktemp("noise-cache")


@pytest.mark.parametrize("with_rig", [False, True])
def test_a_rig_camera_whose_images_register_to_nothing_is_a_clear_error(
        two_camera_survey, tmp_path, with_rig, noise_cache):
    """The oblique camera's images replaced by unrelated texture (a rig whose cameras see
    nothing in common): refused in one line naming the fix, not reported as a survey —
    also with the rig's relative orientation, where the station's pose would give the
    texture images a pose without a single tie point of their own."""
    rig = tmp_path / "rig"
    shutil.copytree(two_camera_survey / "ground-truth", rig / "ground-truth")
    (rig / "images").mkdir()
    rng = np.random.default_rng(0)
    for image in sorted((two_camera_survey / "images").iterdir()):
        if "_F" in image.name:
            noise = rng.integers(0, 256, size=(420, 560, 3), dtype=np.uint8)
            Image.fromarray(noise).save(rig / "images" / image.name)
        else:
            (rig / "images" / image.name).symlink_to(image)
    rigs = processing_rigs(load_project(two_camera_survey.parent / "project.xml",
                                        check_files=False)) if with_rig else []
    messages: list[str] = []
    with pytest.raises(DesignerError, match="see nothing in common") as error:
        # 1024 SIFT features an image (not 8192): noise images match nothing at any count
        reconstruct(rig, tmp_path / "r", mode="free", log=messages.append,
                    max_features=1024, feature_cache=noise_cache, rigs=rigs)
    assert "incremental SfM" in messages  # the mapper ran on this variant's rig layout
    message = str(error.value)
    assert "\n" not in message and "'oblique' (12 images)" in message
    assert "overlap" in message
