"""Moving objects on real Cycles renders: an object moves by speed × Δt between photos,
its mask is its rendered silhouette, the positions table is exact, a project without
moving objects is unchanged, and every bad value is a located one-line error."""

from __future__ import annotations

import re
from dataclasses import replace

import cv2
import numpy as np
import pytest

from designer.core.projection import project_points
from designer.project import load_project
from designer.project import model as m
from designer.render.job import prepare_job
from designer.render.moving_truth import read_positions_csv
from designer.render.pipeline import render_project
from designer.render.provenance import job_provenance
from designer.scene.moving import path_xy_heading
from designer.study.factors import FACTORS
from tests.synthetic import assert_located_error, write_project_file
from tests.world.helpers import ORIGIN
from tests.world.moving_helpers import BOX_SIZE_M, SPEED_M_S, box_coverage, moving_project

TIMES_S = (0.0, 2.0)


@pytest.fixture(scope="module")
def renders(tmp_path_factory):
    folder = tmp_path_factory.mktemp("moving")
    p = moving_project(TIMES_S)
    bare = replace(p, scene=replace(p.scene, moving_objects=()))
    render_project(write_project_file(p, folder / "moving"), folder / "moving" / "out")
    render_project(write_project_file(bare, folder / "bare"), folder / "bare" / "out")
    return p, folder / "moving" / "out", folder / "bare" / "out"


def test_the_object_moves_by_speed_times_elapsed_time_in_the_images(renders):
    p, out, bare = renders
    rows = read_positions_csv(out / "ground-truth" / "moving_objects.csv")
    assert [r["image"] for r in rows] == ["IMG_000.png", "IMG_001.png"]
    step = np.hypot(rows[1]["X"] - rows[0]["X"], rows[1]["Y"] - rows[0]["Y"])
    assert step == pytest.approx(SPEED_M_S * (TIMES_S[1] - TIMES_S[0]), abs=1e-6)
    assert rows[0]["X"] == pytest.approx(ORIGIN[0] - 2.5, abs=1e-6)
    assert rows[1]["heading_deg"] == pytest.approx(90.0)
    prepared = prepare_job(p, out.parent, out.parent / "scratch")
    poses, interior = prepared.poses, prepared.interior
    centroids, projected = [], []
    for k, row in enumerate(rows):
        c = box_coverage(out / "images" / row["image"], bare / "images" / row["image"])
        v, u = np.mgrid[:c.shape[0], :c.shape[1]] + 0.5
        centroids.append(np.array([(c * u).sum(), (c * v).sum()]) / c.sum())
        # the silhouette is the level top face: its centroid is its centre's projection
        top = np.array([[row["X"], row["Y"], row["Z"] + BOX_SIZE_M[2]]])
        projected.append(project_points(top, poses[k].C_world, poses[k].R_cam_to_world,
                                        interior).uv_px[0, 0])
    moved_px = centroids[1] - centroids[0]
    assert np.linalg.norm(moved_px) > 40  # 3 m at 6 cm/px
    assert np.linalg.norm(moved_px - (projected[1] - projected[0])) <= 0.1
    for seen, true in zip(centroids, projected, strict=True):
        assert np.linalg.norm(seen - true) <= 0.1


def test_masks_are_the_rendered_silhouettes(renders):
    _, out, bare = renders
    for name in ("IMG_000.png", "IMG_001.png"):
        mask = cv2.imread(str(out / "ground-truth" / "masks" / name.replace(".png", "_mask.png")),
                          cv2.IMREAD_UNCHANGED)
        assert mask.dtype == np.uint8 and set(np.unique(mask)) == {0, 255}
        covered = box_coverage(out / "images" / name, bare / "images" / name) >= 0.5
        inside = mask > 0
        iou = (covered & inside).sum() / (covered | inside).sum()
        assert iou >= 0.98, iou
        assert 0.9 < inside.sum() / (1 / 0.06) ** 2 < 1.1  # 1 m² at about 6 cm/px


def test_a_project_without_moving_objects_is_unchanged(renders, tmp_path):
    """An object that never enters the view changes no pixel; without moving objects
    there are no masks and no positions table."""
    p, _, bare = renders
    E0, N0, _ = ORIGIN
    far = replace(p.scene.moving_objects[0], path=(m.PathPoint(E0 + 15, N0 + 15),
                                                   m.PathPoint(E0 + 19, N0 + 15)))
    away = replace(p, scene=replace(p.scene, moving_objects=(far,)))
    render_project(write_project_file(away, tmp_path), tmp_path / "out")
    for name in ("IMG_000.png", "IMG_001.png"):
        assert (tmp_path / "out/images" / name).read_bytes() == \
            (bare / "images" / name).read_bytes()
        assert not (cv2.imread(str(tmp_path / "out/ground-truth/masks" /
                                   name.replace(".png", "_mask.png"))) > 0).any()
    assert not (bare / "ground-truth" / "masks").exists()
    assert not (bare / "ground-truth" / "moving_objects.csv").exists()
    job = (bare / ".designer-job" / "job.json").read_text()
    assert '"moving_poses": null' in job


def test_resume_renders_again_exactly_the_images_where_an_object_moved(tmp_path):
    """Image 0 is taken before the object starts: a new speed changes only image 1."""
    p = moving_project(TIMES_S)
    p = replace(p, scene=replace(p.scene, moving_objects=(
        replace(p.scene.moving_objects[0], start_s=1.0),)))
    faster = FACTORS["moving-object-speed-m-s"].set(p, 3.0)
    assert FACTORS["moving-object-speed-m-s"].get(faster) == 3.0
    a = prepare_job(p, tmp_path, tmp_path / "a")
    b = prepare_job(faster, tmp_path, tmp_path / "b")
    pa = job_provenance(a.job, a.job_path.parent)
    pb = job_provenance(b.job, b.job_path.parent)
    assert pa[0].digest == pb[0].digest
    assert pa[1].changed_parts(pb[1].to_json()) == ["pose"]


def test_poses_wait_at_the_ends_or_loop():
    E0, N0 = 0.0, 0.0
    obj = m.MovingObject("p", (m.PathPoint(E0, N0), m.PathPoint(E0, N0 + 10),
                               m.PathPoint(E0 + 10, N0 + 10)), 2.0, shape="person",
                         start_s=5.0)
    assert path_xy_heading(obj, 0.0) == (0.0, 0.0, 0.0)      # waits at the start
    assert path_xy_heading(obj, 7.5) == (0.0, 5.0, 0.0)      # north
    assert path_xy_heading(obj, 12.5) == pytest.approx((5.0, 10.0, 90.0))  # then east
    assert path_xy_heading(obj, 99.0) == pytest.approx((10.0, 10.0, 90.0))  # stays
    ring = replace(obj, loop=True)  # 10 + 10 + 14.14 m round
    assert path_xy_heading(ring, 5.0 + (20 + 200 ** 0.5 + 3) / 2.0) == pytest.approx(
        (0.0, 3.0, 0.0))
    assert path_xy_heading(ring, 5.0 + 25 / 2.0)[2] == pytest.approx(225.0)


@pytest.mark.parametrize(("edit", "needle", "words"), [
    (lambda t: t.replace('speed-m-s="1.5"', 'speed-m-s="0"'), "<path", "speed-m-s"),
    (lambda t: t.replace('speed-m-s="1.5"', 'speed-m-s="-2"'), "<path", "speed-m-s"),
    (lambda t: re.sub(r'(<point [^>]*/>)\s*<point [^>]*/>', r"\1", t), "<path", "two"),
    (lambda t: t.replace('shape="box"', 'shape="bus"'), 'shape="bus"', "unknown shape"),
    (lambda t: t.replace(' length-m="1.0"', ""), "shape=", "a length, a width"),
    (lambda t: t.replace('shape="box"', 'file="no_such_car.ply"'), "no_such_car", "no_such_car"),
    (lambda t: t.replace('albedo-rgb="0.9 0.02 0.02"', 'albedo-rgb="red"'), "albedo",
     "albedo-rgb"),
    (lambda t: t.replace('start-s', 'x').replace('<path ', '<path start-s="-1" '), "<path",
     "start-s"),
    (lambda t: re.sub(r"<time-line[^>]*/>", "", t).replace(' time-s="2.0"', "").replace(
        ' time-s="0.0"', ""), 'shape="box"', "time line"),
])
def test_bad_moving_object_values_are_located_one_line_errors(tmp_path, edit, needle, words):
    assert_located_error(moving_project(TIMES_S), tmp_path, edit, needle, words)


def test_moving_objects_survive_a_round_trip_through_the_file(tmp_path):
    p = moving_project(TIMES_S)
    E0, N0, _ = ORIGIN  # a path on the terrain
    car = m.MovingObject("car", (m.PathPoint(E0 + 1.0, N0 + 2.0),
                                 m.PathPoint(E0 + 3.0, N0 + 4.5)), 8.0,
                         start_s=2.5, loop=True)
    p = replace(p, scene=replace(p.scene, moving_objects=(*p.scene.moving_objects, car)))
    back = load_project(write_project_file(p, tmp_path))
    assert back.scene.moving_objects == p.scene.moving_objects


def test_compare_uses_the_static_ground_unless_given_a_time(tmp_path, capsys):
    from designer.cli.main import main as cli_main
    from designer.evaluate.compare import reference_mesh

    p = moving_project(TIMES_S)
    path = write_project_file(p, tmp_path / "moving")
    bare = write_project_file(replace(p, scene=replace(p.scene, moving_objects=())),
                              tmp_path / "bare")
    static = reference_mesh(path)
    assert np.array_equal(static.vertices, reference_mesh(bare).vertices)
    posed = reference_mesh(path, at_time_s=2.0)
    box = posed.vertices[len(static.vertices):]
    assert len(box) == 8 and posed.faces.max() == len(posed.vertices) - 1
    E0, N0, H0 = ORIGIN
    assert box.mean(axis=0) == pytest.approx((E0 - 2.5 + 3.0, N0 + 0.5,
                                              H0 + 0.25 + BOX_SIZE_M[2] / 2))
    cloud = tmp_path / "cloud.ply"
    cloud.write_text("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n"
                     "property float y\nproperty float z\nend_header\n0 0 0\n")
    assert cli_main(["compare", str(cloud), str(tmp_path / "cloud.ply"), "-o",
                     str(tmp_path / "o"), "--at-time", "2"]) == 2
    assert "--at-time 2.0: needs a project XML" in capsys.readouterr().err


def test_a_mesh_file_object_is_placed_by_its_pose(tmp_path):
    """A mesh in the object's frame (+Y forward) heading east lies along +X."""
    from designer.evaluate.compare import reference_mesh

    (tmp_path / "plate.ply").write_text(
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
        "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
        "end_header\n0 0 0\n0 2 0\n0.5 0 0\n3 0 1 2\n")
    p = moving_project(TIMES_S)
    plate = replace(p.scene.moving_objects[0], shape=None, file="plate.ply", size_m=None)
    path = write_project_file(replace(p, scene=replace(p.scene, moving_objects=(plate,))),
                              tmp_path)
    static = reference_mesh(path)
    posed = reference_mesh(path, at_time_s=2.0).vertices[len(static.vertices):]
    E0, N0, H0 = ORIGIN
    x, y = E0 - 2.5 + SPEED_M_S * 2.0, N0 + 0.5
    np.testing.assert_allclose(posed, [[x, y, H0 + 0.25], [x + 2, y, H0 + 0.25],
                                       [x, y - 0.5, H0 + 0.25]], atol=1e-9)
