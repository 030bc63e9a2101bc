"""The final bundle adjustment: COLMAP's Ceres problem plus the observations of a survey.

COLMAP (pycolmap) builds its bundle adjustment problem — tie-point reprojection errors
on the registered images, poses, points and the camera — and this module adds to that
same Ceres problem, with COLMAP's own cost functions:

* control points: their marked image positions (reprojection error with σ = the
  marking σ, at least :data:`MIN_MARKING_SIGMA_PX`) and their surveyed coordinates
  (a 3D prior with the surveyed σ per axis, at least :data:`MIN_GCP_SIGMA_M`) — so
  the control points bend the block, not only move it;
* camera-position priors (GNSS/RTK centres with σ horizontal/vertical);
* which interior parameters are estimated (a subset manifold on the camera block).

With rolling-shutter compensation (``rolling_shutter`` given) the problem is built by
designer.sfm.rolling_adjustment instead, with the same observations and weights plus
each rolling-shutter image's velocity during its readout.

Everything is in the local frame (world − offset, float64). Tie points are weighted
with σ = 1 px, so σ₀ is the a-posteriori standard deviation of unit weight in px.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from designer.sfm.settings import VARIABLE_PARAMS

#: a marking error of 0 px (ideal) is still given this σ in the adjustment, px
MIN_MARKING_SIGMA_PX = 0.1
#: surveyed σ below this (e.g. 0 for a perfect survey) is raised to it, m
MIN_GCP_SIGMA_M = 0.001


@dataclass(frozen=True)
class ControlPoint:
    """A control point in the adjustment: surveyed position (local m), σ (m), marks."""

    gcp_id: str
    surveyed_local: np.ndarray
    sigma_m: np.ndarray
    marks: tuple[tuple[str, np.ndarray], ...]  # (image name, uv px)


@dataclass(frozen=True)
class PositionPriors:
    """Measured camera centres by image name (local m) and their σ (m)."""

    C_local: dict[str, np.ndarray]
    sigma_h_m: float
    sigma_v_m: float


@dataclass
class AdjustmentResult:
    sigma0: float
    iterations: int
    termination: str
    residuals: int
    parameters: int
    control_xyz_local: dict[str, np.ndarray] = field(default_factory=dict)
    #: rolling-shutter compensation: estimated velocity by image name (model frame, /s)
    velocities: dict[str, np.ndarray] | None = None

    def as_dict(self) -> dict:
        out = {"sigma0": self.sigma0, "iterations": self.iterations,
               "termination": self.termination, "residuals": self.residuals,
               "parameters": self.parameters}
        if self.velocities is not None:
            speeds = [float(np.linalg.norm(v)) for v in self.velocities.values()]
            out["rolling_shutter"] = {
                "images_compensated": len(speeds),
                "median_speed": float(np.median(speeds)) if speeds else None,
                "velocities": {n: [float(x) for x in v]
                               for n, v in sorted(self.velocities.items())}}
        return out


def adjust(rec, calibration: str, control: list[ControlPoint] | None = None,
           marking_sigma_px: float = 0.0, priors: PositionPriors | None = None,
           max_iterations: int = 100, rolling_shutter: dict | None = None
           ) -> AdjustmentResult:
    """Adjust ``rec`` in place (local frame); the datum comes from the control points or
    priors when given, otherwise the gauge is fixed on two cameras. ``rolling_shutter``:
    image name → designer.sfm.rolling_adjustment.RollingShutterImage, the images whose
    velocity during the readout is estimated (compensation)."""
    import pyceres
    import pycolmap
    from pycolmap import cost_functions as cf

    control = control or []
    variable = VARIABLE_PARAMS[calibration]
    if rolling_shutter is not None:
        from designer.sfm.rolling_adjustment import adjust_rolling

        solution, xyz = adjust_rolling(
            rec, variable, rolling_shutter, control,
            max(marking_sigma_px, MIN_MARKING_SIGMA_PX), priors, MIN_GCP_SIGMA_M,
            max_iterations, fix_gauge=not control and priors is None)
        return _result(solution.summary, xyz, solution.velocities)
    options = pycolmap.BundleAdjustmentOptions()
    options.refine_focal_length = options.refine_principal_point = bool(variable)
    options.refine_extra_params = bool(variable)
    options.ceres.solver_options.max_num_iterations = max_iterations
    options.ceres.solver_options.function_tolerance = 1e-9
    options.ceres.solver_options.num_threads = -1
    options.print_summary = False
    config = pycolmap.BundleAdjustmentConfig()
    for image_id in rec.reg_image_ids():
        config.add_image(image_id)
    if not control and priors is None:
        config.fix_gauge(pycolmap.BundleAdjustmentGauge.TWO_CAMS_FROM_WORLD)
    adjuster = pycolmap.create_default_ceres_bundle_adjuster(options, config, rec)
    problem = adjuster.problem

    keep_alive: list[np.ndarray] = []
    # each camera (of a rig: each its own interior orientation) is its own parameter
    # block; ``params`` is a view of the camera's memory, COLMAP's block
    cam_params = {cid: camera.params for cid, camera in rec.cameras.items()}
    for params in cam_params.values():
        if variable and problem.has_parameter_block(params):
            constant = [i for i in range(len(params)) if i not in variable]
            problem.set_manifold(params, pyceres.SubsetManifold(len(params), constant))

    poses, camera_of = {}, {}
    for image in rec.images.values():
        if image.has_pose:
            pose = rec.frames[image.frame_id].rig_from_world.params
            if problem.has_parameter_block(pose):
                poses[image.name] = pose
                camera_of[image.name] = image.camera_id

    identity = np.array([0, 0, 0, 1, 0, 0, 0, 0], float)  # Sim3d: quat xyzw, t, log scale
    xyz_by_id = {}
    sigma_mark = max(marking_sigma_px, MIN_MARKING_SIGMA_PX)
    cov_uv = np.eye(2) * sigma_mark ** 2
    for cp in control:
        marks = [(name, uv) for name, uv in cp.marks if name in poses]
        if not marks:
            continue
        xyz = np.array(cp.surveyed_local, float)
        keep_alive.append(xyz)
        xyz_by_id[cp.gcp_id] = xyz
        sigma = np.maximum(np.asarray(cp.sigma_m, float), MIN_GCP_SIGMA_M)
        problem.add_residual_block(
            cf.Point3DAlignmentCost(np.diag(sigma ** 2), np.asarray(cp.surveyed_local, float)),
            None, [xyz, identity])
        for name, uv in marks:
            cid = camera_of[name]
            problem.add_residual_block(
                cf.ReprojErrorCost(rec.cameras[cid].model, cov_uv, np.asarray(uv, float)),
                None, [xyz, poses[name], cam_params[cid]])
    if xyz_by_id:
        problem.set_parameter_block_constant(identity)
    if priors is not None:
        cov = np.diag([priors.sigma_h_m ** 2, priors.sigma_h_m ** 2, priors.sigma_v_m ** 2])
        for name, C in priors.C_local.items():
            if name in poses:
                problem.add_residual_block(
                    cf.AbsolutePosePositionPriorCost(cov, np.asarray(C, float)), None,
                    [poses[name]])
    summary = adjuster.solve()
    return _result(summary.ceres_summary, xyz_by_id)


def _result(s, xyz_by_id: dict, velocities: dict | None = None) -> AdjustmentResult:
    """The result of a solved Ceres problem (its summary ``s``)."""
    redundancy = max(s.num_residuals_reduced - s.num_effective_parameters_reduced, 1)
    return AdjustmentResult(
        sigma0=float(np.sqrt(2.0 * s.final_cost / redundancy)),
        iterations=int(s.num_successful_steps + s.num_unsuccessful_steps),
        termination=str(s.termination_type).split(".")[-1],
        residuals=int(s.num_residuals_reduced),
        parameters=int(s.num_effective_parameters_reduced),
        control_xyz_local={k: v.copy() for k, v in xyz_by_id.items()},
        velocities=velocities)
