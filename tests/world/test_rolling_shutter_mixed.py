"""A job whose images come from different cameras, some with a rolling shutter and some
without (docs/world.md, "Rolling shutter"): each image is rendered and its ground truth
written through its own camera's shutter; a rig's rolling-shutter mount moves with the
station's velocity."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from designer.core.projection import project_points
from designer.core.rolling_shutter import rolling_shutter_projection
from designer.export.tables import read_gcp_observations_csv, read_gcp_truth_csv
from designer.project import model as m
from designer.render.pipeline import render_project
from tests.synthetic import write_project_file
from tests.world.rolling_helpers import AZIMUTH_DEG, HEIGHT_M, READOUT_S, SPEED_M_S, rolling_project

pytestmark = [pytest.mark.blender]

#: IMG_000, IMG_001: the rolling-shutter camera alone; IMG_002, IMG_003: the rig, whose
#: mount _G is a global-shutter camera (half the image size) and _R the rolling one
ROLLING = ("IMG_000.png", "IMG_001.png", "IMG_002_R.png", "IMG_003_R.png")
GLOBAL = ("IMG_002_G.png", "IMG_003_G.png")


def mixed_project() -> m.Project:
    p = rolling_project(samples=4)
    cam = p.cameras[0]
    glob = replace(cam, id="glob", image_width_px=cam.image_width_px // 2,
                   image_height_px=cam.image_height_px // 2, rolling_shutter=None)
    rig = m.Rig("duo", (m.Mount("glob", "_G"), m.Mount("cam", "_R", kappa_deg=90.0)))
    E0, N0, H0 = p.origin.E0, p.origin.N0, p.origin.H0
    az = math.radians(AZIMUTH_DEG)
    # four stations 1 m apart along one straight leg: two of the camera, two of the rig
    photos = tuple(
        m.ExteriorOrientation(f"IMG_{k:03d}.png", "cam" if k < 2 else "duo",
                              E0 + (k - 1.5) * math.sin(az), N0 + (k - 1.5) * math.cos(az),
                              H0 + HEIGHT_M, 0.0, 0.0, 20.0)
        for k in range(4))
    return replace(p, cameras=(cam, glob),
                   trajectory=replace(p.trajectory, exterior_orientations=photos, rigs=(rig,)))


@pytest.fixture(scope="module")
def rendered(tmp_path_factory):
    folder = tmp_path_factory.mktemp("mixed")
    return render_project(write_project_file(mixed_project(), folder), folder / "out",
                          workers=1)


def test_each_image_is_rendered_with_its_own_cameras_shutter(rendered):
    frames = {f.image_name: f for f in rendered.prepared.job.frames}
    assert sorted(frames) == sorted(ROLLING + GLOBAL)
    for name in ROLLING:
        assert frames[name].shutter_matrices_local is not None
    for name in GLOBAL:
        assert frames[name].shutter_matrices_local is None
    for name in frames:
        assert (rendered.images_dir / name).is_file()


def test_gcp_pixels_follow_each_images_own_shutter(rendered):
    gt = rendered.ground_truth
    obs = read_gcp_observations_csv(gt["gcp_observations"])
    truth = {g.gcp_id: g.true_xyz for g in read_gcp_truth_csv(gt["gcp_truth"])}
    poses = {p.image_name: p for p in rendered.prepared.poses}
    az = math.radians(AZIMUTH_DEG)
    # one straight leg: every image, rig mounts too, moves 10 m/s towards azimuth 60°
    velocity = SPEED_M_S * np.array([math.sin(az), math.cos(az), 0.0])
    seen = {o.image_name for o in obs}
    assert seen == set(ROLLING + GLOBAL)
    skew: dict[str, float] = {}
    for o in obs:
        pose = poses[o.image_name]
        interior = rendered.prepared.interior_of(o.image_name)
        point = np.array([truth[o.gcp_id]])
        flat = project_points(point, pose.C_world, pose.R_cam_to_world, interior).uv_px[0, 0]
        if o.image_name in ROLLING:
            rs = rolling_shutter_projection(point, pose.C_world, pose.R_cam_to_world,
                                            velocity, READOUT_S, interior, "top-to-bottom")[0]
            np.testing.assert_allclose(o.uv_px, rs, atol=1e-6)
            skew[o.image_name] = max(skew.get(o.image_name, 0.0), np.abs(rs - flat).max())
        else:
            assert interior.image_size_px == (160, 120)
            np.testing.assert_allclose(o.uv_px, flat, atol=1e-9)
    # the rolling images are not where a global shutter puts them (rows read later skew)
    assert sorted(skew) == sorted(ROLLING) and min(skew.values()) > 2.0
    # every export carries the same pixels
    odm = gt["odm_gcp_list"].read_text().splitlines()[1:]
    by_key = {(o.gcp_id, o.image_name): np.array(o.uv_px) for o in obs}
    assert len(odm) == len(by_key)
    for line in odm:
        *_, u, v, image_name, gcp_id = line.split()[:7]
        np.testing.assert_allclose(np.array([float(u), float(v)]) + 0.5,
                                   by_key[(gcp_id, image_name)], atol=1e-9)


def test_the_rolling_shutter_table_lists_only_the_rolling_images_with_their_camera(rendered):
    table = rendered.ground_truth["rolling_shutter"].read_text().splitlines()
    assert table[0].split(",")[-1] == "camera"
    rows = [r.split(",") for r in table[1:]]
    assert [r[0] for r in rows] == list(ROLLING)
    assert all(r[-1] == "cam" for r in rows)
    assert all([float(x) for x in r[3:6]] == pytest.approx([8.660254, 5.0, 0.0])
               for r in rows)
