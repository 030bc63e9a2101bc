"""Buildings on real Cycles renders: the building masks are the rendered buildings, a
roof corner projected with the exported COLMAP camera lands on the rendered corner, a
target behind a building is not observed, the DSM holds the roofs and the DTM does not,
changed buildings re-render the images, and a project without buildings is unchanged."""

from __future__ import annotations

import json
from dataclasses import replace
from pathlib import Path

import cv2
import numpy as np
import pytest

from designer.export.colmap_read import camera_poses, model_offset_world, read_cameras, read_images
from designer.project import model as m
from designer.render.job import prepare_job
from designer.render.pipeline import render_project
from designer.render.provenance import job_provenance
from designer.scene.buildings import roof_height_m
from designer.study.factors import FACTORS
from tests.synthetic import write_project_file
from tests.world.building_helpers import HIDDEN, building_project, changed_pixels, rectangle
from tests.world.helpers import ORIGIN

IMAGES = ("IMG_000.png", "IMG_001.png")


@pytest.fixture(scope="module")
def renders(tmp_path_factory):
    folder = tmp_path_factory.mktemp("buildings")
    p = building_project()
    bare = building_project(with_buildings=False)
    render_project(write_project_file(p, folder / "with"), folder / "with" / "out")
    render_project(write_project_file(bare, folder / "bare"), folder / "bare" / "out")
    return p, folder / "with" / "out", folder / "bare" / "out"


def test_building_masks_are_the_rendered_buildings(renders):
    _, out, bare = renders
    for name in IMAGES:
        mask = cv2.imread(str(out / "ground-truth/building_masks" / name), cv2.IMREAD_UNCHANGED)
        assert mask.dtype == np.uint8 and set(np.unique(mask)) == {0, 255}
        changed, inside = changed_pixels(out, bare, name), mask > 0
        iou = (changed & inside).sum() / (changed | inside).sum()
        assert iou > 0.95, (name, iou)
        assert inside.sum() > 1000


def _read_ply_buildings(path: Path):
    from plyfile import PlyData

    ply = PlyData.read(str(path))
    v = np.column_stack([ply["vertex"][k] for k in "xyz"]).astype(float)
    faces = np.vstack(ply["face"]["vertex_indices"])
    owner = np.asarray(ply["face"]["building"])
    names = [c.split()[2] for c in ply.comments if c.startswith("building ")]
    return v, faces, owner, names


def test_a_roof_corner_lands_where_the_exported_camera_projects_it(renders):
    """The tower's roof corners away from the camera are corners of its silhouette (the
    pixels the buildings change): its corners are where the exported COLMAP camera
    projects them (world coordinates: the model's offset added back)."""
    _, out, bare = renders
    v, faces, owner, names = _read_ply_buildings(out / "ground-truth/buildings.ply")
    tower = v[np.unique(faces[owner == names.index("tower")])]
    top = tower[tower[:, 2] > tower[:, 2].max() - 1e-9]
    corners = top[top[:, 0] > top[:, 0].mean()]  # the two east corners (x = 5.5 m)
    model = out / "ground-truth/colmap"
    (camera,) = read_cameras(model).values()
    fx, fy, cx, cy = camera.params[:4]
    images = read_images(model)
    (pose,) = [p for p in camera_poses(images, model_offset_world(model))
               if p.image_name == IMAGES[0]]
    x = (corners - pose.C_world) @ pose.R_cam_to_world * [1, -1, -1]  # CV frame
    uv = np.column_stack([fx * x[:, 0] / x[:, 2] + cx, fy * x[:, 1] / x[:, 2] + cy])
    changed = changed_pixels(out, bare, IMAGES[0]).astype(np.uint8)
    contours, _ = cv2.findContours(changed, cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_NONE)
    outline = max(contours, key=lambda c: cv2.pointPolygonTest(c, tuple(map(float, uv[0])), True))
    # the silhouette's corner pixels; a binary silhouette puts each edge within half a
    # pixel of the boundary of its last covered pixel, so the true corner lies within
    # 0.5 px (along each axis) of a corner of a corner pixel
    pixels = cv2.approxPolyDP(outline, 1.0, True)[:, 0]
    pixel_corners = (pixels[:, None, :] + np.array([[0, 0], [1, 0], [0, 1], [1, 1]])).reshape(-1, 2)
    for corner in uv:
        gap = np.abs(pixel_corners - corner).max(axis=1).min()
        assert gap <= 0.5, (corner, pixels)
    # the corner is 15 m up: the base's projection is far from it (the test can fail)
    assert np.linalg.norm(uv[0] - uv[1]) > 15


def test_a_target_behind_a_building_is_not_observed(renders):
    _, out, bare = renders

    def observed(folder):
        text = (folder / "ground-truth/gcp_observations.csv").read_text().splitlines()
        return {tuple(line.split(",")[:2]) for line in text if not line.startswith("#")}

    assert (HIDDEN, IMAGES[0]) in observed(bare)
    assert (HIDDEN, IMAGES[0]) not in observed(out)
    assert {(HIDDEN, IMAGES[1]), ("G_open", IMAGES[0])} <= observed(out)


def test_compare_finds_the_roof_on_the_dsm_and_not_on_the_dtm(renders, tmp_path, capsys):
    from designer.cli.main import main
    from tests.evaluate.helpers import write_cloud

    p, out, _ = renders
    prepared = prepare_job(p, out.parent, tmp_path / "scratch")
    (gable,) = [b for b in prepared.buildings if b.id == "gable"]
    building = p.scene.buildings[1]
    rng = np.random.default_rng(5)
    E0, N0, _ = ORIGIN
    x, y = E0 + rng.uniform(-3.8, 1.8, 300), N0 + rng.uniform(-4.3, -1.7, 300)
    z = roof_height_m(building, gable.base_z_m, x, y)
    write_cloud(tmp_path / "roof.ply", np.column_stack([x, y, z]))
    medians = {}
    for surface in ("dtm", "dsm"):
        folder = tmp_path / surface
        assert main(["compare", str(tmp_path / "roof.ply"), str(out.parent / "project.xml"),
                     "-o", str(folder), "--no-targets", "--surface", surface]) == 0
        capsys.readouterr()
        medians[surface] = json.loads((folder / "summary.json").read_text())["distances"]["median"]
    assert medians["dsm"] == pytest.approx(0.0, abs=1e-6)
    # 3 to 5 m above the base; the bare earth lies within 0.5 m of it
    assert 3.0 < medians["dtm"] < 5.5


def test_changed_buildings_render_every_image_again(renders, tmp_path):
    p, out, _ = renders
    taller = FACTORS["building-eave-height-m"].set(p, 17.0)
    assert FACTORS["building-eave-height-m"].get(taller) == 17.0
    jobs = []
    for k, project in enumerate((p, taller)):
        prepared = prepare_job(project, out.parent, tmp_path / str(k))
        jobs.append(job_provenance(prepared.job, prepared.job_path.parent))
    for i in range(len(IMAGES)):
        assert jobs[0][i].changed_parts(jobs[1][i].parts) == ["scene"]


def test_a_project_without_buildings_in_view_renders_the_same_bytes(renders, tmp_path):
    """A building outside every view changes no pixel (the buildings are only added to
    the scene); without buildings there is no building ground truth."""
    p, _, bare = renders
    far = replace(p, scene=replace(p.scene, buildings=(
        m.Building("far", rectangle(15.0, 15.0, 18.0, 18.0), "flat", 3.0),)))
    render_project(write_project_file(far, tmp_path), tmp_path / "out")
    for name in IMAGES:
        assert (tmp_path / "out/images" / name).read_bytes() == \
            (bare / "images" / name).read_bytes()
    assert not (bare / "ground-truth/building_masks").exists()
    assert not (bare / "ground-truth/buildings.ply").exists()
    job = json.loads((bare / ".designer-job/job.json").read_text())
    assert "buildings" not in {o["name"] for o in job["objects"]}


def test_with_a_sun_over_time_each_photo_lights_the_buildings_with_its_own_sun(tmp_path):
    from designer.scene.lighting import irradiance, sun_direction_world
    from tests.world.helpers import TAKEOFF

    p = building_project()
    photos = tuple(replace(e, time_s=t) for e, t in
                   zip(p.trajectory.exterior_orientations, (0.0, 7200.0), strict=True))
    p = replace(p, trajectory=m.Trajectory(photos, None, m.TimeLine(TAKEOFF, 5.0, 8.0)),
                scene=replace(p.scene, lighting=m.Lighting(m.SunOverTime())))
    summary = render_project(write_project_file(p, tmp_path), tmp_path / "out")
    assert sorted(summary.report.rendered) == [0, 1]
    job = summary.prepared.job
    assert [f.light_step for f in job.frames] == [0, 1]
    lights = []
    for step in job.light_steps:
        (spec,) = [o for o in step.objects if o.name == "buildings"]
        sun = sun_direction_world(step.sun_azimuth_deg, step.sun_elevation_deg)
        east_wall = irradiance(np.array([[1.0, 0.0, 0.0]]), np.ones(1), sun,
                               p.scene.lighting.sun_strength, p.scene.lighting.sky_strength)[0]
        strengths = [mat.strength for mat in spec.materials]
        assert min(abs(s - east_wall) for s in strengths) < 1e-9
        assert min(abs(s - 1.0) for s in strengths) < 1e-12  # the level roofs
        lights.append(east_wall)
    assert abs(lights[0] - lights[1]) > 0.1  # the morning sun moved
