"""The COLMAP ground truth through COLMAP's own command line (Debian's colmap 3.8).

A small real render is exported, then, with no hand editing: ``feature_extractor``
(the exported camera, one camera for all images), ``exhaustive_matcher``,
``point_triangulator`` with the exported model as ``--input_path`` (poses and camera
held fixed) and ``image_undistorter``. Checked: the database's image ids equal the
model's (COLMAP 3.8's point_triangulator pairs them by id and stops on a name mismatch;
feature_extractor with one thread numbers images in sorted-name order), every image
keeps its true pose, points are triangulated with sub-pixel reprojection error, and
the undistorted model — also in float32, as COLMAP's dense workspace holds
it — keeps every camera centre within 1 mm of the truth.

``make test`` installs colmap (scripts/install-system-packages.sh); without it the
tests are skipped with that reason.
"""

from __future__ import annotations

import dataclasses
import os
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest

from designer.core.truth import CameraPose
from designer.export import write_all
from designer.export.colmap_read import model_offset_world
from designer.export.tables import read_opk_csv
from designer.project import model as m
from designer.render.pipeline import render_project
from tests.synthetic import small_flight_survey, write_project_file

pytestmark = [
    pytest.mark.blender, pytest.mark.slow,
    pytest.mark.skipif(shutil.which("colmap") is None,
                       reason="the colmap command line is not installed (Debian package "
                              "colmap; 'make setup' installs it)"),
]
pycolmap = pytest.importorskip("pycolmap", reason="pycolmap reads COLMAP's results")

#: COLMAP quiet: warnings and errors only
ENV = {**os.environ, "GLOG_minloglevel": "1", "GLOG_logtostderr": "1",
       "QT_QPA_PLATFORM": "offscreen"}


def colmap(*args: str, expect: Path | None = None) -> str:
    """Run ``colmap ARGS``; fail with its output unless it exits 0 and (COLMAP 3.8 can
    exit 0 after a failure) ``expect`` exists afterwards."""
    run = subprocess.run(["colmap", *args], capture_output=True, text=True, env=ENV,
                         timeout=900)
    output = (run.stdout + run.stderr)[-3000:]
    assert run.returncode == 0, f"colmap {args[0]} exited {run.returncode}:\n{output}"
    assert expect is None or expect.exists(), f"colmap {args[0]} wrote no {expect}:\n{output}"
    return output


@pytest.fixture(scope="module")
def rendered(tmp_path_factory):
    """A dozen 640 × 480 draft renders of the SfM test flight (UTM-sized coordinates)."""
    folder = tmp_path_factory.mktemp("colmap-cli")
    project = small_flight_survey(samples=4)
    project = dataclasses.replace(project, outputs=m.Outputs("output", ("colmap", "opk", "gcp")))
    summary = render_project(write_project_file(project, folder), folder / "out", workers=2)
    return folder / "out", summary


def image_folder(out: Path, tmp: Path, rename=None) -> Path:
    """A folder holding only the survey's images (``rename``: old name → new name)."""
    if rename is None and (out / "images").is_dir():
        return out / "images"
    folder = tmp / "images"
    folder.mkdir()
    source = out / "images" if (out / "images").is_dir() else out
    for image in sorted(source.glob("*.png")):
        name = rename[image.name] if rename else image.name
        shutil.copy(image, folder / name)
    return folder


def true_poses(out: Path) -> dict[str, CameraPose]:
    return {p.image_name: p for p in read_opk_csv(out / "ground-truth" / "camera_poses_opk.csv")}


def run_colmap(model: Path, images: Path, work: Path):
    """The four COLMAP stages on ``model``; (triangulated model, undistorted model)."""
    camera_line = next(ln for ln in (model / "cameras.txt").read_text().splitlines()
                       if ln and not ln.startswith("#"))
    _cid, camera_model, _w, _h, *params = camera_line.split()
    db = work / "database.db"
    colmap("feature_extractor", "--database_path", str(db), "--image_path", str(images),
           "--ImageReader.single_camera", "1", "--ImageReader.camera_model", camera_model,
           "--ImageReader.camera_params", ",".join(params),
           "--SiftExtraction.use_gpu", "0", "--SiftExtraction.num_threads", "1", expect=db)
    # one extraction thread: COLMAP 3.8 numbers images as its threads finish them, which
    # with one thread is its sorted-name reading order — the order the export assumes
    import sqlite3

    with sqlite3.connect(db) as con:
        in_db = dict(con.execute("SELECT name, image_id FROM images"))
    in_model = {img.name: img_id for img_id, img in pycolmap.Reconstruction(str(model))
                .images.items()}
    assert in_db == in_model
    colmap("exhaustive_matcher", "--database_path", str(db), "--SiftMatching.use_gpu", "0",
           "--SiftMatching.num_threads", "2")
    tri = work / "triangulated"
    tri.mkdir()
    colmap("point_triangulator", "--database_path", str(db), "--image_path", str(images),
           "--input_path", str(model), "--output_path", str(tri),
           "--Mapper.ba_refine_focal_length", "0", "--Mapper.ba_refine_principal_point", "0",
           "--Mapper.ba_refine_extra_params", "0", "--Mapper.num_threads", "2",
           expect=tri / "images.bin")
    dense = work / "dense"
    colmap("image_undistorter", "--image_path", str(images), "--input_path", str(tri),
           "--output_path", str(dense), "--output_type", "COLMAP",
           expect=dense / "sparse" / "images.bin")
    return pycolmap.Reconstruction(str(tri)), pycolmap.Reconstruction(str(dense / "sparse"))


def check_results(tri, undistorted, truth: dict[str, CameraPose], offset: np.ndarray) -> None:
    # every image kept its true pose (the model is local: offset.json's offset added back)
    assert tri.num_reg_images() == len(truth)
    for image in tri.images.values():
        true = truth[image.name]
        C = image.projection_center() + offset
        assert np.abs(C - true.C_world).max() < 1e-6, image.name
        # R_colmap = diag(1, -1, -1) · R_cam_to_worldᵀ (docs/conventions)
        R_photo = (np.diag([1.0, -1.0, -1.0]) @ image.cam_from_world().rotation.matrix()).T
        assert np.abs(R_photo - true.R_cam_to_world).max() < 1e-9, image.name
    # points were triangulated with those poses, and they fit the images
    assert tri.num_points3D() > 500
    assert tri.compute_mean_reprojection_error() < 1.0
    # the dense stage's model: camera centres within 1 mm, also in float32 as COLMAP's
    # patch-match workspace (mvs::Model) holds R and t
    worst64 = worst32 = 0.0
    for image in undistorted.images.values():
        true = truth[image.name].C_world
        worst64 = max(worst64, np.abs(image.projection_center() + offset - true).max())
        R32 = image.cam_from_world().rotation.matrix().astype(np.float32)
        t32 = image.cam_from_world().translation.astype(np.float32)
        C32 = -(R32.T @ t32)
        worst32 = max(worst32, np.abs(C32.astype(np.float64) + offset - true).max())
    assert worst64 < 1e-3 and worst32 < 1e-3, (worst64, worst32)


def test_colmap_triangulates_and_undistorts_the_rendered_ground_truth(rendered, tmp_path):
    out, _summary = rendered
    model = out / "ground-truth" / "colmap"
    offset = model_offset_world(model)
    assert np.abs(offset).max() > 1e5  # a UTM-sized site, written as a local model
    pycolmap.Reconstruction(str(model))  # pycolmap reads the exported model
    tri, undistorted = run_colmap(model, image_folder(out, tmp_path), tmp_path)
    check_results(tri, undistorted, true_poses(out), offset)


def test_colmap_pairs_images_by_name_order_when_it_differs_from_the_flight(rendered, tmp_path):
    """Names in reverse flight order: COLMAP's database numbers them by sorted name, so
    the exported IMAGE_IDs must follow the names for point_triangulator to pair them."""
    out, summary = rendered
    truth = true_poses(out)
    flight = list(truth)  # flight order
    rename = {name: f"IMG_{len(flight) - 1 - k:05d}.png" for k, name in enumerate(flight)}
    assert sorted(rename.values()) != [rename[n] for n in flight]
    poses = [CameraPose(rename[n], truth[n].C_world, truth[n].R_cam_to_world) for n in flight]
    export = tmp_path / "export"
    paths = write_all(export, summary.prepared.interior, poses, [], [], "EPSG:32632",
                      formats=("colmap",))
    images = image_folder(out, tmp_path, rename)
    tri, undistorted = run_colmap(paths["colmap"], images, tmp_path)
    check_results(tri, undistorted, {p.image_name: p for p in poses},
                  model_offset_world(paths["colmap"]))


def test_the_offset_is_recorded_and_check_output_uses_the_choice(rendered, tmp_path):
    """The manifest names the offset; a folder rendered with --colmap-offset none is up
    to date for check-output (which rewrites the ground truth with the recorded choice)."""
    import json

    from designer.render.check_output import check_output

    out, _summary = rendered
    manifest = json.loads((out / "manifest.json").read_text())["ground_truth"]
    assert manifest["colmap_offset"] == "local"
    assert manifest["colmap_offset_world_m"] == \
        model_offset_world(out / "ground-truth" / "colmap").tolist()
    copy = tmp_path / "out"
    shutil.copytree(out, copy)
    project = Path(json.loads((out / "manifest.json").read_text())["project"])
    summary = render_project(project, copy, workers=1, resume=True, colmap_offset="none")
    assert not summary.report.rendered  # the images were kept, the ground truth rewritten
    assert model_offset_world(copy / "ground-truth" / "colmap").tolist() == [0.0, 0.0, 0.0]
    assert json.loads((copy / "manifest.json").read_text())["ground_truth"][
        "colmap_offset"] == "none"
    status = check_output(copy)
    assert status.ground_truth == "up to date" and not status.stale and not status.missing
