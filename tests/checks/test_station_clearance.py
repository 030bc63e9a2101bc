"""Camera stations under the ground (or inside a building or a plant) are an error of
``designer check`` and ``designer plan``, naming how many and the lowest clearance, and
the fix (issue #53, finding 1)."""

from __future__ import annotations

import dataclasses
import re

import numpy as np
import pytest

from designer.cli.main import main
from tests.survey.scenes import survey_flown

LOW = re.compile(r"low\.xml:\d+:\d+: <flight-plan>: (\d+) of (\d+) camera stations are below "
                 r"the terrain or within 1 cm of it; the lowest, (DJI_\d+\.png), is "
                 r"(\d+\.\d+) m below it")


def test_check_refuses_a_flight_inside_the_hills(tmp_path, capsys):
    path = survey_flown(tmp_path, 5.0)
    assert main(["check", str(path)]) == 2
    err = capsys.readouterr().err
    found = LOW.search(err)
    assert found, err
    n_low, n, _, depth = found.groups()
    assert 0 < int(n_low) < int(n)
    # 5 m above the mean under a hill 9.4 m above it (and a little pose noise)
    assert 3.5 < float(depth) < 5.5, err
    assert "raise the flight height (altitude-agl-m) by more than" in err, err
    assert "1 problem; not a valid designer project" in err, err
    # figures measured from under the ground are not reported as if they were true
    assert "texel" not in err, err


def test_plan_refuses_a_flight_inside_the_hills(tmp_path, capsys):
    path = survey_flown(tmp_path, 5.0)
    assert main(["plan", str(path)]) == 2
    captured = capsys.readouterr()
    assert LOW.search(captured.err), captured.err
    assert "GSD over the terrain" not in captured.out


def test_a_flight_above_the_hills_is_valid(tmp_path, capsys):
    path = survey_flown(tmp_path, 20.0, 80.0, 70.0)
    assert main(["check", str(path)]) == 0, capsys.readouterr().err
    assert "camera stations" not in capsys.readouterr().err


def test_stations_inside_a_building_or_a_tree_and_just_above_the_ground():
    """On flat ground at 0 m: a station 1 m above the ground beside everything is clear;
    one 0.5 cm above it is within the camera's near distance; one inside a 6 m building;
    one inside an 8 m tree's crown; one over the building's roof."""
    from designer.checks.station_clearance import NEAR_M, station_clearance
    from designer.core.heightfield import Heightfield

    hf = Heightfield(-50.0, -50.0, 1.0, 1.0, np.zeros((101, 101)))
    box_v = np.array([[x, y, z] for z in (0.0, 6.0) for x, y in
                      ((10, 10), (20, 10), (20, 20), (10, 20))], float)
    box_f = np.array([[4, 5, 6], [4, 6, 7], [0, 2, 1], [0, 3, 2]])  # roof, floor
    plants = (np.array([[-20.0, -20.0, 0.0]]), np.array([8.0]), np.array([5.0]))
    C = np.array([[0, 0, 1.0], [0, 1, 0.005], [15, 15, 3.0], [-21, -20, 7.0],
                  [15, 15, 7.0], [60, 60, -3.0]])
    clear, what = station_clearance(C, hf, [(box_v, box_f)], plants)
    assert clear[0] == pytest.approx(1.0)
    assert 0 < clear[1] < NEAR_M and what[1] == "terrain"
    assert clear[2] == pytest.approx(-3.0) and what[2] == "buildings"
    assert clear[3] == pytest.approx(-1.0) and what[3] == "vegetation"
    assert clear[4] == pytest.approx(1.0) and what[4] == "buildings"
    assert np.isnan(clear[5])  # off the terrain: nothing is known below it


def test_low_stations_as_an_issue_of_the_flight_plan(tmp_path):
    from designer.checks.station_clearance import clearance_issues
    from designer.project import load_project

    project = load_project(survey_flown(tmp_path, 5.0))
    (issue,) = clearance_issues(project, tmp_path)
    assert issue.code == "stations-too-low"
    assert issue.obj is project.trajectory.flight_plan and issue.tag == "flight-plan"
    low = issue.value
    assert 0 < low.n_low < low.n_stations and low.lowest_m < -3.5
    assert low.under == "terrain"
    high = dataclasses.replace(project, trajectory=dataclasses.replace(
        project.trajectory, flight_plan=dataclasses.replace(
            project.trajectory.flight_plan, altitude_agl_m=50.0)))
    assert clearance_issues(high, tmp_path) == []


def test_the_near_distance_is_the_render_cameras():
    from designer.checks.station_clearance import NEAR_M
    from designer.render.job_spec import CameraSpec

    assert CameraSpec(1, 1, "AUTO", 0, 0, 1, 1, 1, 1).clip_start_m == NEAR_M


def test_render_refuses_a_flight_inside_the_hills(tmp_path, capsys):
    """The window saves such a file as work in progress; rendering it would make images
    from inside the hills, so ``designer render`` refuses it as check and plan do, before
    any image is rendered, in one line."""
    path = survey_flown(tmp_path, 5.0)
    out = tmp_path / "out"
    # two frames: were it not refused, the test would not render the whole survey
    assert main(["render", str(path), "-o", str(out), "--frames", "0-1"]) == 2
    err = capsys.readouterr().err
    lines = [line for line in err.splitlines() if line.strip()]
    assert len(lines) == 1, err
    assert LOW.search(lines[0]), err
    assert not (out / "images").exists()
