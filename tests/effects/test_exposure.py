"""Per-image auto exposure and white balance (``<exposure-variation>``), end to end: the
effect's arithmetic, the file, the checks, the study factors, the GUI field and a real
render whose two images differ in brightness and colour as their draws say (the GUI
field: tests/gui/test_effects_declared.py)."""

from __future__ import annotations

import dataclasses

import cv2
import numpy as np
import pytest

from designer.effects.base import FrameContext
from designer.effects.chain import EffectChain
from designer.effects.exposure import ExposureWhiteBalance, white_balance_gains
from designer.project import model as m
from designer.project import parse_project, project_to_bytes
from designer.project.validate import semantic_issues
from designer.study.factors import FACTORS
from tests.synthetic import small_survey, write_project_file


def test_the_gain_and_channel_ratios_are_the_frames_draw():
    fx = ExposureWhiteBalance(0.3, 400.0, 5500.0, seed=4)
    grey = np.full((8, 10, 3), 0.25, np.float32)
    for frame in (0, 1, 7):
        ev, temperature = fx.frame_draw(frame)
        out = fx.apply(grey, frame, FrameContext())
        wb = white_balance_gains(temperature, 5500.0)
        expected = 0.25 * 2 ** ev * np.array([wb["B"], wb["G"], wb["R"]])  # BGR
        np.testing.assert_allclose(out[0, 0], expected, rtol=1e-6)
    assert fx.frame_draw(1) != fx.frame_draw(2)  # a new draw per image
    assert fx.frame_draw(1) == ExposureWhiteBalance(0.3, 400.0, 5500.0, seed=4).frame_draw(1)


def test_white_balance_for_a_warmer_guess_makes_the_image_bluer():
    wb = white_balance_gains(7000.0, 5500.0)  # balanced as if the light were bluer
    assert wb["G"] == pytest.approx(1.0)
    assert wb["R"] > 1.0 > wb["B"]  # … so red is lifted, blue cut: the image turns warm
    assert white_balance_gains(5500.0, 5500.0) == pytest.approx({"R": 1, "G": 1, "B": 1})


def test_it_runs_after_the_optics_and_before_the_sensor():
    from designer.effects.optics import GaussianBlur
    from designer.effects.sensor import SensorModel

    chain = EffectChain([SensorModel(seed=1), ExposureWhiteBalance(0.1, 100.0),
                         GaussianBlur(0.5)])
    assert chain.kinds == ("blur", "exposure", "sensor")
    assert ExposureWhiteBalance(0.0, 0.0).is_identity


def _project(**changes) -> m.Project:
    return small_survey(n_photos=2, samples=4, size_px=(160, 120), effects=m.Effects(
        exposure_variation=m.ExposureVariation(**changes)))


def test_the_element_round_trips_and_its_ranges_are_checked():
    p = _project(exposure_sigma_ev=0.4, white_balance_sigma_k=300.0, seed=9)
    assert parse_project(project_to_bytes(p))[0] == p
    assert b'<exposure-variation exposure-sigma-ev="0.4"' in project_to_bytes(p)
    bad = [i.message for i in semantic_issues(_project(exposure_sigma_ev=3.0))]
    assert "exposure-sigma-ev = 3.0 must be from 0 to 2 EV" in bad


def test_the_study_factors_switch_it_on_and_vary_it():
    plain = small_survey(n_photos=2, samples=4, size_px=(160, 120))
    assert FACTORS["exposure-sigma-ev"].get(plain) is None
    varied = FACTORS["exposure-sigma-ev"].set(plain, FACTORS["exposure-sigma-ev"].parse("0.5"))
    assert varied.effects.exposure_variation == m.ExposureVariation(exposure_sigma_ev=0.5)
    varied = FACTORS["white-balance-sigma-k"].set(varied, 250.0)
    assert FACTORS["white-balance-sigma-k"].get(varied) == 250.0
    assert FACTORS["exposure-sigma-ev"].stage == "render"


@pytest.mark.blender
@pytest.mark.slow
def test_a_render_gives_each_image_its_own_exposure_and_balance(tmp_path):
    from designer.render.pipeline import render_project

    plain = small_survey(n_photos=2, samples=4, size_px=(160, 120))
    varied = dataclasses.replace(plain, effects=m.Effects(exposure_variation=m.ExposureVariation(
        exposure_sigma_ev=0.5, white_balance_sigma_k=800.0, seed=2)))
    images = {}
    for name, project in (("plain", plain), ("varied", varied)):
        summary = render_project(write_project_file(project, tmp_path / name),
                                 tmp_path / name / "out", workers=1)
        images[name] = [cv2.imread(str(p), cv2.IMREAD_UNCHANGED).astype(float)
                        for p in sorted(summary.images_dir.glob("IMG_*.png"))]
    fx = ExposureWhiteBalance(0.5, 800.0, 5500.0, seed=2)
    for frame, (a, b) in enumerate(zip(images["plain"], images["varied"], strict=True)):
        ev, temperature = fx.frame_draw(frame)
        wb = white_balance_gains(temperature, 5500.0)
        # mid-tone pixels away from clipping: the linear-light ratio of each channel
        lin = [((x / 255.0 + 0.055) / 1.055) ** 2.4 for x in (a, b)]
        mask = (a > 40).all(axis=2) & (a < 150).all(axis=2)
        ratios = [np.median(lin[1][..., c][mask] / lin[0][..., c][mask]) for c in range(3)]
        expected = [2 ** ev * wb[ch] for ch in "BGR"]
        np.testing.assert_allclose(ratios, expected, rtol=0.03)
