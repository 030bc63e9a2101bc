"""Lateral chromatic aberration (``<chromatic-aberration>``), end to end: red and blue
imaged at their radial scale about the principal point, green untouched, nothing at all
without the element; the file, the checks, the study factors and the CLI's factor list
(the GUI group: tests/gui/test_effects_declared.py)."""

from __future__ import annotations

import re

import cv2
import numpy as np
import pytest

from designer.cli.main import main
from designer.core.distortion import BrownConrady
from designer.effects import (
    CameraContext,
    EffectChain,
    FrameContext,
    effects_from_model,
    process_file,
)
from designer.effects.chromatic import LateralChromaticAberration
from designer.effects.optics import GaussianBlur, RadialVignetting
from designer.effects.sensor import SensorModel
from designer.project import model as m
from designer.project import parse_project, project_to_bytes
from designer.project.validate import semantic_issues
from designer.study.factors import FACTORS
from tests.synthetic import assert_located_error, pixel_camera, small_survey

#: 240 × 180 px, principal point 7.3 px right of and 4.6 px above the image centre
CAMERA = pixel_camera(240, 180, 300.0, None, pp_px=(7.3, -4.6))
PP = (CAMERA.cx_px, CAMERA.cy_px)


def _dot(u: float, v: float, sigma_px: float = 1.5) -> np.ndarray:
    """A linear-light (180, 240, 3) image of a Gaussian dot centred at (u, v) in every
    channel (pixel centres at i + 0.5)."""
    uu, vv = np.meshgrid(np.arange(240) + 0.5, np.arange(180) + 0.5)
    dot = np.exp(-((uu - u) ** 2 + (vv - v) ** 2) / (2 * sigma_px**2)).astype(np.float32)
    return np.repeat(dot[:, :, None], 3, axis=2)


def _centroid(plane: np.ndarray) -> tuple[float, float]:
    w = np.asarray(plane, float)
    uu, vv = np.meshgrid(np.arange(w.shape[1]) + 0.5, np.arange(w.shape[0]) + 0.5)
    return float((w * uu).sum() / w.sum()), float((w * vv).sum() / w.sum())


def _effect(red_ppm: float, blue_ppm: float) -> LateralChromaticAberration:
    return LateralChromaticAberration.from_model(
        m.ChromaticAberration(red_ppm, blue_ppm), CameraContext(CAMERA))


@pytest.mark.parametrize("order", ["BGR", "RGB"])
def test_red_and_blue_land_at_their_scaled_radius_and_green_stays(order):
    red, blue = 4000.0, -3000.0
    fx = _effect(red, blue)
    u, v = 197.3, 31.8  # ~ (100, −55) px from the principal point
    image = _dot(u, v)
    out = fx.apply(image, 0, FrameContext(channel_order=order))
    channel = {c: order.index(c) for c in "RGB"}
    np.testing.assert_array_equal(out[:, :, channel["G"]], image[:, :, channel["G"]])
    for c, ppm in (("R", red), ("B", blue)):
        scale = 1 + ppm * 1e-6
        expected = (PP[0] + (u - PP[0]) * scale, PP[1] + (v - PP[1]) * scale)
        found = _centroid(out[:, :, channel[c]])
        assert np.hypot(found[0] - u, found[1] - v) > 0.25  # it did move (≥ 0.26 px)
        assert np.hypot(found[0] - expected[0], found[1] - expected[1]) <= 0.02, (c, found)
    np.testing.assert_array_equal(image, _dot(u, v))  # the input is not modified


def test_a_dot_at_the_principal_point_does_not_move():
    out = _effect(4000.0, -3000.0).apply(_dot(*PP), 0, FrameContext())
    for c in range(3):
        found = _centroid(out[:, :, c])
        assert np.hypot(found[0] - PP[0], found[1] - PP[1]) <= 1e-3


def test_green_codes_are_unchanged_through_the_chain():
    rng = np.random.default_rng(3)
    image = rng.integers(0, 256, (180, 240, 3), dtype=np.uint8)
    out = EffectChain([_effect(800.0, -600.0)]).apply(image, 0)
    np.testing.assert_array_equal(out[:, :, 1], image[:, :, 1])  # BGR: green in the middle
    assert (out[:, :, 0] != image[:, :, 0]).any() and (out[:, :, 2] != image[:, :, 2]).any()


def test_without_the_element_or_at_zero_scale_images_stay_byte_identical(tmp_path):
    for effects in (None, m.Effects(), m.Effects(chromatic_aberration=m.ChromaticAberration())):
        assert effects_from_model(effects, CAMERA).is_empty
    rng = np.random.default_rng(5)
    src = tmp_path / "render.png"
    cv2.imwrite(str(src), rng.integers(0, 256, (180, 240, 3), dtype=np.uint8))
    zero = effects_from_model(m.Effects(chromatic_aberration=m.ChromaticAberration(0.0, 0.0)),
                              CAMERA)
    process_file(src, tmp_path / "out.png", zero)
    assert (tmp_path / "out.png").read_bytes() == src.read_bytes()
    # beside another effect: the same bytes as without the element
    blur = m.Effects(blur=m.Blur(0.8))
    both = m.Effects(blur=m.Blur(0.8), chromatic_aberration=m.ChromaticAberration())
    for name, effects in (("blur", blur), ("both", both)):
        process_file(src, tmp_path / f"{name}.png", effects_from_model(effects, CAMERA))
    assert (tmp_path / "blur.png").read_bytes() == (tmp_path / "both.png").read_bytes()


def test_it_runs_after_the_lens_distortion_and_before_vignetting_blur_and_sensor():
    chain = EffectChain([SensorModel(seed=1), GaussianBlur(0.5), _effect(100.0, 0.0),
                         RadialVignetting.from_corner_falloff(CAMERA, 0.2)])
    assert chain.kinds == ("chromatic_aberration", "vignetting", "blur", "sensor")
    assert _effect(0.0, 0.0).is_identity and not _effect(0.0, 1.0).is_identity
    distorted = pixel_camera(64, 48, 60.0, BrownConrady(k1=-0.1), pp_px=(2.5, 1.5))
    built = effects_from_model(m.Effects(chromatic_aberration=m.ChromaticAberration(50.0),
                                         vignetting=m.Vignetting(0.2)), distorted)
    assert built.kinds == ("distortion", "chromatic_aberration", "vignetting")
    ca = built.effects[-2]
    assert (ca.cx_px, ca.cy_px) == (distorted.cx_px, distorted.cy_px)  # the output camera's


def test_an_image_of_another_size_is_refused():
    with pytest.raises(ValueError, match="240 × 180"):
        _effect(100.0, 0.0).apply(np.zeros((10, 12, 3), np.float32), 0, FrameContext())


def _project(**values) -> m.Project:
    return small_survey(n_photos=2, samples=4, size_px=(160, 120), effects=m.Effects(
        chromatic_aberration=m.ChromaticAberration(**values)))


def test_the_element_round_trips_through_the_file():
    p = _project(red_scale_ppm=250.0, blue_scale_ppm=-180.5)
    data = project_to_bytes(p)
    assert b'<chromatic-aberration red-scale-ppm="250.0" blue-scale-ppm="-180.5"' in data
    assert parse_project(data)[0] == p


def test_an_out_of_range_scale_is_a_located_one_line_error(tmp_path):
    bad = [i.message for i in semantic_issues(_project(red_scale_ppm=6000.0))]
    assert "red-scale-ppm = 6000.0 must be from -5000 to 5000 ppm" in bad
    assert_located_error(
        _project(red_scale_ppm=100.0), tmp_path,
        lambda text: re.sub(r'(<chromatic-aberration[^>]* blue-scale-ppm=)"[^"]*"',
                            r'\1"-7000"', text),
        "<chromatic-aberration", ("blue-scale-ppm", "chromatic-aberration"))


def test_the_study_factors_switch_it_on_and_vary_one_channel_each():
    plain = small_survey(n_photos=2, samples=4, size_px=(160, 120))
    red, blue = FACTORS["chromatic-aberration-red-ppm"], FACTORS["chromatic-aberration-blue-ppm"]
    assert red.get(plain) is None and red.stage == "render"
    varied = red.set(plain, red.parse("300"))
    assert varied.effects.chromatic_aberration == m.ChromaticAberration(red_scale_ppm=300.0)
    varied = blue.set(varied, blue.parse("-200"))
    assert varied.effects.chromatic_aberration == m.ChromaticAberration(300.0, -200.0)


def test_designer_study_factors_lists_them(capsys):
    assert main(["study", "factors"]) == 0
    listed = capsys.readouterr().out
    assert re.search(r"^chromatic-aberration-red-ppm +render ", listed, re.M)
    assert re.search(r"^chromatic-aberration-blue-ppm +render ", listed, re.M)
