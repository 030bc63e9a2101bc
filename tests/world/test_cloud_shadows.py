"""Cloud shadows without rendering: the field, the file round trip, located errors for
bad values, and the study factors."""

from __future__ import annotations

import re
from dataclasses import replace

import numpy as np
import pytest

from designer.project import load_project
from designer.project import model as m
from designer.scene.cloud_shadows import attenuation, shadow_share
from designer.study.factors import DRAWS, FACTORS
from tests.synthetic import assert_located_error, write_project_file
from tests.world.helpers import timed_survey

CLOUDS = m.CloudShadows(cover=0.3, size_m=40.0, softness_m=5.0, depth=0.6,
                        wind_speed_m_s=5.0, wind_direction_deg=270.0, seed=3)


def _cloudy(clouds=CLOUDS) -> m.Project:
    p = timed_survey(sun_over_time=False)
    return replace(p, scene=replace(p.scene, lighting=replace(p.scene.lighting, clouds=clouds)))


def _grid(n=400, step=1.0):
    return np.arange(n) * step, np.arange(n)[::-1] * step


def test_the_shadowed_share_of_a_large_area_is_the_cover():
    xs, ys = _grid(800, 2.0)  # 1.6 km: 40 clouds across
    for cover in (0.1, 0.3, 0.7):
        share = shadow_share(replace(CLOUDS, cover=cover, softness_m=0.0), xs, ys, 0.0)
        assert abs(share.mean() - cover) < 0.05, (cover, share.mean())
    assert shadow_share(replace(CLOUDS, cover=0.0), xs, ys, 0.0).max() == 0.0


def test_the_field_moves_with_the_wind_and_depends_on_the_seed():
    xs, ys = _grid()
    c = replace(CLOUDS, wind_direction_deg=90.0, wind_speed_m_s=2.0)  # towards east
    a0 = attenuation(c, xs, ys, 0.0)
    a1 = attenuation(c, xs, ys, 10.0)  # 20 m = 20 texels east
    assert np.abs(a1[:, 20:] - a0[:, :-20]).max() < 1e-5
    assert np.abs(a1 - a0).max() > 0.5
    assert a0.min() == pytest.approx(1 - c.depth, abs=1e-6) and a0.max() == pytest.approx(1.0)
    other = attenuation(replace(c, seed=4), xs, ys, 0.0)
    assert np.mean(np.abs(other - a0) > 0.1) > 0.1


def test_an_edge_is_softness_wide():
    xs, ys = _grid(600, 0.25)
    hard = shadow_share(replace(CLOUDS, softness_m=0.0), xs, ys, 0.0)
    soft = shadow_share(replace(CLOUDS, softness_m=8.0), xs, ys, 0.0)
    partial = lambda s: np.mean((s > 0.1) & (s < 0.9))  # noqa: E731
    assert partial(soft) > 5 * partial(hard)


def test_the_clouds_survive_a_round_trip_through_the_file(tmp_path):
    p = _cloudy()
    path = write_project_file(p, tmp_path)
    assert "<cloud-shadows" in path.read_text()
    assert load_project(path).scene.lighting.clouds == CLOUDS


@pytest.mark.parametrize(("attr", "value"), [
    ("cover", "1.5"), ("cover", "-0.1"), ("size-m", "0"), ("size-m", "-4"),
    ("depth", "1.2"), ("depth", "-0.5"), ("wind-speed-m-s", "-1"), ("softness-m", "-1"),
    ("wind-direction-deg", "360"), ("seed", "-2"), ("cover", "nan"),
])
def test_every_bad_value_is_a_located_one_line_error(tmp_path, attr, value):
    assert_located_error(
        _cloudy(), tmp_path,
        lambda text: re.sub(rf'(<cloud-shadows[^>]* {attr}=)"[^"]*"', rf'\1"{value}"', text),
        "<cloud-shadows", (attr, "cloud-shadows"))


def test_the_study_engine_can_vary_the_clouds():
    p = timed_survey(sun_over_time=False)
    assert FACTORS["cloud-cover"].get(p) == 0.0
    cloudy = FACTORS["cloud-cover"].set(p, FACTORS["cloud-cover"].parse("0.4"))
    assert cloudy.scene.lighting.clouds.cover == 0.4
    windy = FACTORS["wind-speed-m-s"].set(cloudy, 7.0)
    assert FACTORS["wind-speed-m-s"].get(windy) == 7.0
    assert FACTORS["wind-direction-deg"].get(
        FACTORS["wind-direction-deg"].set(windy, 45.0)) == 45.0
    assert FACTORS["cloud-size-m"].get(FACTORS["cloud-size-m"].set(windy, 25.0)) == 25.0
    assert FACTORS["cloud-depth"].get(FACTORS["cloud-depth"].set(windy, 0.3)) == 0.3
    assert FACTORS["cloud-cover"].set(windy, 0.0).scene.lighting.clouds is None
    assert DRAWS["clouds"][1](windy, 9).scene.lighting.clouds.seed == 9


def test_without_a_time_line_the_clouds_stay_as_at_takeoff(tmp_path):
    """One light map for every photo, dimmed by the clouds at t = 0; with the time line
    each photo gets its own light map."""
    import cv2

    from designer.render.job import prepare_job

    frozen = replace(_cloudy(replace(CLOUDS, size_m=8.0)), trajectory=replace(
        _cloudy().trajectory, time_line=None))
    job = prepare_job(frozen, tmp_path, tmp_path / "frozen").job
    assert job.light_steps == () and all(f.light_step is None for f in job.frames)
    clear = replace(frozen, scene=replace(frozen.scene, lighting=replace(
        frozen.scene.lighting, clouds=None)))
    prepare_job(clear, tmp_path, tmp_path / "clear")
    lm = [cv2.imread(str(tmp_path / d / ".designer-job/lightmap.png"), cv2.IMREAD_UNCHANGED)
          .astype(float) for d in ("frozen", "clear")]
    assert np.mean(lm[0] < 0.9 * lm[1]) > 0.05  # shadows on part of the ground
    drifting = prepare_job(_cloudy(replace(CLOUDS, size_m=8.0)), tmp_path, tmp_path / "d").job
    assert len(drifting.light_steps) == 2
    assert [f.light_step for f in drifting.frames] == [0, 1]
