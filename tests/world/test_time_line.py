"""The flight time line: times against hand computation, the sun per image against
astral, bad values as located one-line errors, and the study factors."""

from __future__ import annotations

import datetime as _dt
import re
from dataclasses import replace

import numpy as np
import pytest
from astral import Observer
from astral.sun import azimuth, elevation

from designer.project import load_project
from designer.project import model as m
from designer.project.interiors import interior_from_camera
from designer.project.problems import ProjectError
from designer.scene.sun_over_time import Site, project_site, sun_at
from designer.study.factors import FACTORS
from designer.survey.flight import Station, camera_calc
from designer.survey.project_poses import project_stations
from designer.survey.timeline import project_station_times, station_times_s
from tests.synthetic import assert_located_error, small_survey, write_project_file
from tests.world.helpers import ORIGIN, TAKEOFF, timed_survey


def _station(name, x, y, line):
    return Station(name, np.array([x, y, 100.0]), np.eye(3), line, 0, 90.0)


def test_times_follow_the_legs_at_the_speed_plus_a_turn_per_line_change():
    stations = [_station("a", 0, 0, 0), _station("b", 10, 0, 0), _station("c", 20, 0, 0),
                _station("d", 20, 15, 1), _station("e", 10, 15, 1)]
    times = station_times_s(stations, m.TimeLine(TAKEOFF, speed_m_s=5.0, turn_s=8.0))
    # by hand: 10 m at 5 m/s = 2 s; the line change: 15 m / 5 m/s + 8 s turn = 11 s
    assert times.tolist() == [0.0, 2.0, 4.0, 15.0, 17.0]


def test_an_explicit_time_replaces_the_computed_one_and_the_flight_goes_on_from_it():
    stations = [_station("a", 0, 0, -1), _station("b", 30, 0, -2), _station("c", 30, 40, -3)]
    times = station_times_s(stations, m.TimeLine(TAKEOFF, 10.0, 8.0), [None, 100.0, None])
    assert times.tolist() == [0.0, 100.0, 104.0]  # explicit photos turn no corners


def test_a_planned_flight_is_timed_by_its_trigger_distance_and_turns():
    p = small_survey(origin=ORIGIN)
    E0, N0, _ = ORIGIN
    plan = m.FlightPlan("cam", "F", ((E0 - 15, N0 - 15), (E0 + 15, N0 - 15), (E0 + 15, N0 + 15),
                                     (E0 - 15, N0 + 15)), altitude_agl_m=30.0,
                        altitude_reference=400.0)
    tl = m.TimeLine(TAKEOFF, 4.0, 12.5)
    p = replace(p, trajectory=m.Trajectory((), plan, tl))
    stations, _ = project_stations(p, None)
    times = project_station_times(p, stations)
    calc = camera_calc(interior_from_camera(p.cameras[0]), altitude_agl_m=30.0,
                       front_overlap_fraction=0.8, side_overlap_fraction=0.7)
    lines = [s.line_index for s in stations]
    assert len(set(lines)) > 1
    for k in range(1, len(stations)):
        dt = times[k].time_s - times[k - 1].time_s
        if lines[k] == lines[k - 1]:
            assert dt == pytest.approx(calc.trigger_distance_m / 4.0, rel=1e-9)
        else:
            gap = float(np.linalg.norm(stations[k].C_world - stations[k - 1].C_world))
            assert dt == pytest.approx(gap / 4.0 + 12.5, rel=1e-9)
        assert times[k].time_utc == times[0].time_utc + _dt.timedelta(seconds=times[k].time_s)


def test_the_sun_per_image_is_astrals_turned_by_the_meridian_convergence():
    site = Site(46.9, 9.0, 0.0)
    moment = _dt.datetime(2026, 6, 21, 7, 15, 30, tzinfo=_dt.UTC)
    obs = Observer(latitude=46.9, longitude=9.0)
    assert sun_at(moment, site) == pytest.approx((azimuth(obs, moment), elevation(obs, moment)))
    project = timed_survey()
    project = replace(project, origin=m.Origin(560000.0, 5200000.0, 400.0))  # 60 km east
    site = project_site(project, project.scene.lighting.sun)
    assert 0.3 < site.convergence_deg < 1  # east of the central meridian, north: γ > 0
    az, _ = sun_at(moment, site)
    true_az = azimuth(Observer(site.latitude_deg, site.longitude_deg), moment)
    assert az == pytest.approx(true_az - site.convergence_deg)


def _load_error(tmp_path, project, edit=None) -> list[str]:
    path = write_project_file(project, tmp_path)
    if edit is not None:
        path.write_text(edit(path.read_text()))
    with pytest.raises(ProjectError) as info:
        load_project(path)
    return info.value.lines


@pytest.mark.parametrize(("edit", "needle", "words"), [
    (lambda t: t.replace('speed-m-s="5.0"', 'speed-m-s="-5"'), "<time-line", "speed-m-s"),
    (lambda t: t.replace('takeoff-utc="2026-06-21T06:00:00Z"',
                         'takeoff-utc="2026-06-21T08:00:00+02:00"'), "<time-line", "UTC"),
    (lambda t: t.replace('turn-s="8.0"', 'turn-s="-1"'), "<time-line", "turn-s"),
    (lambda t: t.replace('time-s="7200.0"', 'time-s="-3"'), 'time-s="-3"', "time-s"),
])
def test_bad_time_line_values_are_located_one_line_errors(tmp_path, edit, needle, words):
    assert_located_error(timed_survey(), tmp_path, edit, needle, words)


def test_a_trigger_interval_too_long_for_the_overlap_is_refused(tmp_path):
    p = small_survey(origin=ORIGIN)
    E0, N0, _ = ORIGIN
    plan = m.FlightPlan("cam", "F", ((E0 - 15, N0 - 15), (E0 + 15, N0 - 15), (E0 + 15, N0 + 15),
                                     (E0 - 15, N0 + 15)), altitude_agl_m=30.0,
                        altitude_reference=400.0)
    # 30 m: footprint along 30 * 4.8 / 5 = 28.8 m, 80 % overlap: a photo every 5.76 m
    slow = replace(p, trajectory=m.Trajectory((), plan, m.TimeLine(TAKEOFF, 5.76 / 2.0, 0.0,
                                                                   2.0)))
    write_project_file(slow, tmp_path)
    load_project(tmp_path / "project.xml")  # exactly the camera's pace: fine
    fast = replace(slow, trajectory=replace(slow.trajectory, time_line=m.TimeLine(
        TAKEOFF, 5.0, 0.0, 2.0)))
    lines = _load_error(tmp_path, fast)
    assert len(lines) == 1 and "time-line" in lines[0] and "trigger interval" in lines[0]
    assert "at most 2.88 m/s" in lines[0]


@pytest.mark.parametrize(("change", "words"), [
    (lambda p: replace(p, trajectory=replace(p.trajectory, time_line=None)), "sun-over-time"),
    (lambda p: replace(p, render=replace(p.render, image_metadata="exif")), "jpeg or tiff"),
    (lambda p: replace(p, scene=replace(p.scene, lighting=m.Lighting(m.SunOverTime(46.0)))),
     "both the latitude and the longitude"),
])
def test_inconsistent_world_elements_are_clean_errors(tmp_path, change, words):
    lines = _load_error(tmp_path, change(timed_survey()))
    assert any(words in line and re.match(r".*project\.xml:\d+:\d+: ", line) for line in lines), \
        lines


def test_the_study_engine_can_vary_the_timing():
    p = timed_survey()
    later = FACTORS["takeoff-time"].set(p, FACTORS["takeoff-time"].parse("2026-06-21T10:00:00Z"))
    assert FACTORS["takeoff-time"].get(later) == "2026-06-21T10:00:00Z"
    assert FACTORS["flight-speed-m-s"].get(FACTORS["flight-speed-m-s"].set(p, 9.0)) == 9.0
    assert FACTORS["turn-s"].get(FACTORS["turn-s"].set(p, 3.0)) == 3.0
    with pytest.raises(ValueError, match="UTC"):
        FACTORS["takeoff-time"].parse("2026-06-21T10:00:00+02:00")
    bare = replace(p, trajectory=replace(p.trajectory, time_line=None))
    with pytest.raises(ValueError, match="time-line"):
        FACTORS["flight-speed-m-s"].set(bare, 4.0)


def test_the_new_elements_survive_a_round_trip_through_the_file(tmp_path):
    p = timed_survey()
    p = replace(p, trajectory=replace(p.trajectory, time_line=m.TimeLine(
        "2026-06-21T06:00:00.250Z", 6.5, 0.0, 1.5)),
        scene=replace(p.scene, lighting=m.Lighting(m.SunOverTime(46.5, 7.25))),
        render=replace(p.render, output_format="tiff", image_metadata="exif"),
        effects=None)
    photos = tuple(replace(eo, name=eo.name.replace(".png", ".tif"))
                   for eo in p.trajectory.exterior_orientations)
    p = replace(p, trajectory=replace(p.trajectory, exterior_orientations=photos))
    assert load_project(write_project_file(p, tmp_path)) == p
    untimed = tuple(replace(eo, time_s=None) for eo in photos)
    bare = replace(p, trajectory=replace(p.trajectory, time_line=None,
                                         exterior_orientations=untimed),
                   render=replace(p.render, image_metadata="none"),
                   scene=replace(p.scene, lighting=m.Lighting(m.Sun(150.0, 55.0))))
    text = write_project_file(bare, tmp_path / "bare").read_text()
    assert "time" not in text.split("<trajectory>")[1] and "metadata" not in text
