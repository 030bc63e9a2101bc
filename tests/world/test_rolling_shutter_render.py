"""Rolling shutter on real Cycles renders: checker targets flown over at a known speed are
skewed exactly as the exported rolling-shutter projection predicts (docs/world.md,
"Rolling shutter")."""

from __future__ import annotations

import re

import cv2
import numpy as np
import pytest

from designer.core.projection import project_points
from designer.export.tables import read_gcp_observations_csv, read_gcp_truth_csv
from designer.render.pipeline import render_project
from tests.synthetic import write_project_file
from tests.world.rolling_helpers import READOUT_S, rolling_project

pytestmark = [pytest.mark.blender, pytest.mark.slow]

#: the bound of the issue: detected corners within 0.05 px of the exported projection
MAX_ERROR_PX = 0.05
#: samples per pixel of the renders
SAMPLES = 64


def detect_corners(image_gray: np.ndarray, uv_expected: np.ndarray, rng) -> np.ndarray:
    """Sub-pixel checker centres near ``uv_expected`` (designer pixel convention).

    The image is first blurred by a Gaussian of σ 1.5 px: a checker centre is point
    symmetric (also sheared by the readout), so the blur leaves it in place while it
    removes the sub-pixel phase bias cornerSubPix has on box-filtered edges (0.07 px at
    most without it, 0.02 px with it, on the same renders with a global shutter)."""
    gray = cv2.GaussianBlur(image_gray.astype(np.float32), (0, 0), 1.5)
    start = uv_expected - 0.5 + rng.uniform(-1.0, 1.0, uv_expected.shape)
    criteria = (cv2.TERM_CRITERIA_EPS + cv2.TERM_CRITERIA_COUNT, 200, 1e-5)
    refined = cv2.cornerSubPix(gray, start.astype(np.float32).reshape(-1, 1, 2), (7, 7),
                               (-1, -1), criteria)
    return refined.reshape(-1, 2) + 0.5


@pytest.fixture(scope="module", params=["top-to-bottom", "bottom-to-top"])
def rendered(request, tmp_path_factory):
    folder = tmp_path_factory.mktemp(f"rolling-{request.param}")
    path = write_project_file(rolling_project(direction=request.param, samples=SAMPLES),
                              folder)
    return request.param, render_project(path, folder / "out", workers=1)


def test_corners_lie_where_the_exported_rolling_shutter_projection_puts_them(rendered):
    direction, summary = rendered
    gt = summary.ground_truth
    obs = read_gcp_observations_csv(gt["gcp_observations"])
    truth = {g.gcp_id: g.true_xyz for g in read_gcp_truth_csv(gt["gcp_truth"])}
    poses = {p.image_name: p for p in summary.prepared.poses}
    interior = summary.prepared.interior
    rng = np.random.default_rng(0)
    errors, skews = [], []
    for image_name in sorted({o.image_name for o in obs}):
        rows = [o for o in obs if o.image_name == image_name]
        uv = np.array([o.uv_px for o in rows])
        gray = cv2.imread(str(summary.images_dir / image_name), cv2.IMREAD_GRAYSCALE)
        found = detect_corners(gray, uv, rng)
        errors.append(found - uv)
        pose = poses[image_name]
        points = np.array([truth[o.gcp_id] for o in rows])
        global_uv = project_points(points, pose.C_world, pose.R_cam_to_world,
                                   interior).uv_px[0]
        skews.append(found - global_uv)
    d, skew = np.concatenate(errors), np.concatenate(skews)
    print(f"{direction}: {len(d)} corners; error to the rolling-shutter projection: max "
          f"{np.abs(d).max():.4f} px, RMS {np.sqrt((d ** 2).mean()):.4f} px; to the global "
          f"projection: max {np.abs(skew).max():.2f} px")
    assert len(d) == 18
    assert np.abs(d).max() <= MAX_ERROR_PX
    # the global-shutter projection misses by the predicted skew (up to 8 px here)
    assert np.abs(skew).max() > 3.0


def test_every_export_carries_the_rolling_shutter_pixels(rendered):
    direction, summary = rendered
    gt = summary.ground_truth
    obs = {(o.gcp_id, o.image_name): np.array(o.uv_px)
           for o in read_gcp_observations_csv(gt["gcp_observations"])}
    odm = gt["odm_gcp_list"].read_text().splitlines()[1:]
    assert len(odm) == len(obs)
    for line in odm:
        *_, u, v, image_name, gcp_id = line.split()[:7]
        # ODM's pixel origin is the centre of the top-left pixel
        np.testing.assert_allclose(np.array([float(u), float(v)]) + 0.5,
                                   obs[(gcp_id, image_name)], atol=1e-9)
    xml = gt["metashape_markers_xml"].read_text()
    located = re.findall(r'<location [^>]*x="([-\d.e]+)" y="([-\d.e]+)"', xml)
    assert sorted(float(x) for x, _ in located) == pytest.approx(
        sorted(uv[0] for uv in obs.values()), abs=1e-9)
    table = gt["rolling_shutter"].read_text().splitlines()
    assert table[0].startswith("image,readout_s,direction,velocity_E_m_s,velocity_N_m_s")
    first = table[1].split(",")
    assert first[1:3] == [repr(READOUT_S), direction]
    # 10 m/s towards azimuth 60°
    assert [float(x) for x in first[3:6]] == pytest.approx([8.660254, 5.0, 0.0])


def test_a_changed_readout_makes_the_images_and_ground_truth_out_of_date(rendered):
    from designer.render.check_output import check_output

    _, summary = rendered
    assert "--rolling-shutter-readout 30" in (summary.out_dir / "README.txt").read_text()
    project_path = summary.out_dir.parent / "project.xml"
    assert check_output(summary.out_dir, project_path).ok
    text = project_path.read_text()
    changed = summary.out_dir.parent / "changed.xml"
    changed.write_text(text.replace(f'readout-s="{READOUT_S}"', 'readout-s="0.02"'))
    status = check_output(summary.out_dir, changed)
    assert sorted(status.stale) == ["IMG_000.png", "IMG_001.png"]
    assert all(parts == ["pose"] for parts in status.stale.values())
    assert status.ground_truth.startswith("out of date")


def test_moving_object_masks_follow_the_rolling_shutter(tmp_path):
    """A box on the ground under a camera flying north with a 50 ms readout: its mask is
    where the rows see it (each row from its own pose), not where the first row's pose
    would put it."""
    from dataclasses import replace

    from designer.core.truth import CameraPose
    from designer.project import model as m
    from designer.render.moving_truth import object_mask
    from tests.world.moving_helpers import box_coverage, moving_project

    p = moving_project()
    p = replace(p, cameras=(replace(p.cameras[0], rolling_shutter=m.RollingShutter(0.05)),))
    bare = replace(p, scene=replace(p.scene, moving_objects=()))
    out = render_project(write_project_file(p, tmp_path / "moving"), tmp_path / "moving/out")
    ground = render_project(write_project_file(bare, tmp_path / "bare"), tmp_path / "bare/out")
    prepared = out.prepared
    for k, name in enumerate(("IMG_000.png", "IMG_001.png")):
        mask = cv2.imread(str(out.out_dir / "ground-truth/masks" / name.replace(".png",
                                                                                "_mask.png")),
                          cv2.IMREAD_UNCHANGED) > 0
        covered = box_coverage(out.images_dir / name, ground.images_dir / name) >= 0.5
        iou = (covered & mask).sum() / (covered | mask).sum()
        pose: CameraPose = prepared.poses[k]
        first_row = object_mask(prepared.moving_poses[k], prepared.moving_meshes, pose,
                                prepared.interior) > 0
        iou_first_row = (covered & first_row).sum() / (covered | first_row).sum()
        print(f"{name}: mask IoU {iou:.3f}, first-row-pose mask IoU {iou_first_row:.3f}")
        assert iou >= 0.98
        assert iou_first_row < 0.95


def test_building_masks_follow_the_rolling_shutter(tmp_path):
    """Buildings under a camera flying east at 10 m/s with a 50 ms readout (5 px of skew
    at 10 cm/px): their masks are where the rows see them."""
    from dataclasses import replace

    from designer.project import model as m
    from designer.render.building_truth import building_mask
    from tests.world.building_helpers import building_project, changed_pixels

    def rolling(p):
        return replace(p, cameras=(replace(p.cameras[0],
                                           rolling_shutter=m.RollingShutter(0.05)),),
                       trajectory=replace(p.trajectory, time_line=m.TimeLine(
                           "2026-06-21T09:30:00Z", 10.0)))

    p = rolling(building_project())
    out = render_project(write_project_file(p, tmp_path / "with"), tmp_path / "with/out")
    render_project(write_project_file(rolling(building_project(with_buildings=False)),
                                      tmp_path / "bare"), tmp_path / "bare/out")
    prepared = out.prepared
    for k, name in enumerate(("IMG_000.png", "IMG_001.png")):
        mask = cv2.imread(str(out.out_dir / "ground-truth/building_masks" / name),
                          cv2.IMREAD_UNCHANGED) > 0
        changed = changed_pixels(out.out_dir, tmp_path / "bare/out", name)
        first_row = building_mask(prepared.buildings, prepared.poses[k],
                                  prepared.interior) > 0
        iou = (changed & mask).sum() / (changed | mask).sum()
        iou_first_row = (changed & first_row).sum() / (changed | first_row).sum()
        print(f"{name}: building mask IoU {iou:.3f}, first-row-pose mask {iou_first_row:.3f}")
        assert iou > 0.95
        assert iou_first_row < iou - 0.05
