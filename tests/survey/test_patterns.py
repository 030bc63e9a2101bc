"""Orbit and facade flights: geometry of the stations, the file, the plan report."""

from __future__ import annotations

import json
import re
import subprocess
import sys
from dataclasses import replace

import numpy as np
import pytest

from designer.core.interior import InteriorOrientation
from designer.core.projection import project_points
from designer.project import load_project
from designer.project import model as m
from designer.project.problems import ProjectError
from designer.survey.patterns import facade_stations, orbit_stations
from designer.survey.project_poses import project_images
from tests.synthetic import ORIGIN_WORLD, rig_survey, write_project_file

CAMERA = InteriorOrientation(focal_length_mm=4.0, sensor_width_mm=6.4, sensor_height_mm=4.8,
                             image_width_px=640, image_height_px=480)


@pytest.mark.parametrize("n", [1, 7, 24])
def test_orbit_cameras_face_the_centre_from_the_circle(n):
    centre = ORIGIN_WORLD + [3.0, -2.0, 1.5]
    stations = orbit_stations(centre, 30.0, 20.0, n, start_azimuth_deg=15.0)
    assert len(stations) == n
    for k, st in enumerate(stations):
        d = st.C_world - centre
        assert np.hypot(d[0], d[1]) == pytest.approx(30.0) and d[2] == pytest.approx(20.0)
        azimuth = np.degrees(np.arctan2(d[0], d[1])) % 360
        assert azimuth == pytest.approx((15.0 + 360.0 * k / n) % 360, abs=1e-9)
        uv = project_points(centre[None], st.C_world, st.R_cam_to_world, CAMERA).uv_px[0, 0]
        assert np.allclose(uv, [320.0, 240.0], atol=1e-9)  # the principal point
        assert st.R_cam_to_world[2, 1] > 0  # image top away from the ground


def test_orbit_with_a_tilt_looks_that_far_from_nadir_towards_the_centre():
    centre = ORIGIN_WORLD
    for st in orbit_stations(centre, 30.0, 20.0, 6, tilt_deg=45.0):
        view = -st.R_cam_to_world[:, 2]
        assert np.degrees(np.arccos(-view[2])) == pytest.approx(45.0)
        towards = (centre - st.C_world)[:2]
        assert np.cross(view[:2], towards) == pytest.approx(0.0, abs=1e-9)
        assert view[:2] @ towards > 0


@pytest.mark.parametrize("side", ["left", "right"])
def test_facade_rows_stand_at_the_distance_and_face_the_wall(side):
    start, end = ORIGIN_WORLD[:2], ORIGIN_WORLD[:2] + [30.0, 40.0]  # 50 m long
    stations = facade_stations(start, end, 250.0, 12.0, (3.0, 7.5), 10.0, side=side)
    assert len(stations) == 2 * 6
    along = (end - start) / 50.0
    normal = np.array([along[1], -along[0]]) * (1 if side == "right" else -1)
    for st in stations:
        rel = st.C_world[:2] - start
        assert rel @ normal == pytest.approx(12.0)
        assert st.C_world[2] in (253.0, 257.5)
        # level camera facing the wall: the wall point straight ahead is at the principal
        # point, at the camera's height
        wall = np.array([*(start + (rel @ along) * along), st.C_world[2]])
        uv = project_points(wall[None], st.C_world, st.R_cam_to_world, CAMERA).uv_px[0, 0]
        assert np.allclose(uv, [320.0, 240.0], atol=1e-9)
    # the second row is flown back
    first, second = stations[:6], stations[6:]
    assert np.allclose([s.C_world[:2] for s in first], [s.C_world[:2] for s in second[::-1]])


def test_facade_tilt_looks_down_at_the_wall():
    st = facade_stations((0.0, 0.0), (10.0, 0.0), 0.0, 5.0, (10.0,), 5.0, tilt_deg=20.0)[0]
    view = -st.R_cam_to_world[:, 2]
    assert np.degrees(np.arcsin(-view[2])) == pytest.approx(20.0)


def _patterned(tmp_path):
    project = rig_survey(n_stations=2)
    orbit = m.OrbitPattern("penta", "ORB_", m.Point3(*ORIGIN_WORLD), 15.0, 12.0, 8,
                           tilt_deg=40.0)
    facade = m.FacadePattern("nadir", "FAC_", tuple(ORIGIN_WORLD[:2] + [-10, 10]),
                             tuple(ORIGIN_WORLD[:2] + [10, 10]), ORIGIN_WORLD[2], 8.0,
                             (3.0, 6.0), 5.0, "right", 10.0)
    project = replace(project, trajectory=replace(project.trajectory,
                                                  patterns=(orbit, facade)))
    return project, write_project_file(project, tmp_path)


def test_patterns_survive_the_file_and_fly_with_a_rig(tmp_path):
    project, path = _patterned(tmp_path)
    assert load_project(path) == project
    images = project_images(project, None)
    names = [s.image_name for s in images.stations]
    assert len(names) == 2 * 5 + 8 * 5 + 10
    assert "ORB_00008_R.png" in names and "FAC_00010.png" in names


def test_plan_reports_rig_orbit_and_facade(tmp_path):
    _, path = _patterned(tmp_path)
    run = subprocess.run([sys.executable, "-m", "designer", "plan", str(path)],
                         capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stderr
    out = run.stdout
    assert "rig penta: 5 cameras" in out and "60 images in all" in out
    assert re.search(r"orbit ORB_ \(penta\): 8 stations, radius 15 m", out), out
    assert re.search(r"facade FAC_ \(nadir\): 10 stations in 2 rows every 5 m", out), out
    # every camera of the rig has its own GSD line
    gsd = {c: float(v) for c, v in re.findall(
        r"camera (\w+): \d+ images, GSD at the image centre ([\d.]+) cm", out)}
    assert set(gsd) == {"nadir", "fwd", "back", "left", "right"}
    run = subprocess.run([sys.executable, "-m", "designer", "plan", str(path), "--json"],
                         capture_output=True, text=True, timeout=300)
    figures = json.loads(run.stdout)
    assert figures["n_images_all_cameras"] == 60
    assert {c["id"]: c["images"] for c in figures["cameras"]}["fwd"] == 10


@pytest.mark.parametrize(("edit", "words"), [
    (lambda t: t.replace('stations="8"', 'stations="0"'), "stations"),
    (lambda t: t.replace('tilt-deg="40.0"', 'tilt-deg="120"'), "tilt-deg"),
    (lambda t: re.sub(r'X2="[^"]*" Y2="[^"]*"', lambda _: 'X2="{}" Y2="{}"'.format(
        *re.search(r'X1="([^"]*)" Y1="([^"]*)"', t).groups()), t), "same point"),
    (lambda t: t.replace('camera="nadir" image-prefix="FAC_"',
                         'camera="zoom" image-prefix="FAC_"'), "camera 'zoom'"),
    (lambda t: t.replace('side="right"', 'side="up"'), "side"),
])
def test_bad_patterns_are_one_line_errors(tmp_path, edit, words):
    _, path = _patterned(tmp_path)
    text = path.read_text()
    path.write_text(edit(text))
    assert path.read_text() != text
    with pytest.raises(ProjectError) as info:
        load_project(path)
    lines = info.value.lines
    assert any(words in x for x in lines), lines
    assert all("\n" not in x for x in lines)


def test_written_poses_of_a_rig_flight_give_the_same_images(tmp_path):
    project, path = _patterned(tmp_path)
    out = tmp_path / "poses.xml"
    run = subprocess.run([sys.executable, "-m", "designer", "plan", str(path),
                          "--write-poses", str(out)], capture_output=True, text=True,
                         timeout=300)
    assert run.returncode == 0, run.stderr
    explicit = load_project(out)
    assert explicit.trajectory.patterns == () and explicit.trajectory.rigs
    a, b = project_images(project, None), project_images(explicit, None)
    assert [s.image_name for s in a.stations] == [s.image_name for s in b.stations]
    assert a.camera_ids == b.camera_ids
    for s, t in zip(a.stations, b.stations, strict=True):
        assert np.allclose(s.C_world, t.C_world, atol=1e-9)
        assert np.allclose(s.R_cam_to_world, t.R_cam_to_world, atol=1e-12)
