"""Render provenance: each kind of change invalidates exactly the images it affects, and
an output folder can never silently hold images and ground truth of different projects."""

from __future__ import annotations

import json
from dataclasses import replace

import numpy as np
import pytest

from designer.core.projection import project_points
from designer.project import load_project
from designer.project import model as m
from designer.render.job import prepare_job
from designer.render.provenance import job_provenance
from tests.synthetic import small_survey, write_project_file


def base_project() -> m.Project:
    """Eight small images over the 40 m square, its nine targets 10 m apart."""
    return small_survey(n_photos=8, samples=2, size_px=(160, 120))


def _with_target(project: m.Project, target_id: str, **true) -> m.Project:
    targets = tuple(replace(t, true=replace(t.true, **true)) if t.id == target_id else t
                    for t in project.targets)
    return replace(project, scene=replace(project.scene,
                                          targets=replace(project.scene.targets,
                                                          targets=targets)))


def _with_photo(project: m.Project, k: int, **changes) -> m.Project:
    photos = list(project.trajectory.exterior_orientations)
    photos[k] = replace(photos[k], **changes)
    return replace(project, trajectory=replace(project.trajectory,
                                               exterior_orientations=tuple(photos)))


def _provenance(project: m.Project, folder):
    path = write_project_file(project, folder)
    prepared = prepare_job(load_project(path), path.parent, folder / "out")
    return prepared, job_provenance(prepared.job, prepared.job_path.parent)


def _seeing(prepared, xyz) -> set[int]:
    """Frames whose image contains the world point (projected with the true camera)."""
    C = np.array([p.C_world for p in prepared.poses])
    R = np.array([p.R_cam_to_world for p in prepared.poses])
    proj = project_points(np.array([xyz], float), C, R, prepared.interior)
    return set(np.flatnonzero(proj.in_image[:, 0]).tolist())


CHANGES = {
    "terrain": lambda p: replace(p, scene=replace(p.scene, terrain=replace(
        p.scene.terrain, source=replace(p.scene.terrain.source, max_height_m=0.8)))),
    "texture": lambda p: replace(p, scene=replace(p.scene, texture=replace(
        p.scene.texture, source=replace(p.scene.texture.source, seed=9)))),
    "sun": lambda p: replace(p, scene=replace(p.scene, lighting=m.Lighting(
        m.Sun(azimuth_deg=120.0, elevation_deg=40.0)))),
    "camera": lambda p: replace(p, cameras=(replace(p.cameras[0], focal_length_mm=5.2),)),
    "effect": lambda p: replace(p, effects=m.Effects(sensor_noise=m.SensorNoise(1.0, 1))),
    "render setting": lambda p: replace(p, render=replace(p.render, samples=3)),
}


@pytest.fixture(scope="module")
def base(tmp_path_factory):
    folder = tmp_path_factory.mktemp("base")
    return _provenance(base_project(), folder)


def _changed(base, other) -> set[int]:
    _, before = base
    return {i for i in before if before[i].digest != other[i].digest}


@pytest.mark.parametrize("kind", sorted(CHANGES))
def test_a_change_of_the_whole_scene_invalidates_every_image(base, tmp_path, kind):
    _, after = _provenance(CHANGES[kind](base_project()), tmp_path)
    assert _changed(base, after) == set(range(8))


def test_a_pose_change_invalidates_that_image_only(base, tmp_path):
    project = base_project()
    photo = project.trajectory.exterior_orientations[5]
    _, after = _provenance(_with_photo(project, 5, kappa_deg=photo.kappa_deg + 1.0), tmp_path)
    assert _changed(base, after) == {5}
    assert after[5].changed_parts(base[1][5].to_json()) == ["pose"]


def test_a_moved_gcp_invalidates_the_images_that_see_it(base, tmp_path):
    prepared, _ = base
    target = next(t for t in prepared.scene.targets if t.target.id == "T00")
    seeing = _seeing(prepared, target.true_xyz)
    assert 0 < len(seeing) < 8 or len(seeing) == 8
    _, after = _provenance(_with_target(base_project(), "T00", X=0.3), tmp_path)
    changed = _changed(base, after)
    assert seeing <= changed  # every image that shows it
    # and no image whose view (with the 25 % margin) is far from it
    C = np.array([p.C_world for p in prepared.poses])
    far = {i for i in range(8) if np.hypot(*(C[i, :2] - target.true_xyz[:2])) > 12.0}
    assert not changed & far


def test_a_gcp_no_image_sees_invalidates_nothing(base, tmp_path):
    prepared, _ = base
    corner = next(t for t in prepared.scene.targets if t.target.id == "T-1-1")
    assert _seeing(prepared, corner.true_xyz) == set()
    _, after = _provenance(_with_target(base_project(), "T-1-1", X=-10.4), tmp_path)
    assert _changed(base, after) == set()


def test_survey_error_changes_the_ground_truth_not_the_images(base, tmp_path):
    project = base_project()
    sigma = m.SurveyAccuracy(m.Sigma3(0.02, 0.02, 0.04), seed=7)
    targets = tuple(replace(t, surveyed=None) for t in project.targets)
    changed = replace(project, scene=replace(project.scene, targets=m.Targets(targets, sigma)))
    _, after = _provenance(changed, tmp_path)
    assert _changed(base, after) == set()


def test_the_manifest_records_each_image_and_the_ground_truth(tmp_path):
    """Without Blender: the manifest is written as images land (here by hand)."""
    from designer.render.manifest import Manifest
    from designer.render.pipeline import write_ground_truth
    from designer.render.runner import RenderReport

    project = base_project()
    path = write_project_file(project, tmp_path)
    prepared = prepare_job(load_project(path), path.parent, tmp_path / "out")
    provenance = job_provenance(prepared.job, prepared.job_path.parent)
    manifest = Manifest(tmp_path / "out", path, prepared, provenance, 0.1)
    write_ground_truth(project, prepared, tmp_path / "out")
    manifest.ground_truth_written()
    assert manifest.changed_parts(0) == ["unrecorded"]
    manifest.image_done(0, 1.5)
    data = json.loads((tmp_path / "out" / "manifest.json").read_text())
    assert data["images"]["IMG_000.png"]["inputs"]["digest"] == provenance[0].digest
    assert len(data["ground_truth"]["digest"]) == 32
    manifest.finish(RenderReport())
    again = Manifest(tmp_path / "out", path, prepared, provenance, 0.1)
    assert again.changed_parts(0) == [] and again.changed_parts(1) == ["unrecorded"]


@pytest.mark.blender
def test_resume_rerenders_what_changed_and_check_output_agrees(tmp_path):
    from designer.render.check_output import check_output
    from designer.render.pipeline import render_project

    project = small_survey(n_photos=4, samples=2, size_px=(96, 72))
    folder = tmp_path / "survey"
    path = write_project_file(project, folder)
    out = tmp_path / "out"
    render_project(path, out, workers=1)
    status = check_output(out)
    assert status.ok and len(status.up_to_date) == 4

    # the terrain changes and nobody renders: the folder says so, image by image
    write_project_file(CHANGES["terrain"](project), folder)
    status = check_output(out)
    assert not status.ok
    assert set(status.stale) == {f"IMG_{k:03d}.png" for k in range(4)}
    # the targets lie on the terrain, so they moved with it
    assert all(parts == ["terrain"] for parts in status.stale.values())
    assert status.ground_truth.startswith("out of date")

    # one pose changes too; --resume re-renders all four (terrain) and reports why
    summary = render_project(path, out, workers=1, resume=True)
    assert sorted(summary.report.rendered) == [0, 1, 2, 3] and summary.report.skipped == []
    assert check_output(out).ok

    photo = project.trajectory.exterior_orientations[2]
    write_project_file(_with_photo(CHANGES["terrain"](project), 2, X=photo.X + 0.5), folder)
    summary = render_project(path, out, workers=1, resume=True)
    assert sorted(summary.report.rendered) == [2] and sorted(summary.report.skipped) == [0, 1, 3]
    assert summary.stale == {2: ["pose"]}
    status = check_output(out)
    assert status.ok, status.summary()

    # a stray image in the folder and an edited ground-truth file are both reported
    (out / "images" / "IMG_999.png").write_bytes((out / "images" / "IMG_000.png").read_bytes())
    opk = out / "ground-truth" / "camera_poses_opk.csv"
    opk.write_text(opk.read_text().replace("IMG_000", "IMG_00X"))
    status = check_output(out)
    assert status.extra == ["IMG_999.png"]
    assert status.ground_truth == "edited after rendering"


def test_two_processes_rendering_slices_keep_each_others_records(tmp_path):
    """A job array renders frames 0-3 and 4-7 of one folder at once: both manifests'
    writers add their images; neither erases the other's."""
    from designer.render.manifest import Manifest

    path = write_project_file(base_project(), tmp_path)
    prepared = prepare_job(load_project(path), path.parent, tmp_path / "out")
    provenance = job_provenance(prepared.job, prepared.job_path.parent)
    a = Manifest(tmp_path / "out", path, prepared, provenance, 0.1)
    b = Manifest(tmp_path / "out", path, prepared, provenance, 0.1)
    for k in range(4):
        a.image_done(k, 1.0)
        b.image_done(4 + k, 1.0)
    data = json.loads((tmp_path / "out" / "manifest.json").read_text())
    assert sorted(data["images"]) == [f"IMG_{k:03d}.png" for k in range(8)]


@pytest.mark.blender
def test_out_of_date_reasons_name_exactly_what_changed(tmp_path):
    """Only the resolution scale changes: the images on disk are out of date by their
    size (never 'missing', never 'pose'); only the sun: by the lighting; one pose: that
    image by its pose."""
    from designer.render.check_output import check_output
    from designer.render.pipeline import render_project

    project = small_survey(n_photos=3, samples=1, size_px=(96, 72),
                           effects=m.Effects(sensor_noise=m.SensorNoise(1.0, 1)))
    folder = tmp_path / "survey"
    path = write_project_file(project, folder)
    out = tmp_path / "out"
    render_project(path, out, workers=1)
    names = [f"IMG_{k:03d}.png" for k in range(3)]

    halved = replace(project, render=replace(project.render, resolution_scale=0.5))
    write_project_file(halved, folder)
    status = check_output(out)
    assert status.missing == []
    assert status.stale == {n: ["image size 96 × 72 → 48 × 36"] for n in names}
    assert "3 out of date: 3 by image size 96 × 72 → 48 × 36" in status.summary()

    write_project_file(CHANGES["sun"](project), folder)
    status = check_output(out)
    assert status.missing == []
    assert status.stale == {n: ["lighting"] for n in names}
    assert "3 by the lighting" in status.summary()

    photo = project.trajectory.exterior_orientations[1]
    write_project_file(_with_photo(project, 1, X=photo.X + 0.5), folder)
    status = check_output(out)
    assert status.stale == {"IMG_001.png": ["pose"]}

    # --resume after the resolution change says the same as check-output
    write_project_file(halved, folder)
    summary = render_project(path, out, workers=1, resume=True)
    assert summary.stale == {k: ["image size 96 × 72 → 48 × 36"] for k in range(3)}
    assert check_output(out).ok
