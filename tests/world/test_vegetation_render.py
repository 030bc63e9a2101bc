"""Vegetation on real Cycles renders: the masks are the rendered plants at each image's
time, plants stay off the GCP targets, the table lists every plant, and a project
without vegetation renders as before."""

from __future__ import annotations

from dataclasses import replace

import cv2
import numpy as np
import pytest

from designer.project import load_project
from designer.render.job import prepare_job
from designer.render.pipeline import render_project
from designer.render.provenance import job_provenance
from designer.render.vegetation_truth import read_plants_csv, vegetation_mask
from designer.scene.vegetation import place_vegetation
from tests.synthetic import write_project_file
from tests.world.moving_helpers import linear_rgb
from tests.world.vegetation_helpers import vegetation_project

TIMES_S = (0.0, 1.0)
NAMES = ("IMG_000.png", "IMG_001.png")


def _red(path) -> np.ndarray:
    """Pixels mostly covered by a red plant (linear red well above green and blue)."""
    c = linear_rgb(path)
    return c[:, :, 0] - np.maximum(c[:, :, 1], c[:, :, 2]) > 0.3


def _iou(a: np.ndarray, b: np.ndarray) -> float:
    return float((a & b).sum() / (a | b).sum())


@pytest.fixture(scope="module")
def renders(tmp_path_factory):
    folder = tmp_path_factory.mktemp("vegetation")
    p = vegetation_project(TIMES_S)
    path = write_project_file(p, folder / "veg")
    summary = render_project(path, folder / "veg" / "out")
    return p, path, folder / "veg" / "out", summary.prepared


def test_masks_are_the_rendered_plants_at_each_images_time(renders):
    p, path, out, prepared = renders
    masks = []
    for name in NAMES:
        mask = cv2.imread(str(out / "ground-truth" / "vegetation_masks" / name),
                          cv2.IMREAD_UNCHANGED)
        assert mask.dtype == np.uint8 and set(np.unique(mask)) == {0, 255}
        masks.append(mask > 0)
        seen = _red(out / "images" / name)
        assert 0.05 < seen.mean() < 0.8  # several shrubs in view
        assert _iou(seen, masks[-1]) > 0.9, (name, _iou(seen, masks[-1]))
    # the sway moved the plants between the images: each image matches its own time's
    # mask better than the other's
    seen1 = _red(out / "images" / NAMES[1])
    assert _iou(seen1, masks[1]) > _iou(seen1, masks[0]) + 0.03
    # the mask is the exported geometry projected with the exported camera
    plants = place_vegetation(p, path.parent, prepared.scene)
    again = vegetation_mask(plants, p.scene.vegetation.wind, TIMES_S[1], prepared.poses[1],
                            prepared.interior)
    assert np.array_equal(again > 0, masks[1])


def test_plants_stay_off_the_targets_and_the_table_lists_them(renders):
    p, path, out, prepared = renders
    rows = read_plants_csv(out / "ground-truth" / "vegetation.csv")
    plants = place_vegetation(p, path.parent, prepared.scene)
    assert len(rows) == sum(len(g) for g in plants) > 100
    assert [r["plant"] for r in rows] == list(range(1, len(rows) + 1))
    veg = p.scene.vegetation
    lean = np.sin(np.radians(veg.wind.amplitude_deg))
    for t in p.targets:
        d = np.array([np.hypot(r["E"] - t.true.X, r["N"] - t.true.Y) for r in rows])
        reach = np.array([r["crown_m"] / 2 + lean * r["height_m"] for r in rows])
        assert (d - reach >= t.size_m / np.sqrt(2) + veg.clearance_m - 1e-9).all()
    ext = p.scene.terrain.extent
    for r in rows:
        assert ext.min_X <= r["E"] - r["crown_m"] / 2 and r["E"] + r["crown_m"] / 2 <= ext.max_X
        assert r["H"] == pytest.approx(p.scene.terrain.source.height_m)  # on the ground
        assert r["kind"] == "shrub" and 0.2 <= r["height_m"] <= 3.0
    # the target in view (at the origin) is free of plants in every image
    target = next(t for t in prepared.scene.targets if t.target.id == "T00")
    for name, pose in zip(NAMES, prepared.poses, strict=True):
        from designer.core.projection import project_points

        uv = project_points(target.vertices_world, pose.C_world, pose.R_cam_to_world,
                            prepared.interior).uv_px[0]
        lo, hi = np.floor(uv.min(axis=0)).astype(int), np.ceil(uv.max(axis=0)).astype(int)
        mask = cv2.imread(str(out / "ground-truth" / "vegetation_masks" / name), 0)
        assert not mask[lo[1]:hi[1], lo[0]:hi[0]].any()


def test_changed_vegetation_invalidates_the_images(renders, tmp_path):
    p, path, _, prepared = renders
    base = job_provenance(prepared.job, prepared.job_path.parent)
    for changed in (replace(p.scene.vegetation, seed=6),
                    replace(p.scene.vegetation, wind=replace(p.scene.vegetation.wind,
                                                             amplitude_deg=10.0))):
        q = replace(p, scene=replace(p.scene, vegetation=changed))
        job = prepare_job(q, path.parent, tmp_path / f"j{changed.seed}")
        other = job_provenance(job.job, job.job_path.parent)
        for i in (0, 1):
            assert base[i].changed_parts(other[i].to_json()) == ["scene"]


def test_a_project_without_vegetation_has_no_plants_and_no_vegetation_truth(renders,
                                                                           tmp_path):
    p, _, _, _ = renders
    bare = replace(p, scene=replace(p.scene, vegetation=None))
    path = write_project_file(bare, tmp_path)
    assert load_project(path).scene.vegetation is None
    assert "vegetation" not in path.read_text()
    prepared = prepare_job(bare, tmp_path, tmp_path / "out")
    assert prepared.job.vegetation == () and prepared.job.wind is None
    assert not list((tmp_path / "out" / ".designer-job").glob("plants_*"))


def test_mesh_file_plants_are_rendered_where_their_masks_say(tmp_path):
    """A group of mesh plants (a square pyramid in the plant's frame, scaled to the group's
    height): rendered silhouettes match the masks."""
    (tmp_path / "bush.ply").write_text(
        "ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\nproperty float y\n"
        "property float z\nelement face 4\nproperty list uchar int vertex_indices\n"
        "end_header\n-1 -1 0\n1 -1 0\n1 1 0\n-1 1 0\n0 0 2\n"
        "3 0 1 4\n3 1 2 4\n3 2 3 4\n3 3 0 4\n")
    p = vegetation_project((0.0, 1.0), samples=8)
    group = replace(p.scene.vegetation.plants[0], kind=None, mesh="bush.ply", crown_m=None)
    p = replace(p, scene=replace(p.scene, vegetation=replace(p.scene.vegetation,
                                                             plants=(group,))))
    render_project(write_project_file(p, tmp_path), tmp_path / "out")
    rows = read_plants_csv(tmp_path / "out" / "ground-truth" / "vegetation.csv")
    assert rows and {r["kind"] for r in rows} == {"bush.ply"}
    # scaled to the group's height, the crown with it (the mesh is 2 m tall, 2.83 m wide)
    assert [r["crown_m"] / r["height_m"] for r in rows] == pytest.approx(
        [2 * np.sqrt(2) / 2] * len(rows))
    for name in NAMES:
        mask = cv2.imread(str(tmp_path / "out/ground-truth/vegetation_masks" / name), 0) > 0
        seen = _red(tmp_path / "out" / "images" / name)
        assert mask.mean() > 0.05 and _iou(seen, mask) > 0.9, _iou(seen, mask)
