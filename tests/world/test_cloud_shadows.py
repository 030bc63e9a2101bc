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


def _cloudy_buildings(clouds: m.CloudShadows, times_s: tuple[float, ...] | None) -> m.Project:
    from tests.world.building_helpers import building_project
    from tests.world.helpers import TAKEOFF

    p = building_project()
    trajectory = p.trajectory
    if times_s is not None:
        photos = tuple(replace(e, time_s=t) for e, t in
                       zip(p.trajectory.exterior_orientations, times_s, strict=True))
        trajectory = m.Trajectory(photos, None, m.TimeLine(TAKEOFF, 5.0, 8.0))
    lighting = replace(p.scene.lighting, clouds=clouds)
    return replace(p, trajectory=trajectory, scene=replace(p.scene, lighting=lighting))


def _light_of(objects, name: str) -> list[float]:
    (spec,) = [o for o in objects if o.name == name]
    return [mat.strength if mat.texture else mat.color[0] for mat in spec.materials]


def test_under_a_full_cover_buildings_and_targets_lose_the_depth_share_of_the_sun(tmp_path):
    """Cloud shadows dim what stands on the ground as they dim the ground: a roof and a
    target under a cloud get ``1 − depth`` of the direct sun, a clear sky all of it."""
    from designer.render.job import prepare_job
    from designer.render.job_light import TARGET_WHITE
    from designer.scene.lighting import irradiance, sun_direction_world

    overcast = replace(CLOUDS, cover=1.0, depth=0.6)
    lights = {}
    for name, clouds in (("clear", None), ("overcast", overcast)):
        job = prepare_job(_cloudy_buildings(clouds, None), tmp_path, tmp_path / name).job
        lights[name] = job.objects
    p = _cloudy_buildings(None, None)
    lighting = p.scene.lighting
    sun = sun_direction_world(lighting.sun.azimuth_deg, lighting.sun.elevation_deg)
    up = np.array([[0.0, 0.0, 1.0]])
    dimmed = irradiance(up, np.array([0.4]), sun, lighting.sun_strength,
                        lighting.sky_strength)[0]
    clear, overcast = _light_of(lights["clear"], "buildings"), _light_of(
        lights["overcast"], "buildings")
    assert min(abs(e - 1.0) for e in clear) < 1e-12  # the level roofs, in the sun
    assert min(abs(e - dimmed) for e in overcast) < 1e-6  # ... (float32 cloud mask)
    assert max(overcast) < 0.8 * max(clear)  # every face in the cloud's shadow
    # the targets (on gently sloping ground) lose the same share as a level roof
    white_clear = max(_light_of(lights["clear"], "gcp_targets"))
    assert white_clear == pytest.approx(TARGET_WHITE, rel=0.01)
    assert max(_light_of(lights["overcast"], "gcp_targets")) / white_clear == pytest.approx(
        dimmed, rel=0.01)


def test_drifting_clouds_light_each_photos_buildings_as_the_ground_under_them(tmp_path):
    """With a time line each photo's buildings, targets and objects are lit by the clouds
    of its moment: a level roof's light is the direct sun dimmed by the clouds' factor at
    the roof's centre, evaluated independently from the cloud field."""
    from designer.render.job import prepare_job
    from designer.scene.lighting import irradiance, sun_direction_world

    clouds = replace(CLOUDS, cover=0.5, size_m=6.0, softness_m=0.5, depth=0.8,
                     wind_speed_m_s=3.0, wind_direction_deg=90.0, seed=0)
    p = _cloudy_buildings(clouds, (0.0, 2.0))
    prepared = prepare_job(p, tmp_path, tmp_path / "job")
    job = prepared.job
    assert [f.light_step for f in job.frames] == [0, 1]
    lighting = p.scene.lighting
    sun = sun_direction_world(lighting.sun.azimuth_deg, lighting.sun.elevation_deg)
    # the tower's flat roof: 4.5..5.5 m east, -1..1 m north of the origin, 15 m high
    x, y = np.array([5.0 - 0.01, 5.0 + 0.01]), np.array([0.01, -0.01])
    roof_lights = []
    for step, t in zip(job.light_steps, (0.0, 2.0), strict=True):
        (spec,) = [o for o in step.objects if o.name == "buildings"]
        data = np.load(tmp_path / "job" / ".designer-job" / spec.mesh)
        corners = data["vertices_local"][data["faces"]]
        on_tower = ((np.abs(corners[:, :, 0].mean(1) - 5.0) < 0.5)
                    & (np.abs(corners[:, :, 1].mean(1)) < 1.0)
                    & (corners[:, :, 2].min(1) > corners[:, :, 2].max() - 1e-6))
        levels = set(data["material_index"][on_tower])
        a = attenuation(clouds, x, y, t).mean()
        expected = irradiance(np.array([[0.0, 0.0, 1.0]]), np.array([a]), sun,
                              lighting.sun_strength, lighting.sky_strength)[0]
        got = [spec.materials[i].strength for i in levels]
        assert max(abs(g - expected) for g in got) < 0.02, (t, got, expected)
        roof_lights.append(float(np.mean(got)))
    # seed 0: the tower is under a cloud at take-off, in the sun 2 s later
    assert roof_lights[1] - roof_lights[0] > 0.3, roof_lights
