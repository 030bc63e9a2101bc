"""The sun at 1° and 89° elevation (docs/hard-cases.md): tiny real renders whose images are
exposed like any other (the light map is relative to flat ground in full sun), whose GCP
centres are found where the ground truth says, and whose shadows are what the sun
height makes them; a sun below the horizon is refused with the moment and the fix."""

from __future__ import annotations

import datetime as dt
from dataclasses import replace

import cv2
import numpy as np
import pytest

from designer.cli.main import main
from designer.errors import DesignerError
from designer.project import model as m
from designer.render.pipeline import render_project
from designer.scene.lighting import bake_lightmap
from designer.scene.sun_over_time import Site, suns_at
from tests.hard_cases import scenes
from tests.hard_cases.centres import MEAN_PX, measured_centres
from tests.synthetic import write_project_file

SUN_STRENGTH, SKY_STRENGTH = 4.0, 1.0  # tiny_survey's lighting


def _with_sun(sun) -> m.Project:
    project = scenes.tiny_survey(n_photos=2)
    light = replace(project.scene.lighting, sun=sun)
    assert (light.sun_strength, light.sky_strength) == (SUN_STRENGTH, SKY_STRENGTH)
    return replace(project, scene=replace(project.scene, lighting=light))


@pytest.fixture(scope="module", params=[1.0, 89.0], ids=["sun at 1°", "sun at 89°"])
def rendered(request, tmp_path_factory):
    folder = tmp_path_factory.mktemp("sun")
    project = _with_sun(m.Sun(azimuth_deg=150.0, elevation_deg=request.param))
    summary = render_project(write_project_file(project, folder), folder / "out", workers=1)
    light = cv2.imread(str(summary.out_dir / ".designer-job" / "lightmap.png"),
                       cv2.IMREAD_UNCHANGED)
    assert light is not None and light.dtype == np.uint16
    return request.param, summary, light.astype(np.float64) / 65535.0 * 2.0


@pytest.mark.blender
def test_images_under_a_low_and_a_high_sun_are_exposed_like_any_other(rendered):
    """Mean grey 60..140 of 255 (the ±0.5 m terrain at 55° gives 95), texture contrast
    kept, no pixel clipped; the light map finite and within its range."""
    elevation, summary, light = rendered
    assert np.isfinite(light).all() and light.min() > 0.5 and light.max() < 2.0
    for path in sorted(summary.images_dir.glob("*.png")):
        grey = cv2.imread(str(path), cv2.IMREAD_GRAYSCALE)
        assert 60 <= grey.mean() <= 140, f"sun at {elevation}°: {path.name} mean {grey.mean()}"
        assert grey.std() >= 10, f"sun at {elevation}°: {path.name} flat (std {grey.std()})"
        assert (grey == 0).mean() < 0.001 and (grey == 255).mean() < 0.001


@pytest.mark.blender
def test_gcp_centres_are_found_where_the_ground_truth_says_under_a_low_and_a_high_sun(
        rendered):
    elevation, summary, _ = rendered
    d = measured_centres(summary, 4)
    assert len(d) >= 6 and np.isfinite(d).all(), f"sun at {elevation}°: {len(d)} centres"
    assert (np.abs(d.mean(axis=0)) <= MEAN_PX).all(), f"sun at {elevation}°: {d.mean(axis=0)}"


@pytest.mark.blender
def test_shadows_are_what_the_sun_height_makes_them(rendered):
    """Against the same light map baked without cast shadows: at 1° the ±0.5 m bumps cast
    shadows over ground that faces the sun (≥ 100 texels; 406 of 512², 0.15 %, measured —
    a further 5 % faces away from so low a sun and is dark anyway), where the ground
    gets the sky only — sky / (sun·sin 1° + sky) = 0.935 of flat ground in full sun, less
    the little sky a slope does not see; at 89° nothing casts a shadow. Elsewhere the two
    maps agree to the 16-bit encoding."""
    elevation, summary, light = rendered
    open_sky = bake_lightmap(summary.prepared.scene.heightfield, 150.0, elevation,
                             SUN_STRENGTH, SKY_STRENGTH, size_px=light.shape[::-1],
                             shadows=False)
    cast = light < open_sky - 5e-5  # the 16-bit encoding rounds to 1.5e-5
    assert np.abs(light - open_sky)[~cast].max() <= 5e-5
    if elevation < 10:
        sky_only = SKY_STRENGTH / (SUN_STRENGTH * np.sin(np.radians(elevation)) + SKY_STRENGTH)
        assert cast.sum() >= 100, f"sun at 1°: {cast.sum()} texels in cast shadow"
        assert np.abs(light[cast] - sky_only).max() <= 3e-3
    else:
        assert not cast.any(), f"sun at 89°: {cast.mean():.2%} of the ground in shadow"


def test_a_sun_position_below_the_horizon_is_refused_with_the_moment_and_the_fix(
        tmp_path, capsys):
    night = _with_sun(m.SunPosition("2024-06-21T00:30:00+02:00", 47.0, 8.0))
    path = write_project_file(night, tmp_path)
    assert main(["check", str(path)]) == 2
    (line, *_) = capsys.readouterr().err.splitlines()
    assert line.startswith(f"{path}:") and "<sun-position>" in line
    assert "the sun is 18.3° below the horizon at 2024-06-21T00:30:00+02:00" in line
    assert "give a moment in daylight" in line
    day = _with_sun(m.SunPosition("2024-06-21T12:30:00+02:00", 47.0, 8.0))
    assert main(["check", str(write_project_file(day, tmp_path / "day"))]) == 0


def test_a_sun_over_time_that_sets_during_the_flight_is_refused():
    site = Site(47.0, 8.0, 0.0)
    evening = [dt.datetime(2024, 6, 21, 19, 0, tzinfo=dt.UTC) + dt.timedelta(minutes=k)
               for k in (0, 30, 60)]  # sunset at 47° N, 8° E: about 19:27 UTC
    with pytest.raises(DesignerError) as info:
        suns_at(evening, site)
    message = str(info.value)
    assert "\n" not in message and "below the horizon at 2024-06-21T19:30:00+00:00" in message
    assert "move <time-line> takeoff-utc into daylight" in message
    assert len(suns_at(evening[:1], site)) == 1
