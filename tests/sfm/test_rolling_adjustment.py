"""Rolling-shutter compensation in the final adjustment (designer.sfm.rolling_adjustment)
on a synthetic nadir block: observations made by a rolling-shutter projection, no render."""

from __future__ import annotations

import numpy as np
import pytest

pycolmap = pytest.importorskip("pycolmap")

from designer.bench.synthetic_block import add_tracks  # noqa: E402
from designer.errors import DesignerError  # noqa: E402
from designer.sfm.adjustment import PositionPriors, adjust  # noqa: E402
from designer.sfm.rolling_adjustment import (  # noqa: E402
    RollingShutterImage,
    check_compensation,
    start_velocities,
)

W, H, F = 400, 300, 500.0
HEIGHT = 40.0
SPEED = 8.0
INTERVAL_S = 1.0
FLIP = np.diag([1.0, -1.0, -1.0])


def _rs_uv(X, C, vel, readout):
    """Rolling-shutter pixel of world points X (N, 3) in a nadir camera (first-row centre
    C, image top north): v solved by fixed-point iteration on the row's delay."""
    R_cv = FLIP  # cam_from_world rotation of ω = φ = κ = 0 (CV frame)
    v = np.full(len(X), H / 2)
    for _ in range(30):
        delay = (v - 0.5) / H * readout
        p = (X - C - delay[:, None] * vel) @ R_cv.T
        u = F * p[:, 0] / p[:, 2] + W / 2
        v = F * p[:, 1] / p[:, 2] + H / 2
    return np.stack([u, v], axis=1)


def synthetic_block(readout_s: float, noise_px: float = 0.2, seed: int = 0):
    """(reconstruction perturbed from the truth, true points, true centres, shutters):
    three strips of eight photos flown north, south, north at SPEED."""
    rng = np.random.default_rng(seed)
    centres, vels, times = [], [], []
    k = 0
    for strip in range(3):
        sign = 1.0 if strip % 2 == 0 else -1.0
        for i in range(8):
            y = sign * (i - 3.5) * SPEED * INTERVAL_S
            centres.append(np.array([strip * 20.0, y, HEIGHT]))
            vels.append(np.array([0.0, sign * SPEED, 0.0]))
            times.append(k * INTERVAL_S + strip * 10.0)
            k += 1
    pts = np.column_stack([rng.uniform(-10, 50, 1500), rng.uniform(-40, 40, 1500),
                           rng.uniform(-3, 3, 1500)])
    rec = pycolmap.Reconstruction()
    camera = pycolmap.Camera(model="FULL_OPENCV", width=W, height=H,
                             params=[F, F, W / 2, H / 2] + [0.0] * 8, camera_id=1)
    rec.add_camera_with_trivial_rig(camera)
    obs = {}
    names = []
    for idx, (C, vel) in enumerate(zip(centres, vels, strict=True)):
        name = f"IMG_{idx:03d}.png"
        names.append(name)
        uv = _rs_uv(pts, C, vel, readout_s)
        inside = (uv[:, 0] > 1) & (uv[:, 0] < W - 1) & (uv[:, 1] > 1) & (uv[:, 1] < H - 1)
        ids = np.flatnonzero(inside)
        uv = uv[ids] + rng.normal(0, noise_px, (len(ids), 2))
        image = pycolmap.Image(name=name, camera_id=1, image_id=idx + 1)
        image.points2D = pycolmap.Point2DList([pycolmap.Point2D(xy) for xy in uv])
        # a perturbed start: centres off by a few cm, attitude by a few 0.01°
        C0 = C + rng.normal(0, 0.05, 3)
        Rn = pycolmap.Rotation3d(rng.normal(0, 3e-4, 3)).matrix()
        R_cv = Rn @ FLIP
        rec.add_image_with_trivial_frame(
            image, pycolmap.Rigid3d(pycolmap.Rotation3d(R_cv), -R_cv @ C0))
        for j, p in enumerate(ids):
            obs.setdefault(int(p), []).append((idx + 1, j))
    true_pts = add_tracks(rec, obs, pts, rng)
    shutters = {n: RollingShutterImage(readout_s, "top-to-bottom", tm)
                for n, tm in zip(names, times, strict=True)} if readout_s > 0 else {}
    true_C = dict(zip(names, centres, strict=True))
    return rec, true_pts, true_C, shutters


def _point_rmse(rec, true_pts) -> float:
    d = np.array([rec.points3D[pid].xyz - X for pid, X in true_pts.items()
                  if pid in rec.points3D])
    return float(np.sqrt(np.mean(np.sum(d ** 2, axis=1))))


def _priors(true_C):
    return PositionPriors({n: C.copy() for n, C in true_C.items()}, 0.02, 0.03)


def _compensation_removes_the_error(rec, true_pts, true_C, shutters):
    """Adjust a copy of ``rec`` without and ``rec`` with compensation: σ0 back to the
    observation noise (0.2 px), point errors down several-fold. The compensated result."""
    plain = pycolmap.Reconstruction(rec)
    r_plain = adjust(plain, "fixed", priors=_priors(true_C))
    r_rs = adjust(rec, "fixed", priors=_priors(true_C), rolling_shutter=shutters)
    assert r_rs.sigma0 < 0.25 < r_plain.sigma0
    e_plain, e_rs = _point_rmse(plain, true_pts), _point_rmse(rec, true_pts)
    assert e_rs < 0.4 * e_plain and e_rs < 0.15
    return r_rs


def test_velocity_parameters_remove_the_rolling_shutter_error():
    rec, true_pts, true_C, shutters = synthetic_block(0.02)
    r_rs = _compensation_removes_the_error(rec, true_pts, true_C, shutters)
    # the velocities come out as flown: along the strip at about SPEED (each image's
    # from a 2 px motion during its readout, observed with 0.2 px noise)
    v = np.array(list(r_rs.velocities.values()))
    assert np.allclose(np.abs(v[:, 1]), SPEED, rtol=0.35)
    assert abs(np.mean(np.abs(v[:, 1])) - SPEED) < 0.15 * SPEED
    assert np.abs(v[:, 0]).max() < 2.5 and np.abs(v[:, 2]).max() < 2.5  # weakly seen
    assert r_rs.as_dict()["rolling_shutter"]["images_compensated"] == 24


def test_reprojection_errors_and_outliers_are_judged_with_the_compensation():
    """A fast readout (60 ms at 8 m/s: ~10 px of motion over the image): COLMAP's own
    errors project every row from the first row's pose and call good points outliers;
    the compensated errors are the observation noise, and only they decide."""
    from designer.sfm.tie_points import drop_outliers, mean_reprojection_error_px

    rec, _, true_C, shutters = synthetic_block(0.06)
    r = adjust(rec, "fixed", priors=_priors(true_C), rolling_shutter=shutters)
    errors = r.point_errors_px
    assert set(errors) == set(rec.points3D)
    assert sum(len(e) for e in errors.values()) == sum(
        pt.track.length() for pt in rec.points3D.values())
    compensated = mean_reprojection_error_px(rec, errors)
    colmap = mean_reprojection_error_px(rec, None)
    assert compensated < 0.35 < 1.0 < colmap  # noise 0.2 px: mean |e| ≈ 0.25 px
    n = rec.num_points3D()
    colmap_copy = pycolmap.Reconstruction(rec)
    assert drop_outliers(colmap_copy, 2.0) > 0  # COLMAP's errors would drop good points
    assert drop_outliers(rec, 2.0, errors) == 0 and rec.num_points3D() == n


def test_compensation_of_a_global_shutter_block_changes_nothing_much():
    rec, true_pts, true_C, _ = synthetic_block(0.0)
    shutters = {n: RollingShutterImage(0.02, "top-to-bottom", 0.0) for n in true_C}
    plain = pycolmap.Reconstruction(rec)
    adjust(plain, "fixed", priors=_priors(true_C))
    r_rs = adjust(rec, "fixed", priors=_priors(true_C), rolling_shutter=shutters)
    assert r_rs.sigma0 < 0.25
    assert _point_rmse(rec, true_pts) < 1.5 * _point_rmse(plain, true_pts) + 0.005


def test_start_velocities_follow_the_time_line():
    C = {"a": np.zeros(3), "b": np.array([0, 8.0, 0]), "c": np.array([0, 16.0, 0]),
         "d": np.array([20.0, 16.0, 0])}
    s = {n: RollingShutterImage(0.02, "top-to-bottom", t)
         for n, t in zip("abcd", (0.0, 1.0, 2.0, 12.0), strict=True)}
    v = start_velocities(C, s)
    assert np.allclose(v["a"], [0, 8, 0]) and np.allclose(v["c"], [0, 8, 0])
    assert np.allclose(v["d"], 0)  # alone on its leg (the gap is a turn)


def test_compensation_of_global_shutter_images_is_refused():
    with pytest.raises(DesignerError, match=r"global shutter.*--rolling-shutter none"):
        check_compensation({}, ["IMG_000.png"], "survey")


def test_the_setting_round_trips_through_the_project_file(tmp_path):
    from dataclasses import replace

    from designer.project import model as m
    from designer.project.load import load_project
    from designer.project.model_to_xml import write_project
    from designer.sfm.settings import resolve_processing
    from tests.world.rolling_helpers import rolling_project

    p = rolling_project()
    proc = m.Processing(calibration=m.Calibration("fixed", rolling_shutter="compensate"))
    path = tmp_path / "p.xml"
    write_project(replace(p, processing=proc), path)
    assert 'rolling-shutter="compensate"' in path.read_text()
    assert load_project(path, check_files=False).processing.calibration.rolling_shutter \
        == "compensate"
    assert resolve_processing(tmp_path, path, rolling_shutter="none") \
        .calibration.rolling_shutter == "none"


TILT = np.radians(30.0)
#: cam_from_rig of a second, global-shutter camera turned 30° forward (about x) on the rig
R_FWD = np.array([[1.0, 0.0, 0.0],
                  [0.0, np.cos(TILT), np.sin(TILT)],
                  [0.0, -np.sin(TILT), np.cos(TILT)]])


def synthetic_rig_block(readout_s: float, noise_px: float = 0.2, seed: int = 1):
    """:func:`synthetic_block` with a rig at every station: the rolling-shutter nadir
    camera (reference) and a global-shutter camera turned 30° forward, fixed
    cam_from_rig; a station's images share one perturbed pose (a COLMAP frame)."""
    rng = np.random.default_rng(seed)
    rec = pycolmap.Reconstruction()
    for cid in (1, 2):
        rec.add_camera(pycolmap.Camera(model="FULL_OPENCV", width=W, height=H,
                                       params=[F, F, W / 2, H / 2] + [0.0] * 8,
                                       camera_id=cid))
    rig = pycolmap.Rig(rig_id=1)
    rig.add_ref_sensor(pycolmap.sensor_t(pycolmap.SensorType.CAMERA, 1))
    rig.add_sensor(pycolmap.sensor_t(pycolmap.SensorType.CAMERA, 2),
                   pycolmap.Rigid3d(pycolmap.Rotation3d(R_FWD), np.zeros(3)))
    rec.add_rig(rig)
    pts = np.column_stack([rng.uniform(-10, 50, 2000), rng.uniform(-60, 60, 2000),
                           rng.uniform(-3, 3, 2000)])
    obs, names, true_C, shutters = {}, [], {}, {}
    k = 0
    for strip in range(3):
        sign = 1.0 if strip % 2 == 0 else -1.0
        for i in range(8):
            C = np.array([strip * 20.0, sign * (i - 3.5) * SPEED * INTERVAL_S, HEIGHT])
            vel = np.array([0.0, sign * SPEED, 0.0])
            C0 = C + rng.normal(0, 0.05, 3)
            R0 = pycolmap.Rotation3d(rng.normal(0, 3e-4, 3)).matrix() @ FLIP
            frame = pycolmap.Frame(frame_id=k + 1, rig_id=1)
            ids, images = {}, []
            for cid, R_cam_from_rig in ((1, np.eye(3)), (2, R_FWD)):
                image_id = 2 * k + cid
                name = f"ST_{k:03d}_{'N' if cid == 1 else 'F'}.png"
                R_cv = R_cam_from_rig @ FLIP
                if cid == 1:
                    uv = _rs_uv(pts, C, vel, readout_s)
                    shutters[name] = RollingShutterImage(readout_s, "top-to-bottom",
                                                         k * INTERVAL_S + strip * 10.0)
                else:  # global shutter: the first row's pose for every row
                    p = (pts - C) @ R_cv.T
                    uv = np.stack([F * p[:, 0] / p[:, 2] + W / 2,
                                   F * p[:, 1] / p[:, 2] + H / 2], axis=1)
                    uv[p[:, 2] <= 0] = -1
                inside = (uv[:, 0] > 1) & (uv[:, 0] < W - 1) & (uv[:, 1] > 1) & \
                    (uv[:, 1] < H - 1)
                ids[cid] = np.flatnonzero(inside)
                uv = uv[ids[cid]] + rng.normal(0, noise_px, (len(ids[cid]), 2))
                image = pycolmap.Image(name=name, camera_id=cid, image_id=image_id,
                                       frame_id=k + 1)
                image.points2D = pycolmap.Point2DList([pycolmap.Point2D(xy) for xy in uv])
                frame.add_data_id(image.data_id)
                images.append(image)
                names.append(name)
                true_C[name] = C
                for j, pid in enumerate(ids[cid]):
                    obs.setdefault(int(pid), []).append((image_id, j))
            frame.rig_from_world = pycolmap.Rigid3d(pycolmap.Rotation3d(R0), -R0 @ C0)
            rec.add_frame(frame)
            for image in images:
                rec.add_image(image)
            rec.register_frame(k + 1)
            k += 1
    return rec, add_tracks(rec, obs, pts, rng), true_C, shutters


def test_a_rig_keeps_its_relative_orientation_while_its_rolling_shutter_is_compensated():
    """Rolling-shutter nadir + global-shutter forward camera on a rig (20 ms readout,
    8 m/s): the compensated adjustment keeps one pose per station (both images' centres
    equal, the relative rotation the rig's), estimates the nadir images' velocities and
    removes the rolling-shutter error; the forward images have no velocity."""
    rec, true_pts, true_C, shutters = synthetic_rig_block(0.02)
    r_rs = _compensation_removes_the_error(rec, true_pts, true_C, shutters)
    assert set(r_rs.velocities) == {n for n in true_C if n.endswith("_N.png")}
    v = np.array(list(r_rs.velocities.values()))
    assert abs(np.mean(np.abs(v[:, 1])) - SPEED) < 0.15 * SPEED
    for k in range(24):
        nadir = rec.find_image_with_name(f"ST_{k:03d}_N.png")
        fwd = rec.find_image_with_name(f"ST_{k:03d}_F.png")
        assert nadir.frame_id == fwd.frame_id
        np.testing.assert_allclose(nadir.projection_center(), fwd.projection_center(),
                                   atol=1e-9)
        relative = fwd.cam_from_world().rotation.matrix() @ \
            nadir.cam_from_world().rotation.matrix().T
        np.testing.assert_allclose(relative, R_FWD, atol=1e-9)
