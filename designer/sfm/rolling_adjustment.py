"""Rolling-shutter compensation in the final bundle adjustment.

A rolling-shutter image's rows are exposed one after the other (docs/world.md, "Rolling
shutter"; :mod:`designer.core.rolling_shutter`): the image's pose is that of the **first
row read**, at its time t0, and continuous row coordinate v is exposed
``delay(v) = (v − ½) / H · readout`` later (``(H − ½ − v) / H · readout`` bottom-to-top),
while the camera moves on at a constant velocity and keeps its attitude. With
compensation, every image gets three more parameters, its velocity ``vel`` (model frame,
m/s), and a point X seen at (u, v) is projected from the perspective centre
C + delay(v) · vel — equivalently, the point X − delay(v) · vel is projected with the
image's own pose, which is how it is evaluated (∂/∂vel = −delay · ∂/∂X). The delay comes
from the observed row (the usual first-order form of rolling-shutter adjustment; the
observed row differs from the model row by the residual).

The problem — the same observations, weights, priors and gauge as COLMAP's adjustment
in designer.sfm.adjustment, from one set-up (designer.sfm.block_setup) — is held in
arrays and evaluated for all observations at once with analytic Jacobians
(designer.sfm.rolling_problem, COLMAP's FULL_OPENCV model in designer.sfm.full_opencv),
and solved by Ceres's Levenberg–Marquardt with the points eliminated by the Schur
complement (designer.sfm.schur_lm): 60 images and 110,000 observations in about 2 s of
CPU where a Ceres problem with a Python cost per observation took 27 s
(designer.bench.rolling_reference, kept as the reference; ``designer bench
rolling-adjustment``).

Velocities start from the model's camera centres differenced along the flight's time
line (the next photo in time, else the previous, when they are at most
:data:`MAX_NEIGHBOUR_GAP` trigger intervals apart) and are held by a prior around that
start, σ :data:`VELOCITY_PRIOR_SIGMA` (model units per second, m/s once georeferenced):
the centres are known to centimetres a second apart, while a free velocity is seen
weakly (with σ 20 m/s the vertical velocities of a 20 ms readout scattered by 3 m/s).
An image without a
neighbour on its leg starts from zero with σ :data:`VELOCITY_PRIOR_SIGMA_NO_START`.

The readout and direction are known (the camera's, from the ground truth): the
adjustment does not estimate them. The attitude is held during the readout (no angular
velocity).
"""

from __future__ import annotations

import csv
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from designer.core.rolling_shutter import row_delay_s
from designer.errors import DesignerError

#: σ of the velocity prior around its time-line start (model units / s: m/s once
#: georeferenced)
VELOCITY_PRIOR_SIGMA = 1.0
#: σ of the velocity prior of an image without a neighbour on its leg (start: zero)
VELOCITY_PRIOR_SIGMA_NO_START = 20.0
#: a neighbour in time further than this many median trigger intervals is another leg
MAX_NEIGHBOUR_GAP = 1.5


@dataclass(frozen=True)
class RollingShutterImage:
    """The shutter of one image: readout (s), direction, and its first row's time (s)."""

    readout_s: float
    direction: str
    time_s: float


def read_rolling_shutter_truth(survey: Path) -> dict[str, RollingShutterImage]:
    """Image name → its rolling shutter, from ``ground-truth/rolling_shutter.csv`` (only
    the rolling-shutter images with a readout above 0; empty when the file is absent)."""
    from designer.core.layout import GROUND_TRUTH_DIR, ROLLING_SHUTTER_CSV

    path = Path(survey) / GROUND_TRUTH_DIR / ROLLING_SHUTTER_CSV
    if not path.is_file():
        return {}
    out = {}
    with path.open(newline="") as f:
        for row in csv.DictReader(f):
            readout = float(row["readout_s"])
            if readout > 0:
                out[row["image"]] = RollingShutterImage(readout, row["direction"],
                                                        float(row["first_row_time_s"]))
    return out


def check_compensation(shutters: dict[str, RollingShutterImage], names, survey) -> None:
    """One-line error when compensation is asked for images without a rolling shutter."""
    if not any(n in shutters for n in names):
        raise DesignerError(
            f"{survey}: --rolling-shutter compensate, but its images have a global shutter "
            "(no camera reads its rows out: ground-truth/rolling_shutter.csv lists no image "
            "with a readout above 0); use --rolling-shutter none (or "
            "<calibration rolling-shutter=\"none\">)")


def start_velocities(C: dict[str, np.ndarray], shutters: dict[str, RollingShutterImage]
                     ) -> dict[str, np.ndarray]:
    """Start velocity of each rolling-shutter image: its centre's motion to the next photo
    in time (else from the previous), zero without a neighbour on the same leg."""
    names = sorted((n for n in shutters if n in C), key=lambda n: shutters[n].time_s)
    t = np.array([shutters[n].time_s for n in names])
    dts = np.diff(t)
    gap = MAX_NEIGHBOUR_GAP * float(np.median(dts[dts > 0])) if np.any(dts > 0) else 0.0
    out = {}
    for k, n in enumerate(names):
        vel = np.zeros(3)
        for j in (k + 1, k - 1):
            if 0 <= j < len(names):
                dt = t[j] - t[k]
                if 0 < abs(dt) <= gap:
                    vel = (C[names[j]] - C[n]) / dt
                    break
        out[n] = vel
    return out


@dataclass
class RollingShutterSolution:
    """The estimated velocities by image name (model frame, per second) and the summary."""

    velocities: dict[str, np.ndarray]
    summary: object
    #: reprojection errors (px) of each tie point's observations, with the compensation
    point_errors_px: dict[int, list[float]] = field(default_factory=dict)


def adjust_rolling(rec, variable: tuple[int, ...], shutters: dict[str, RollingShutterImage],
                   control, sigma_mark_px: float, priors, min_gcp_sigma_m: float,
                   max_iterations: int = 100, fix_gauge: bool = False
                   ) -> tuple[RollingShutterSolution, dict[str, np.ndarray]]:
    """The final adjustment with each rolling-shutter image's velocity (module
    docstring): tie points (σ 1 px), control marks and surveyed control coordinates, camera
    position priors, the interior parameters ``variable``; ``rec`` is updated in place.
    Images without a rolling shutter (not in ``shutters``) are global-shutter images.
    Returns the solution and the control points' adjusted coordinates by id.

    All observations are evaluated at once (designer.sfm.rolling_problem) and solved by
    Levenberg–Marquardt with the points eliminated (designer.sfm.schur_lm); the Ceres
    formulation it replaced, a Python cost per observation, is
    designer.bench.rolling_reference."""
    from designer.sfm.rolling_problem import RollingProblem
    from designer.sfm.schur_lm import SchurLayout, solve

    block = _rolling_block(rec, variable, shutters, control, sigma_mark_px, priors,
                           min_gcp_sigma_m, fix_gauge)
    a = block.arrays
    velocities = {n: v.copy() for n, v in block.starts.items()}
    if not len(a.obs_image):
        from designer.sfm.schur_lm import LMSummary

        summary = LMSummary(0.0, 0.0, 0, 0, "CONVERGENCE", 0, 0)
        return RollingShutterSolution(velocities, summary, {}), {}
    problem = RollingProblem(a)
    layout = SchurLayout(a.obs_image, a.obs_point, a.image_cols, a.n_cam,
                         len(block.state.X))
    state, summary = solve(problem, layout, block.state, max_iterations,
                           n_residuals=a.n_residuals)

    from designer.core.rotation import quaternion_from_rotation

    q_wxyz = quaternion_from_rotation(state.R)
    for k, fid in enumerate(block.frame_ids):
        pose = rec.frames[fid].rig_from_world
        pose.params[:4] = np.roll(q_wxyz[k], -1)  # COLMAP's order: x y z w
        pose.params[4:] = state.t[k]
    for k, pid in enumerate(block.point_ids):
        rec.points3D[pid].xyz = state.X[k]
    if len(a.variable):
        for k, cid in enumerate(block.camera_ids):
            camera = rec.cameras[cid]
            n = len(camera.params)
            camera.params = state.cam[k, :n]
    for k, name in enumerate(block.image_names):
        if name in velocities:
            velocities[name] = state.vel[k].copy()
    # each tie observation's reprojection error with the compensation (σ 1 px: the
    # residual is in px), by point: COLMAP's own figures would project every row from the
    # first row's pose
    r = problem.residuals(state)[block.tie_rows]
    by_point = np.argsort(block.tie_point_ids, kind="stable")
    norms = np.hypot(r[by_point, 0], r[by_point, 1]).tolist()
    ids, first = np.unique(block.tie_point_ids[by_point], return_index=True)
    ends = [*first[1:].tolist(), len(norms)]
    errors = {pid: norms[a:b] for pid, a, b in zip(ids.tolist(), first.tolist(), ends,
                                                   strict=True)}
    n_tie = len(block.point_ids)
    xyz = {gid: state.X[n_tie + k].copy() for k, gid in enumerate(block.control_ids)}
    return RollingShutterSolution(velocities, summary, errors), xyz


@dataclass
class _RollingBlock:
    """The arrays of a rolling-shutter adjustment and what their indices stand for."""

    arrays: object  # designer.sfm.rolling_problem.RollingArrays
    state: object   # designer.sfm.rolling_problem.RollingState
    starts: dict[str, np.ndarray]
    frame_ids: list[int]
    image_names: list[str]
    camera_ids: list[int]
    point_ids: list[int]        # tie points (the control points follow them)
    control_ids: list[str]
    tie_rows: np.ndarray        # rows of the sorted observations that are tie points
    tie_point_ids: np.ndarray   # their point ids


def _rolling_block(rec, variable, shutters, control, sigma_mark_px, priors,
                   min_gcp_sigma_m, fix_gauge) -> _RollingBlock:
    """The problem of :func:`adjust_rolling` as arrays (designer.sfm.rolling_problem):
    the images with a pose and an observation, their stations and cameras, the points."""
    from designer.sfm.block_setup import posed_images, prior_sigmas_m
    from designer.sfm.rolling_problem import RollingArrays, RollingState

    posed = posed_images(rec)
    starts = start_velocities({n: rec.images[im.image_id].projection_center()
                               for n, im in posed.items()}, shutters)
    obs = _block_observations(rec, posed, control, sigma_mark_px, min_gcp_sigma_m)
    o_img, o_pt, o_uv, o_w, X, point_ids, in_block, n_tie_obs = obs
    n_tie = len(point_ids)
    used = _used_images(rec, posed, o_img)
    image_names, o_img, images, frame_ids, camera_ids, image_frame, image_camera = used
    mount_R, mount_t = _mounts(images)
    cams = [rec.cameras[cid] for cid in camera_ids]
    cam = _camera_params(cams)
    variable = np.array(sorted(variable), np.int64)
    delay, vel = _delays_and_starts(rec, image_names, images, shutters, starts, o_img, o_uv)
    R, t = _station_poses(rec, frame_ids)
    image_cols, vel_image, n = _columns(frame_ids, t, image_names, shutters, cams, variable,
                                        image_frame, image_camera, fix_gauge)
    prior_frame, prior_C = _station_prior_rows(priors, frame_ids, posed)
    prior_sigma = np.tile(prior_sigmas_m(priors), (len(prior_frame), 1)) if priors \
        is not None else np.zeros((0, 3))
    vel_sigma = [VELOCITY_PRIOR_SIGMA if np.any(starts[image_names[k]])
                 else VELOCITY_PRIOR_SIGMA_NO_START for k in vel_image]

    order = np.lexsort((o_pt, o_img))  # by image, then point
    tie_rows = np.flatnonzero(order < n_tie_obs)  # sorted rows of the tie observations
    arrays = RollingArrays(
        obs_image=o_img[order], obs_point=o_pt[order], uv=o_uv[order], weight=o_w[order],
        delay=delay[order], image_frame=image_frame, image_camera=image_camera,
        mount_R=mount_R, mount_t=mount_t, variable=variable,
        control_index=np.arange(n_tie, n_tie + len(in_block), dtype=np.int64),
        control_xyz=np.array([cp.surveyed_local for cp in in_block]).reshape(-1, 3),
        control_sigma=np.array([cp.sigma_m for cp in in_block]).reshape(-1, 3),
        prior_frame=np.array(prior_frame, np.int64), prior_C=np.array(prior_C).reshape(-1, 3),
        prior_sigma=prior_sigma, vel_image=np.array(vel_image, np.int64),
        vel_start=vel[vel_image].reshape(-1, 3), vel_sigma=np.array(vel_sigma, float),
        image_cols=image_cols, n_cam=n)
    state = RollingState(R=R, t=t, vel=vel, cam=cam, X=X)
    return _RollingBlock(arrays, state, starts, frame_ids, list(image_names), camera_ids,
                         point_ids.tolist(), [cp.gcp_id for cp in in_block], tie_rows,
                         point_ids[o_pt[order][tie_rows]])


def _block_observations(rec, posed: dict, control, sigma_mark_px: float,
                        min_gcp_sigma_m: float):
    """The observations of the posed images: (image index into ``posed``, point index,
    uv px, weight 1/px) each, tie points first (weight 1) then the control points' marks;
    the points' start coordinates (tie points, then control points; local, m); the tie
    points' ids; the control points in the block; the number of tie observations."""
    from designer.sfm.control_costs import control_in_block
    from designer.sfm.observations import tie_observations

    names = list(posed)
    # tie observations of the posed images, image by image
    tie = tie_observations(rec)
    image_index = np.full(int(max(rec.images, default=0)) + 1, -1)
    image_index[[im.image_id for im in posed.values()]] = np.arange(len(posed))
    o_img = image_index[tie.image_id]
    keep = o_img >= 0
    o_img = o_img[keep]
    point_ids, o_pt = np.unique(tie.point3D_id[keep], return_inverse=True)
    o_uv = [tie.xy[keep]]
    n_tie_obs, n_tie = len(o_img), len(point_ids)
    by_id = np.argsort(tie.point_ids)
    X = [tie.point_xyz[by_id[np.searchsorted(tie.point_ids, point_ids, sorter=by_id)]]]
    o_img, o_pt, o_w = [o_img], [o_pt], [np.ones(n_tie_obs)]
    in_block = control_in_block(control, posed.__contains__, min_gcp_sigma_m)
    names_index = {n: k for k, n in enumerate(names)}
    for k, cp in enumerate(in_block):
        X.append(cp.surveyed_local[None])
        o_img.append(np.array([names_index[name] for name, _ in cp.marks]))
        o_pt.append(np.full(len(cp.marks), n_tie + k))
        o_uv.append(np.array([uv for _, uv in cp.marks], float))
        o_w.append(np.full(len(cp.marks), 1.0 / sigma_mark_px))
    return (np.concatenate(o_img).astype(np.int64), np.concatenate(o_pt).astype(np.int64),
            np.concatenate(o_uv).reshape(-1, 2), np.concatenate(o_w),
            np.concatenate(X).reshape(-1, 3), point_ids, in_block, n_tie_obs)


def _used_images(rec, posed: dict, o_img: np.ndarray):
    """The images, stations and cameras with an observation, in the reconstruction's
    order: (image names, ``o_img`` renumbered to them, their pycolmap images, station
    ids, camera ids, each image's station index and camera index)."""
    names = list(posed)
    used = np.unique(o_img)
    image_names = [names[k] for k in used]
    renumber = np.full(len(names), -1)
    renumber[used] = np.arange(len(used))
    images = [posed[n] for n in image_names]
    used_frames = {im.frame_id for im in images}
    frame_ids = [f for f in dict.fromkeys(im.frame_id for im in posed.values())
                 if f in used_frames]
    camera_ids = list(dict.fromkeys(im.camera_id for im in images))
    image_frame = np.array([frame_ids.index(im.frame_id) for im in images])
    image_camera = np.array([camera_ids.index(im.camera_id) for im in images])
    return (image_names, renumber[o_img], images, frame_ids, camera_ids, image_frame,
            image_camera)


def _mounts(images: list) -> tuple[np.ndarray, np.ndarray]:
    """Each image's camera-from-rig rotation (K, 3, 3) and translation (K, 3), m; the
    identity for an image without a rig."""
    mount_R = np.tile(np.eye(3), (len(images), 1, 1))
    mount_t = np.zeros((len(images), 3))
    for k, im in enumerate(images):
        if im.cam_from_rig is not None:
            mount_R[k] = im.cam_from_rig.rotation.matrix()
            mount_t[k] = im.cam_from_rig.translation
    return mount_R, mount_t


def _camera_params(cams: list) -> np.ndarray:
    """The cameras' FULL_OPENCV parameters (C, 12), or a clear error for a model the
    compensation does not take."""
    from designer.sfm.full_opencv import PREFIX_MODELS, full_opencv_params

    for camera in cams:
        if camera.model.name not in PREFIX_MODELS:
            raise DesignerError(
                f"camera model {camera.model.name}: rolling-shutter compensation supports "
                "pinhole and Brown–Conrady cameras; use a brown-conrady distortion")
    return np.array([full_opencv_params(c.model.name, c.params) for c in cams])


def _delays_and_starts(rec, image_names, images, shutters, starts, o_img, o_uv):
    """Each observation's row delay (s; 0 in a global-shutter image) and each image's
    start velocity (m/s; 0 without a shutter)."""
    delay = np.zeros(len(o_img))
    vel = np.zeros((len(images), 3))
    for k, (name, im) in enumerate(zip(image_names, images, strict=True)):
        s = shutters.get(name)
        if s is not None:
            rows = o_img == k
            delay[rows] = row_delay_s(o_uv[rows, 1], rec.cameras[im.camera_id].height,
                                      s.readout_s, s.direction)
            vel[k] = starts[name]
    return delay, vel


def _station_poses(rec, frame_ids: list[int]) -> tuple[np.ndarray, np.ndarray]:
    """The stations' rig-from-world rotations (F, 3, 3) and translations (F, 3), m."""
    from designer.core.rotation import rotation_from_quaternion

    R, t = [], []
    for fid in frame_ids:
        pose = np.asarray(rec.frames[fid].rig_from_world.params, float)
        R.append(rotation_from_quaternion(np.roll(pose[:4], 1)))  # x y z w → w x y z
        t.append(pose[4:].copy())
    return np.array(R), np.array(t)


def _columns(frame_ids, t, image_names, shutters, cams, variable, image_frame, image_camera,
             fix_gauge):
    """The global camera-side columns: stations (6, less the gauge's), velocities,
    cameras; (each image's columns, the images with a velocity, the number of columns)."""
    from designer.sfm.block_setup import two_station_gauge
    from designer.sfm.rolling_problem import POSE_COLS, VEL_COLS

    held = set()
    if fix_gauge:
        first, second, k = two_station_gauge(list(range(len(frame_ids))), lambda f: t[f])
        held |= {(first, j) for j in range(POSE_COLS)}
        if second is not None:
            held.add((second, 3 + k))
    frame_cols = np.full((len(frame_ids), POSE_COLS), -1)
    n = 0
    for f in range(len(frame_ids)):
        for j in range(POSE_COLS):
            if (f, j) not in held:
                frame_cols[f, j] = n
                n += 1
    vel_cols = np.full((len(image_names), VEL_COLS), -1)
    vel_image = [k for k, name in enumerate(image_names) if name in shutters]
    for k in vel_image:
        vel_cols[k] = np.arange(n, n + VEL_COLS)
        n += VEL_COLS
    cam_cols = np.full((len(cams), len(variable)), -1)
    for c, camera in enumerate(cams):
        for j, p in enumerate(variable):
            if p < len(camera.params):
                cam_cols[c, j] = n
                n += 1
    image_cols = np.hstack([frame_cols[image_frame], vel_cols, cam_cols[image_camera]])
    return image_cols, vel_image, n


def _station_prior_rows(priors, frame_ids: list[int], posed: dict):
    """The stations with a position prior and their prior centres (local, m)."""
    from designer.sfm.block_setup import station_priors

    prior_frame, prior_C = [], []
    if priors is not None:
        frame_index = {f: k for k, f in enumerate(frame_ids)}
        frame_of = {n: frame_index.get(im.frame_id) for n, im in posed.items()}
        for f, C in station_priors(priors, frame_of.get):
            prior_frame.append(f)
            prior_C.append(C)
    return prior_frame, prior_C
