"""The camera of a flown survey: presets named by EXIF model, the base camera otherwise."""

import dataclasses

import pytest

from designer.errors import DesignerError
from designer.flight.camera_pick import named_preset, pick_camera
from designer.flight.photos import CameraInfo
from designer.project import model as m
from designer.project.camera_presets import PRESETS, preset

BASE = m.Camera("cam", 5.0, 6.4, 4.8, 640, 480)


@pytest.mark.parametrize("p", PRESETS, ids=lambda p: p.key)
def test_every_preset_is_named_by_its_exif_model(p):
    for model in p.exif_models:
        info = CameraInfo("X", model.upper(), p.focal_length_mm, p.image_height_px,
                          p.image_width_px)  # portrait images too
        assert named_preset(info) is p
        assert pick_camera([info], BASE) == p.camera()


def test_a_model_with_another_lens_is_not_the_preset():
    info = CameraInfo("SONY", "ILCE-6000", 20.0, 6000, 4000)
    assert named_preset(info) is None
    with pytest.raises(DesignerError, match=r"unknown camera.*ILCE-6000, 20 mm"):
        pick_camera([info], BASE)


def test_the_base_camera_keeps_its_calibration_when_it_is_the_named_preset():
    calibrated = dataclasses.replace(preset("p4p").camera("mine"),
                                     distortion=m.BrownConradyDistortion(k1=-0.02))
    info = CameraInfo("DJI", "FC6310S", 8.8, 5472, 3648)
    assert pick_camera([info], calibrated) is calibrated


def test_base_camera_by_focal_length_and_size_and_without_metadata():
    assert pick_camera([CameraInfo("Acme", "One", 5.02, 640, 480)], BASE) is BASE
    assert pick_camera([None, None], BASE) is BASE
    with pytest.raises(DesignerError, match="several cameras"):
        pick_camera([CameraInfo("A", "B", 5.0, 640, 480), CameraInfo("A", "C", 5.0, 640, 480)],
                    BASE)
