"""Render settings, worker job files, presets and the accuracy benchmark's selection rule."""

from __future__ import annotations

import numpy as np
import pytest

from designer.bench.accuracy import eligible, suggested_presets
from designer.experiments import texture
from designer.experiments.jobs import render_views, scaled_interior, write_job
from designer.experiments.settings import PLAIN_64, QUALITY_PRESETS, RenderSettings, quality
from designer.render.blender_camera import blender_camera
from designer.render.job_spec import AdaptiveSampling, RenderJob, RenderSpec


def test_job_render_section_and_labels():
    plain = RenderSettings(samples=16)
    assert plain.job_render(3) == RenderSpec(samples=16, seed=3, pixel_filter="BOX",
                                             filter_width_px=1.0, format="png", bit_depth=8)
    adaptive = RenderSettings(samples=64, adaptive_threshold=0.01, adaptive_min_samples=4)
    assert adaptive.job_render().adaptive_sampling == AdaptiveSampling(0.01, 4)
    assert adaptive.label() == "64 spp, adaptive 0.01/min 4, box 1 px"
    assert RenderSettings(samples=4, oversample=2, interpolation="Linear").label() == \
        "4 spp, box 1 px, oversample 2x, linear"
    with pytest.raises(ValueError):
        RenderSettings(pixel_filter="MITCHELL")
    with pytest.raises(ValueError, match="unknown quality"):
        quality("best")


def test_presets_keep_the_pixel_as_psf_and_textures_sharp():
    for name, s in QUALITY_PRESETS.items():
        assert s.pixel_filter == "BOX" and s.filter_width_px == 1.0, name
        assert s.interpolation == "Closest" and s.oversample == 1, name
    assert QUALITY_PRESETS["metrology"].samples >= PLAIN_64.samples


def test_oversampled_job_renders_the_same_camera_larger(tmp_path):
    interior = texture.camera()
    settings = RenderSettings(samples=4, oversample=2, interpolation="Linear")
    path = write_job(tmp_path, [texture.plane()], interior, [texture.pose()], settings,
                     tmp_path / "out")
    job = RenderJob.read(path)
    cam, plain = job.camera, blender_camera(interior)
    assert cam.resolution_x_px == 2 * plain.resolution_x_px
    assert cam.shift_x == pytest.approx(plain.shift_x)
    assert cam.lens_mm == plain.lens_mm and cam.sensor_width_mm == plain.sensor_width_mm
    assert job.render.bit_depth == 16  # averaged in linear light, so no 8-bit rounding
    assert job.objects[0].materials[0].interpolation == "Linear"
    assert (tmp_path / "checker.png").is_file() and (tmp_path / "plane.npz").is_file()
    assert np.allclose(job.frames[0].matrix_world_local[0][3], texture.pose()[0][0])
    assert scaled_interior(interior, 2).fx_px == pytest.approx(2 * interior.fx_px)


def _row(samples, std, cpu, bias=0.001, **settings):
    s = RenderSettings(samples=samples, **settings).to_dict()
    return {"settings": s, "texels_per_square": 1, "distortion": False, "std_px": std,
            "cpu_s_per_mp": cpu, "bias_px": bias, "bias_low_px": bias, "group": "x"}


def test_presets_are_the_cheapest_eligible_rows_as_accurate_as_plain_4_16_64():
    rows = [_row(64, 0.056, 19.0), _row(4, 0.128, 1.4), _row(16, 0.069, 5.0),
            _row(64, 0.0565, 6.4, adaptive_threshold=0.01, adaptive_min_samples=4),
            _row(32, 0.060, 5.7, adaptive_threshold=0.01, adaptive_min_samples=4),
            _row(16, 0.02, 5.1, interpolation="Linear"),  # blurs: never a preset
            _row(16, 0.05, 4.0, pixel_filter="GAUSSIAN", filter_width_px=1.5),
            _row(8, 0.05, 2.0, bias=0.03)]  # biased: never a preset
    for r in rows:
        r["eligible"] = eligible(r)
    chosen = suggested_presets(rows)
    assert chosen["draft"] is rows[1] and chosen["survey"] is rows[2]
    assert chosen["metrology"] is rows[3]


@pytest.mark.blender
def test_oversampled_render_is_area_sampled(tmp_path):
    views = render_views(tmp_path, [texture.plane()], texture.camera(), [texture.pose()],
                         RenderSettings(samples=4, oversample=2), workers=1)
    area = texture.expected_area()
    rendered = views.linear(0)
    pure = (area == 0) | (area == 1)
    assert np.array_equal(rendered[pure], area[pure])
    assert np.abs(rendered[~pure] - area[~pure]).mean() < 0.05
    assert views.cpu_seconds[0] > 0 and views.seconds[0] > 0
    assert not list((tmp_path / "images").glob("*_big.png"))
