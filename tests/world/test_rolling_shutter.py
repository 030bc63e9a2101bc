"""Rolling-shutter cameras: the element survives the file, bad values are located one-line
errors, the platform's velocity follows the legs of the time line, a changed readout
makes the images stale, and a readout of 0 renders byte for byte as a global shutter."""

from __future__ import annotations

import re
from dataclasses import replace

import numpy as np
import pytest

from designer.core.rotation import rotation_from_opk
from designer.project import load_project
from designer.project import model as m
from designer.render.job import prepare_job
from designer.render.pipeline import render_project
from designer.render.provenance import ground_truth_digest, job_provenance
from designer.survey.flight import Station
from designer.survey.timeline import station_velocities_m_s
from tests.synthetic import assert_located_error, write_project_file
from tests.world.rolling_helpers import global_shutter, rolling_project


def test_the_rolling_shutter_survives_a_round_trip_through_the_file(tmp_path):
    p = rolling_project(readout_s=0.025, direction="bottom-to-top")
    back = load_project(write_project_file(p, tmp_path))
    assert back.cameras[0].rolling_shutter == m.RollingShutter(0.025, "bottom-to-top")
    assert back.cameras[0].readout_s == 0.025
    bare = load_project(write_project_file(global_shutter(p), tmp_path / "bare"))
    assert bare.cameras[0].rolling_shutter is None and bare.cameras[0].readout_s == 0.0
    assert "rolling-shutter" not in (tmp_path / "bare" / "project.xml").read_text()


@pytest.mark.parametrize(("edit", "words"), [
    (lambda t: re.sub(r"<time-line[^>]*/>", "", t), "add a time line to the trajectory"),
    (lambda t: t.replace('readout-s="0.03"', 'readout-s="-0.01"'), "readout-s"),
    (lambda t: t.replace('readout-s="0.03"', 'readout-s="0.7"'), "readout-s"),
    (lambda t: t.replace('readout-s="0.03"', 'readout-s="fast"'), "readout-s"),
    (lambda t: t.replace('direction="top-to-bottom"', 'direction="left-to-right"'),
     "direction"),
    (lambda t: t.replace('speed-m-s="10.0"',
                         'speed-m-s="10.0" trigger-interval-s="0.02"'),
     "trigger-interval-s"),
    (lambda t: t.replace("<rolling-shutter",
                         '<brown-conrady k1="-0.1" k2="0" k3="0" p1="0" p2="0"/>'
                         "<rolling-shutter"), "distortion"),
])
def test_bad_rolling_shutters_are_located_one_line_errors(tmp_path, edit, words):
    assert_located_error(rolling_project(), tmp_path, edit, "<rolling-shutter", words)


def test_designer_check_names_the_rolling_shutter(tmp_path):
    from designer.project.summary import summary_line

    p = rolling_project(readout_s=0.025)
    assert "rolling shutter (25 ms readout)" in summary_line("p.xml", p)
    assert "rolling shutter" not in summary_line("p.xml", global_shutter(p))


def test_a_readout_of_zero_needs_no_time_line(tmp_path):
    p = rolling_project(readout_s=0.0, time_line=False)
    assert load_project(write_project_file(p, tmp_path)).cameras[0].readout_s == 0.0


def _station(name, xyz, line, azimuth=0.0):
    return Station(name, np.array(xyz, float), rotation_from_opk(0.0, 0.0, 0.0), line, 0,
                   azimuth)


def test_the_velocity_is_the_speed_along_the_leg_flown_and_the_incoming_leg_before_a_turn():
    tl = m.TimeLine("2026-06-21T09:30:00Z", 8.0, turn_s=5.0)
    stations = [_station("a", (0, 0, 100), 0, 0.0), _station("b", (0, 30, 100), 0, 0.0),
                _station("c", (0, 60, 110), 0, 0.0),  # last of line 0: climbs into it
                _station("d", (40, 60, 110), 1, 180.0), _station("e", (40, 30, 110), 1, 180.0)]
    v = station_velocities_m_s(stations, tl)
    np.testing.assert_allclose(v[0], [0, 8, 0])
    np.testing.assert_allclose(v[1], 8 * np.array([0, 30, 10]) / np.hypot(30, 10))
    np.testing.assert_allclose(v[2], v[1])  # the leg that led to it, not the turn
    np.testing.assert_allclose(v[3], [0, -8, 0])
    np.testing.assert_allclose(v[4], [0, -8, 0])
    np.testing.assert_allclose(np.linalg.norm(v, axis=1), 8.0)
    lone = station_velocities_m_s([_station("x", (0, 0, 50), -1, 90.0)], tl)
    np.testing.assert_allclose(lone[0], [8, 0, 0], atol=1e-12)


def test_a_changed_readout_makes_every_image_stale_through_its_pose(tmp_path):
    provenances = []
    for k, readout in enumerate((0.03, 0.02, 0.0)):
        p = rolling_project(readout_s=readout, samples=4)
        prepared = prepare_job(p, tmp_path, tmp_path / f"out{k}")
        provenances.append(job_provenance(prepared.job, prepared.job_path.parent))
    for i in (0, 1):
        a, b, c = (prov[i] for prov in provenances)
        assert a.changed_parts(b.to_json()) == ["pose"]
        assert a.changed_parts(c.to_json()) == ["pose"]


@pytest.mark.blender
def test_a_readout_of_zero_renders_byte_for_byte_as_a_global_shutter(tmp_path):
    zero = rolling_project(readout_s=0.0, samples=4)
    bare = global_shutter(zero)
    a = render_project(write_project_file(bare, tmp_path / "a"), tmp_path / "a" / "out")
    b = render_project(write_project_file(zero, tmp_path / "b"), tmp_path / "b" / "out")
    for name in a.prepared.job.image_names.values():
        assert (a.images_dir / name).read_bytes() == (b.images_dir / name).read_bytes()
    assert ground_truth_digest(tmp_path / "a/out/ground-truth") == \
        ground_truth_digest(tmp_path / "b/out/ground-truth")
    assert not (tmp_path / "b/out/ground-truth/rolling_shutter.csv").exists()
    assert a.prepared.job.to_json() == b.prepared.job.to_json().replace(
        str(tmp_path / "b"), str(tmp_path / "a"))
    # and the rolling shutter does change the image
    rs = render_project(write_project_file(replace(zero, cameras=(replace(
        zero.cameras[0], rolling_shutter=m.RollingShutter(0.03)),)), tmp_path / "c"),
        tmp_path / "c" / "out", frames="0")
    name = a.prepared.job.image_names[0]
    assert (rs.images_dir / name).read_bytes() != (a.images_dir / name).read_bytes()
