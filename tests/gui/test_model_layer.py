"""The Qt-free half of the GUI: document, edits, view geometry, files, presets.

No display and no Qt needed; that these modules import without PySide6, VTK or pyvista
installed is checked with the layer contract (tests/test_architecture.py, IMPORT_WITHOUT).
"""

from __future__ import annotations

import dataclasses
import sys
from pathlib import Path

import numpy as np
import pytest

from designer.core.interior import InteriorOrientation
from designer.core.rotation import rotation_from_opk
from designer.gui.state import camera_presets, edits, files
from designer.gui.state.document import ProjectDocument, changed_parts
from designer.gui.state.view_geometry import station_geometry, terrain_display
from designer.project import load_project, template
from designer.project import model as m
from designer.project.validate_camera import camera_issues
from designer.survey.flight import camera_calc


# ------------------------------------------------------------------- camera presets
@pytest.mark.parametrize("preset", camera_presets.PRESETS, ids=lambda p: p.key)
def test_presets_are_valid_square_pixel_cameras(preset):
    cam = preset.camera()
    assert camera_issues(cam) == []
    interior = InteriorOrientation(cam.focal_length_mm, cam.sensor_width_mm,
                                   cam.sensor_height_mm, cam.image_width_px,
                                   cam.image_height_px)
    assert interior.pixel_pitch_x_mm == pytest.approx(interior.pixel_pitch_y_mm, rel=1e-12)
    # the published height is kept to within 2 % (the GoPro's rounding is the worst)
    assert cam.sensor_height_mm == pytest.approx(preset.published_sensor_height_mm, rel=0.02)
    # a real focal length, not a 35 mm equivalent: horizontal FOV between 30° and 100°
    assert 30 < interior.field_of_view_deg()[0] < 100
    assert camera_presets.matching_preset(cam) is preset


def test_zenmuse_p1_pitch_and_a6000_height():
    assert camera_presets.preset("p1").pixel_pitch_um == pytest.approx(4.4)
    assert camera_presets.preset("a6000").sensor_height_mm == pytest.approx(15.666666666666)


# ------------------------------------------------------------------- document
def test_document_events_and_dirty_by_value():
    project = template("survey").project
    doc = ProjectDocument(project, Path("/tmp/x.xml"))
    seen = []
    doc.events.connect("project", lambda old, new, parts: seen.append(parts))
    doc.events.connect("file", lambda path, dirty: seen.append(("dirty", dirty)))
    assert not doc.dirty
    moved = edits.set_flight(project, altitude_agl_m=60.0)
    doc.set_project(moved)
    assert doc.dirty
    assert seen == [{"trajectory"}, ("dirty", True)]
    doc.set_project(project)  # back to the saved value: clean again
    assert not doc.dirty and seen[-1] == ("dirty", False)


def test_failing_listener_does_not_stop_the_others(monkeypatch):
    doc = ProjectDocument(template("psf").project)
    reported, called = [], []
    monkeypatch.setattr(sys, "excepthook", lambda *exc: reported.append(exc[0]))
    doc.events.connect("project", lambda **_: 1 / 0)
    doc.events.connect("project", lambda **kw: called.append(kw["parts"]))
    doc.set_project(edits.set_effect(doc.project, "jpeg", m.Jpeg(80)))
    assert reported == [ZeroDivisionError] and called == [{"effects"}]


def test_changed_parts():
    p = template("survey").project
    assert changed_parts(p, p) == set()
    assert changed_parts(None, p) >= {"terrain", "cameras", "trajectory"}
    q = edits.replace_path(p, "scene.terrain.source.seed", 8)
    assert changed_parts(p, q) == {"terrain"}
    assert changed_parts(p, edits.add_target(p, p.origin.E0, p.origin.N0)) == {"targets"}


# ------------------------------------------------------------------- edits
def test_replace_and_get_path():
    p = template("survey").project
    q = edits.replace_path(p, "cameras[0].focal_length_mm", 10.0)
    assert edits.get_path(q, "cameras[0].focal_length_mm") == 10.0
    assert p.cameras[0].focal_length_mm == 8.8  # the input is untouched


def test_target_edits_and_default_survey_accuracy():
    p = edits.add_target(edits.add_target(template("psf").project, 1.0, 2.0), 3.0, 4.0, "check")
    assert [t.id for t in p.targets] == ["GCP01", "GCP02"]
    assert p.targets[1].role == "check" and p.targets[0].true.Z is None
    assert p.scene.targets.survey_accuracy == edits.DEFAULT_SURVEY_ACCURACY
    p = edits.move_target(p, "GCP01", 5.0, 6.0)
    assert (p.targets[0].true.X, p.targets[0].true.Y) == (5.0, 6.0)
    p = edits.delete_targets(p, ["GCP01"])
    assert [t.id for t in p.targets] == ["GCP02"]
    assert edits.next_target_id(p) == "GCP01"


def test_set_camera_renames_the_flight_camera():
    p = template("survey").project
    q = edits.set_camera(p, camera_presets.preset("a6000").camera("sony"))
    assert q.trajectory.flight_plan.camera == "sony"
    assert [c.id for c in q.cameras] == ["sony"]


def test_set_camera_renames_rig_mounts_and_patterns_and_keeps_the_time_line():
    p = edits.add_oblique_rig(template("survey-dynamic").project)
    orbit = m.OrbitPattern("p4p", "ORB_", m.Point3(0.0, 0.0, 0.0), 10.0, 10.0, 4)
    p = edits.replace_path(p, "trajectory.patterns", (orbit,))
    q = edits.set_camera(p, camera_presets.preset("a6000").camera("sony"))
    assert {mt.camera for mt in q.trajectory.rigs[0].mounts} == {"sony"}
    assert q.trajectory.patterns[0].camera == "sony"
    assert q.trajectory.flight_plan.camera == p.trajectory.rigs[0].name
    assert q.trajectory.time_line == p.trajectory.time_line is not None


# ------------------------------------------------------------------- view geometry
def test_nadir_footprints_on_flat_ground_match_camera_calc():
    interior = InteriorOrientation(8.8, 13.2, 8.8, 5472, 3648)
    C = np.array([[100.0, 200.0, 50.0], [130.0, 200.0, 50.0]])
    R = np.repeat(rotation_from_opk(0.0, 0.0, 0.0)[None], 2, axis=0)
    g = station_geometry(C, R, np.array([0, 0]), interior, None, ground_z_m=0.0)
    calc = camera_calc(interior, altitude_agl_m=50.0, front_overlap_fraction=0.8,
                       side_overlap_fraction=0.7)
    fp = g.footprint_points.reshape(2, -1, 3)
    assert np.ptp(fp[0, :, 0]) == pytest.approx(calc.footprint_across_m)
    assert np.ptp(fp[0, :, 1]) == pytest.approx(calc.footprint_along_m)
    assert np.allclose(fp[:, :, 2], 0.0)
    assert g.frustum_points.shape == (10, 3)
    # VTK cells: 4 apex→corner segments and one closed rectangle per station
    assert list(g.frustum_lines[:18]) == [2, 0, 1, 2, 0, 2, 2, 0, 3, 2, 0, 4, 5, 1, 2, 3, 4, 1]
    assert g.frustum_lines[18:21].tolist() == [2, 5, 6]
    assert list(g.flight_lines) == [2, 0, 1]
    # the image top points north: corners 1, 2 (top edge) lie north of the centre
    top = g.frustum_points[1:3]
    assert np.all(top[:, 1] > C[0, 1])


def test_terrain_display_thins_large_grids():
    from designer.core.heightfield import Heightfield

    hf = Heightfield(0.0, 0.0, 1.0, 1.0, np.zeros((1001, 1001)))
    d = terrain_display(hf, None, (5, 4), max_nodes_per_side=400)
    assert d.stride == 3
    assert len(d.points_world) == 335 * 335  # every 3rd node plus the last row/column
    assert d.points_world[:, 0].max() == 1000.0
    assert d.uv.max(axis=0).tolist() == [5.0, 4.0]


# ------------------------------------------------------------------- files
def test_save_writes_nothing_when_invalid(tmp_path):
    project = files.blank_project()  # no flight yet
    plan = files.plan_save(project, tmp_path / "blank.xml", tmp_path)
    assert not plan.ok
    assert any("blank.xml:" in line for line in plan.problems)
    with pytest.raises(ValueError):
        files.commit_save(plan)
    assert not (tmp_path / "blank.xml").exists()


def test_template_companions_are_copied_on_first_save(tmp_path):
    project, scratch, names = files.new_from_template("texture", tmp_path)
    assert names == ("texture.png",) and (scratch / "texture.png").is_file()
    plan = files.plan_save(project, tmp_path / "out" / "t.xml", scratch, names)
    assert plan.ok, plan.problems
    files.commit_save(plan)
    assert (tmp_path / "out" / "texture.png").is_file()
    assert load_project(tmp_path / "out" / "t.xml") == project


def test_save_as_elsewhere_rebases_file_names(tmp_path):
    project, scratch, names = files.new_from_template("texture", tmp_path)
    first = tmp_path / "a" / "t.xml"
    files.commit_save(files.plan_save(project, first, scratch, names))
    plan = files.plan_save(project, tmp_path / "b" / "c" / "t.xml", first.parent)
    assert plan.ok, plan.problems
    assert plan.project.scene.texture.source.file == "../../a/texture.png"
    files.commit_save(plan)
    load_project(tmp_path / "b" / "c" / "t.xml")


def test_problems_point_at_panels():
    assert files.panel_for_problem("x.xml:3:5: <altitude-agl-m>: must be > 0") == "Flight"
    assert files.panel_for_problem("x.xml:3:5: <focal-length-mm>: must be > 0") == "Camera"
    assert files.panel_for_problem("x.xml:3:5: <target>: GCP 'A' …") == "GCPs"
    assert files.panel_for_problem("x.xml:3:5: <extent>: min-X …") == "Terrain"
    assert files.panel_for_problem("x.xml:9:5: <sun>: elevation-deg …") == "Lighting"


def test_blank_project_with_a_flight_is_valid(tmp_path):
    project = edits.ensure_flight_plan(files.blank_project())
    plan = files.plan_save(project, tmp_path / "p.xml", tmp_path)
    assert plan.ok, plan.problems
    assert dataclasses.replace(plan.project) == project


# ------------------------------------------------------------------- reconstruction
def test_reconstruct_job_commands_and_stages(tmp_path):
    from designer.cli.main import build_parser
    from designer.gui.state.reconstruct_job import (
        COMPARE_STAGE,
        STAGES,
        ReconstructJob,
        stage_of_line,
    )

    job = ReconstructJob(tmp_path / "s.xml", tmp_path / "out", "free", 2048)
    reconstruct, compare = job.commands()
    assert reconstruct[:3] == [sys.executable, "-m", "designer"]
    args = build_parser().parse_args(reconstruct[3:])  # the real command line parses
    assert (args.survey, args.output, args.mode, args.max_features) == (
        tmp_path / "out", tmp_path / "out" / "reconstruction-free", "free", 2048)
    assert args.project == tmp_path / "s.xml"  # its <processing> is the one used
    args = build_parser().parse_args(ReconstructJob(tmp_path / "s.xml",
                                                    tmp_path / "out").commands()[0][3:])
    assert args.max_features is None and args.project == tmp_path / "s.xml"
    args = build_parser().parse_args(compare[3:])
    assert args.cloud == job.out_dir / "cloud.ply" and args.reference == tmp_path / "s.xml"
    assert args.output == job.compare_dir and args.truth == tmp_path / "out"
    assert job.distances_ply == job.compare_dir / "distances.ply"
    # the log lines designer reconstruct prints, in order, give increasing stages
    lines = ["features: 12 images", "matching: 66 image pairs",
             "triangulating with the true poses", "12/12 images registered, 2000 points",
             "some other line"]
    assert [stage_of_line(t) for t in lines] == [0, 1, 2, 3, None]
    assert stage_of_line("incremental SfM") == 2
    assert COMPARE_STAGE == len(STAGES) - 1


def test_compared_cloud_is_read_back(tmp_path):
    from designer.evaluate import write_distances_ply
    from designer.gui.state.reconstruct_job import read_compared_cloud, survey_status
    from designer.gui.state.results_data import load_compared_cloud

    rng = np.random.default_rng(2)
    xyz = rng.normal(size=(50, 3)) + [512000.0, 5406000.0, 300.0]
    d = rng.normal(scale=0.01, size=50)
    d[3] = np.nan  # beyond a maximum distance: left out
    (tmp_path / "r" / "compare").mkdir(parents=True)
    path = write_distances_ply(tmp_path / "r" / "compare" / "distances.ply", xyz, d)
    got_xyz, got_d = read_compared_cloud(path)
    keep = np.isfinite(d)
    np.testing.assert_array_equal(got_xyz, xyz[keep])
    np.testing.assert_array_equal(got_d, d[keep])
    result = load_compared_cloud(path, "truth")
    assert result.name == "r/cloud.ply" and len(result.distances_m) == 49
    n, text = survey_status(tmp_path)
    assert n == 0 and "no ground truth" in text
