import json

import cv2
import numpy as np
import pytest

from designer.core.rotation import R_CV_FROM_PHOTO, opk_from_rotation, rotation_from_opk
from designer.core.truth import CameraPose
from designer.errors import DesignerError
from designer.evaluate import camera_pose_errors, read_camera_poses, similarity_transform
from designer.export.colmap import write_colmap_text_model
from designer.export.tables import write_opk_csv
from tests.synthetic import ORIGIN_WORLD, grid_poses, mapping_camera


def transformed(poses, s, R, t, noise=None):
    out = []
    for i, p in enumerate(poses):
        C = s * R @ p.C_world + t + (0 if noise is None else noise[i])
        out.append(CameraPose(p.image_name, C, R @ p.R_cam_to_world))
    return out


def test_similarity_is_recovered_at_utm_size():
    rng = np.random.default_rng(0)
    src = ORIGIN_WORLD + rng.normal(0, 50, (20, 3))
    R = rotation_from_opk(0.1, -0.2, 0.3)
    s, t = 1.0003, np.array([12.0, -7.0, 3.0])
    dst = s * src @ R.T + t
    s2, R2, t2 = similarity_transform(src, dst)
    assert abs(s2 - s) < 1e-11 and np.abs(R2 - R).max() < 1e-10  # 1e-9 m at 50 m
    assert np.abs(s2 * src @ R2.T + t2 - dst).max() < 1e-8
    with pytest.raises(DesignerError, match="on a line"):
        similarity_transform(np.outer(np.arange(5.0), [1, 2, 3]), np.outer(np.arange(5.0),
                                                                           [1, 2, 3]))


def test_pose_errors_after_alignment():
    truth = grid_poses()
    R = rotation_from_opk(0.02, 0.01, -0.5)
    moved = transformed(truth, 0.98, R, np.array([5.0, -3.0, 1.0]))
    r = camera_pose_errors(moved, truth)
    assert r["summary"]["rmse_XYZ"] < 1e-8 and r["summary"]["rotation_max_deg"] < 1e-8
    assert r["alignment"]["scale"] == pytest.approx(1 / 0.98)
    raw = camera_pose_errors(moved, truth, align=False)
    assert raw["summary"]["rmse_XYZ"] > 1.0 and raw["summary"]["rotation_max_deg"] > 28
    # a known position error and a known rotation error, no alignment
    est = [CameraPose(p.image_name, p.C_world + [0.03, -0.04, 0.0],
                      p.R_cam_to_world @ rotation_from_opk(0, 0, np.radians(0.5)))
           for p in truth[:-2]]
    r = camera_pose_errors(est, truth, align=False)
    assert r["summary"]["rmse_XY"] == pytest.approx(0.05)
    assert r["summary"]["rotation_rmse_deg"] == pytest.approx(0.5)
    assert r["not_registered"] == [p.image_name for p in truth[-2:]]
    with pytest.raises(DesignerError, match="matches"):
        camera_pose_errors([CameraPose("other.jpg", [0, 0, 0], np.eye(3))], truth)


def same_poses(a, b, tol=1e-6):
    assert [p.image_name for p in a] == [p.image_name for p in b]
    for p, q in zip(a, b, strict=True):
        assert np.abs(p.C_world - q.C_world).max() < tol
        assert np.abs(p.R_cam_to_world - q.R_cam_to_world).max() < 1e-9


def test_readers_colmap_opk_metashape_odm(tmp_path):
    truth = grid_poses()
    write_colmap_text_model(tmp_path / "colmap", mapping_camera(), truth,
                            offset_world=ORIGIN_WORLD)
    same_poses(read_camera_poses(tmp_path / "colmap", offset_world=ORIGIN_WORLD), truth)
    write_opk_csv(tmp_path / "opk.csv", truth, "EPSG:32632")
    same_poses(read_camera_poses(tmp_path / "opk.csv"), truth)
    # Metashape "Omega Phi Kappa" export: tab separated, header in the last comment line
    lines = [f"# Cameras ({len(truth)})",
             "# PhotoID, X, Y, Z, Omega, Phi, Kappa, r11, r12, r13, r21, r22, r23, r31, r32, r33"]
    for p in truth:
        opk = np.degrees(opk_from_rotation(p.R_cam_to_world))
        values = [*p.C_world, *opk, *p.R_cam_to_world.T.ravel()]
        lines.append("\t".join([p.image_name, *(repr(float(v)) for v in values)]))
    (tmp_path / "metashape.txt").write_text("\n".join(lines) + "\n")
    same_poses(read_camera_poses(tmp_path / "metashape.txt"), truth)
    # OpenDroneMap shots.geojson: centre, and the Rodrigues vector of world -> camera (CV)
    features = []
    for p in truth:
        rvec = cv2.Rodrigues(R_CV_FROM_PHOTO @ p.R_cam_to_world.T)[0].ravel()
        features.append({"type": "Feature", "properties": {
            "filename": p.image_name, "translation": p.C_world.tolist(),
            "rotation": rvec.tolist()}, "geometry": {"type": "Point", "coordinates": [0, 0]}})
    (tmp_path / "shots.geojson").write_text(json.dumps({"type": "FeatureCollection",
                                                        "features": features}))
    same_poses(read_camera_poses(tmp_path / "shots.geojson"), truth)


def test_reader_errors(tmp_path):
    with pytest.raises(DesignerError, match="do not exist"):
        read_camera_poses(tmp_path / "none.csv")
    (tmp_path / "empty").mkdir()
    with pytest.raises(DesignerError, match="not a COLMAP model"):
        read_camera_poses(tmp_path / "empty")
    (tmp_path / "x.geojson").write_text('{"features": [{"properties": {}}]}')
    with pytest.raises(DesignerError, match=r"shots\.geojson"):
        read_camera_poses(tmp_path / "x.geojson")
