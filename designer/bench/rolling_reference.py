"""The rolling-shutter adjustment as a Ceres problem with a Python cost per observation.

This is the formulation designer.sfm.rolling_adjustment used before its vectorised
solver (designer 1.x up to f3e0d1c): every observation, prior and velocity is its own
pyceres residual block, COLMAP's reprojection cost wrapped in a Python ``CostFunction``
at the moved point X − delay · velocity. It is kept, unchanged in what it computes, as
the reference the vectorised solver is tested against (tests/sfm/test_rolling_solver.py)
and measured against (``designer bench rolling-adjustment``): 27 s for 60 images where
the vectorised solver takes about a second.
"""

from __future__ import annotations

import numpy as np

from designer.core.rolling_shutter import row_delay_s
from designer.sfm.control_costs import add_control_points
from designer.sfm.rolling_adjustment import (
    VELOCITY_PRIOR_SIGMA,
    VELOCITY_PRIOR_SIGMA_NO_START,
    RollingShutterImage,
    RollingShutterSolution,
    start_velocities,
)


def _rolling_cost_class():
    import pyceres

    class RollingShutterReprojCost(pyceres.CostFunction):
        """Reprojection error of an observation exposed ``delay_s`` after the first row:
        parameter blocks point (3), rotation quaternion xyzw (4), translation (3), camera
        (n), velocity (3); COLMAP's cost at the point moved by −delay · velocity."""

        def __init__(self, inner, delay_s: float, n_camera: int):
            super().__init__()
            self.inner = inner
            self.delay = float(delay_s)
            self.set_num_residuals(2)
            self.set_parameter_block_sizes([3, 4, 3, n_camera, 3])

        def Evaluate(self, parameters, residuals, jacobians):
            X, q, t, cam, vel = parameters
            Y = X - self.delay * vel
            pose = np.concatenate([q, t])
            if jacobians is None:
                r, _ = self.inner.evaluate(Y, pose, cam)
                residuals[:] = r[:, 0]
                return True
            r, (JY, Jpose, Jcam) = self.inner.evaluate(Y, pose, cam)
            residuals[:] = r[:, 0]
            if jacobians[0] is not None:
                jacobians[0][:] = JY.ravel()
            if jacobians[1] is not None:
                jacobians[1][:] = Jpose[:, :4].ravel()
            if jacobians[2] is not None:
                jacobians[2][:] = Jpose[:, 4:].ravel()
            if jacobians[3] is not None:
                jacobians[3][:] = Jcam.ravel()
            if jacobians[4] is not None:
                jacobians[4][:] = (-self.delay * JY).ravel()
            return True

    class PositionPriorCost(pyceres.CostFunction):
        """COLMAP's camera-position prior on a pose split into quaternion and translation."""

        def __init__(self, inner):
            super().__init__()
            self.inner = inner
            self.set_num_residuals(3)
            self.set_parameter_block_sizes([4, 3])

        def Evaluate(self, parameters, residuals, jacobians):
            q, t = parameters
            r, (J,) = self.inner.evaluate(np.concatenate([q, t]))
            residuals[:] = r[:, 0]
            if jacobians is not None:
                if jacobians[0] is not None:
                    jacobians[0][:] = J[:, :4].ravel()
                if jacobians[1] is not None:
                    jacobians[1][:] = J[:, 4:].ravel()
            return True

    class VelocityPriorCost(pyceres.CostFunction):
        """(vel − start) / σ."""

        def __init__(self, start: np.ndarray, sigma: float):
            super().__init__()
            self.start = np.asarray(start, float).copy()
            self.w = 1.0 / float(sigma)
            self.set_num_residuals(3)
            self.set_parameter_block_sizes([3])

        def Evaluate(self, parameters, residuals, jacobians):
            residuals[:] = (parameters[0] - self.start) * self.w
            if jacobians is not None and jacobians[0] is not None:
                jacobians[0][:] = (np.eye(3) * self.w).ravel()
            return True

    return RollingShutterReprojCost, PositionPriorCost, VelocityPriorCost


def adjust_rolling_ceres(
    rec, variable: tuple[int, ...], shutters: dict[str, RollingShutterImage], control,
    sigma_mark_px: float, priors, min_gcp_sigma_m: float, max_iterations: int = 100,
    fix_gauge: bool = False,
) -> tuple[RollingShutterSolution, dict[str, np.ndarray]]:
    """designer.sfm.rolling_adjustment.adjust_rolling's problem (the same arguments and
    returns) as Ceres solves it, with a Python cost per observation; ``rec`` is updated
    in place."""
    import pyceres
    import pycolmap
    from pycolmap import cost_functions as cf

    RSCost, PriorCost, VelPrior = _rolling_cost_class()
    problem = pyceres.Problem()
    keep: list = []
    cam_params = {cid: camera.params for cid, camera in rec.cameras.items()}
    # poses by frame: a rig's images share their station's rig_from_world and project
    # through their mount's fixed cam_from_rig (designer.sfm.rigs)
    q, t, img_of, vel, frame_of, in_rig = {}, {}, {}, {}, {}, {}
    C_now = {}
    for image in rec.images.values():
        if not image.has_pose:
            continue
        fid = image.frame_id
        frame = rec.frames[fid]
        if fid not in q:
            pose = frame.rig_from_world.params
            q[fid] = np.array(pose[:4], float)
            t[fid] = np.array(pose[4:], float)
        rig = rec.rigs[frame.rig_id]
        sensor = pycolmap.sensor_t(pycolmap.SensorType.CAMERA, image.camera_id)
        if not rig.is_ref_sensor(sensor):
            in_rig[image.name] = rig.sensor_from_rig(sensor)
        frame_of[image.name] = fid
        img_of[image.name] = image
        C_now[image.name] = image.projection_center()
    starts = start_velocities(C_now, shutters)
    for name, v0 in starts.items():
        vel[name] = v0.copy()
    eye2 = np.eye(2)
    points = {pid: np.array(pt.xyz, float) for pid, pt in rec.points3D.items()}
    zero_vel = np.zeros(3)  # a global-shutter image's (constant) velocity

    def add_observation(X, name, uv, cov):
        image = img_of[name]
        cid = image.camera_id
        camera = rec.cameras[cid]
        s = shutters.get(name)
        delay = 0.0
        if s is not None:
            delay = float(row_delay_s(uv[1], camera.height, s.readout_s, s.direction))
        uv = np.asarray(uv, float)
        inner = cf.RigReprojErrorCost(camera.model, cov, uv, in_rig[name]) \
            if name in in_rig else cf.ReprojErrorCost(camera.model, cov, uv)
        v = vel.get(name, zero_vel)
        f = frame_of[name]
        return problem.add_residual_block(RSCost(inner, delay, len(cam_params[cid])), None,
                                          [X, q[f], t[f], cam_params[cid], v])

    tie_blocks: list = []  # (point id, residual block) of every tie observation (σ 1 px)
    for pid, X in points.items():
        for el in rec.points3D[pid].track.elements:
            image = rec.images[el.image_id]
            if image.name not in img_of:
                continue
            tie_blocks.append((pid, add_observation(
                X, image.name, np.asarray(image.points2D[el.point2D_idx].xy, float), eye2)))
    if problem.has_parameter_block(zero_vel):
        problem.set_parameter_block_constant(zero_vel)

    xyz_by_id = add_control_points(problem, control, img_of.__contains__, add_observation,
                                   sigma_mark_px, min_gcp_sigma_m, keep)
    if priors is not None:
        cov = np.diag([priors.sigma_h_m ** 2, priors.sigma_h_m ** 2, priors.sigma_v_m ** 2])
        posed = set()  # a station of a rig has one pose: one GNSS position (its first image's)
        for name, C in sorted(priors.C_local.items()):
            f = frame_of.get(name)
            if f is not None and f not in posed and problem.has_parameter_block(q[f]):
                posed.add(f)
                problem.add_residual_block(
                    PriorCost(cf.AbsolutePosePositionPriorCost(cov, np.asarray(C, float))),
                    None, [q[f], t[f]])
    for name, v in vel.items():
        if problem.has_parameter_block(v):
            sigma = VELOCITY_PRIOR_SIGMA if np.any(starts[name]) else \
                VELOCITY_PRIOR_SIGMA_NO_START
            problem.add_residual_block(VelPrior(starts[name], sigma), None, [v])

    for f in q:
        if problem.has_parameter_block(q[f]):
            problem.set_manifold(q[f], pyceres.EigenQuaternionManifold())
    for params in cam_params.values():
        if not problem.has_parameter_block(params):
            continue
        if variable:
            constant = [i for i in range(len(params)) if i not in variable]
            problem.set_manifold(params, pyceres.SubsetManifold(len(params), constant))
        else:
            problem.set_parameter_block_constant(params)
    if fix_gauge:
        _fix_gauge(problem, [f for f in q if problem.has_parameter_block(q[f])], q, t)

    options = pyceres.SolverOptions()
    options.linear_solver_type = pyceres.LinearSolverType.SPARSE_SCHUR
    options.max_num_iterations = max_iterations
    options.function_tolerance = 1e-9
    options.num_threads = 1  # the costs are Python: one thread (the GIL) anyway
    summary = pyceres.SolverSummary()
    pyceres.solve(options, problem, summary)

    for f in q:
        pose = rec.frames[f].rig_from_world
        pose.params[:4] = q[f] / np.linalg.norm(q[f])
        pose.params[4:] = t[f]
    for pid, X in points.items():
        rec.points3D[pid].xyz = X
    # each tie observation's reprojection error with the compensation (σ 1 px: the
    # residual is in px), by point: COLMAP's own figures would project every row from the
    # first row's pose
    errors: dict[int, list[float]] = {}
    if tie_blocks:
        r = np.asarray(problem.evaluate_residuals([b for _, b in tie_blocks]), float)
        norms = np.hypot(r[0::2], r[1::2])
        for (pid, _), e in zip(tie_blocks, norms, strict=True):
            errors.setdefault(pid, []).append(float(e))
    return (RollingShutterSolution({n: v.copy() for n, v in vel.items()}, summary, errors),
            {k: v.copy() for k, v in xyz_by_id.items()})


def _fix_gauge(problem, frames, q, t) -> None:
    """No datum (no control, no priors): the first frame's pose is held, and the second
    frame's largest translation component (the scale), as COLMAP's two-camera gauge."""
    import pyceres

    if not frames:
        return
    first = frames[0]
    problem.set_parameter_block_constant(q[first])
    problem.set_parameter_block_constant(t[first])
    if len(frames) > 1:
        second = frames[1]
        k = int(np.argmax(np.abs(t[second] - t[first])))
        problem.set_manifold(t[second], pyceres.SubsetManifold(3, [k]))
