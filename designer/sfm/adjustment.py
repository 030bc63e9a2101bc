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

With rolling-shutter compensation (``rolling_shutter`` given) the problem is solved by
designer.sfm.rolling_adjustment instead (vectorised, not a Ceres problem), with the same
observations, weights, priors and gauge — the images, stations, camera parameters,
priors and gauge come from one set-up, designer.sfm.block_setup — plus each
rolling-shutter image's velocity during its readout.

Everything is in the local frame (world − offset, float64). Tie points are weighted
with σ = 1 px, so σ₀ is the a-posteriori standard deviation of unit weight in px.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from designer.sfm.block_setup import (
    constant_params,
    posed_images,
    prior_sigmas_m,
    reprojection_cost,
    station_priors,
)
from designer.sfm.control_costs import add_control_points
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
    #: rolling-shutter compensation: each tie point's reprojection errors (px) with the
    #: compensation (COLMAP's own errors ignore it)
    point_errors_px: dict[int, list[float]] | None = None

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
        return _result(solution.summary, xyz, solution.velocities, solution.point_errors_px)
    options = pycolmap.BundleAdjustmentOptions()
    options.refine_focal_length = options.refine_principal_point = bool(variable)
    options.refine_extra_params = bool(variable)
    options.refine_sensor_from_rig = False  # a rig's calibration is known
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
            problem.set_manifold(params, pyceres.SubsetManifold(
                len(params), constant_params(variable, len(params))))
    # a station's pose (rig_from_world) is COLMAP's block, shared by the rig's images
    images = {n: im for n, im in posed_images(rec).items()
              if problem.has_parameter_block(rec.frames[im.frame_id].rig_from_world.params)}
    poses = {f: rec.frames[f].rig_from_world.params for f in {im.frame_id
                                                              for im in images.values()}}

    def add_mark(xyz, name, uv, cov_uv):
        image = images[name]
        problem.add_residual_block(
            reprojection_cost(rec.cameras[image.camera_id], cov_uv, uv, image), None,
            [xyz, poses[image.frame_id], cam_params[image.camera_id]])

    xyz_by_id = add_control_points(problem, control, images.__contains__, add_mark,
                                   max(marking_sigma_px, MIN_MARKING_SIGMA_PX),
                                   MIN_GCP_SIGMA_M, keep_alive)
    if priors is not None:
        cov = np.diag(prior_sigmas_m(priors) ** 2)
        frame_of = {n: im.frame_id for n, im in images.items()}
        for f, C in station_priors(priors, frame_of.get):
            problem.add_residual_block(cf.AbsolutePosePositionPriorCost(cov, C), None,
                                       [poses[f]])
    summary = adjuster.solve()
    return _result(summary.ceres_summary, xyz_by_id)


def _result(s, xyz_by_id: dict, velocities: dict | None = None,
            point_errors_px: dict | None = None) -> AdjustmentResult:
    """The result of a solved Ceres problem (its summary ``s``)."""
    redundancy = max(s.num_residuals_reduced - s.num_effective_parameters_reduced, 1)
    return AdjustmentResult(
        sigma0=float(np.sqrt(2.0 * s.final_cost / redundancy)),
        iterations=int(s.num_successful_steps + s.num_unsuccessful_steps),
        termination=str(s.termination_type).split(".")[-1],
        residuals=int(s.num_residuals_reduced),
        parameters=int(s.num_effective_parameters_reduced),
        control_xyz_local={k: v.copy() for k, v in xyz_by_id.items()},
        velocities=velocities, point_errors_px=point_errors_px)
