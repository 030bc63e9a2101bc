"""Georeferencing and the final adjustment of a free (SfM) reconstruction, local frame.

1. A first datum: the camera-position priors (a robust similarity of the SfM camera
   centres onto them) when there are priors, else a similarity on the triangulated
   control points (``gcps`` similarity or bundle), else none (the model stays in SfM's
   arbitrary frame, and ground errors mean nothing).
2. The final bundle adjustment (designer.sfm.adjustment) with the control points
   (``gcps = bundle``), the priors and the calibration mode.
3. ``gcps = similarity``: a 7-parameter similarity on the control points afterwards.
"""

from __future__ import annotations

import numpy as np

from designer.checks.hard_cases import collinear_problem
from designer.errors import DesignerError
from designer.project import model as m
from designer.sfm.adjustment import ControlPoint, PositionPriors, adjust
from designer.sfm.georeference import fit_similarity, triangulate_gcps

#: RANSAC inlier threshold of the GCP similarity, m
GCP_SIMILARITY_MAX_ERROR_M = 0.5


def georeference_and_adjust(rec, p: m.Processing, gcps, marks, control: set[str],
                            flight_C_local: dict, offset: np.ndarray, log, source: str,
                            rolling_shutter: dict | None = None):
    """Adjust ``rec`` (local) in place; (AdjustmentResult, similarity info or None).
    ``rolling_shutter``: the rolling-shutter images to compensate (name → shutter)."""
    by_id = {g.gcp_id: g for g in gcps}
    use_gcps = p.gcps.mode != "none"
    priors = None
    if p.position_prior.mode != "none":
        sh, sv = p.position_prior.sigmas_m
        priors = PositionPriors(dict(flight_C_local), sh, sv)
    sim_info = None
    if priors is not None:
        names = [img.name for img in rec.images.values() if img.has_pose]
        src = np.array([rec.find_image_with_name(n).projection_center() for n in names])
        tgt = np.array([priors.C_local[n] for n in names])
        sim = fit_similarity(src, tgt, 3.0 * max(priors.sigma_h_m, priors.sigma_v_m),
                             "camera positions")
        rec.transform(sim)
        log(f"aligned on {len(names)} camera positions ({p.position_prior.mode})")
    elif use_gcps:
        sim_info = _gcp_similarity(rec, by_id, marks, control, offset, log, source)
    else:
        log("no GCPs and no camera positions: the model keeps its arbitrary frame")

    control_points = []
    if p.gcps.mode == "bundle":
        for gid in sorted(control):
            g = by_id[gid]
            own = tuple((o.image_name, np.asarray(o.uv_px)) for o in marks if o.gcp_id == gid)
            if len(own) >= 1:
                control_points.append(ControlPoint(
                    gid, np.asarray(g.surveyed_xyz) - offset, np.asarray(g.sigma_xyz), own))
        seen = sum(1 for cp in control_points if len(cp.marks) >= 2)
        if priors is None and seen < 3:
            raise DesignerError(f"{source}: only {seen} control GCPs are marked in 2 or more "
                                "images; GCPs in the adjustment need at least 3 (or "
                                "camera-position priors)")
    log(f"bundle adjustment: calibration {p.calibration.mode}, "
        f"{len(control_points)} control points, priors {p.position_prior.mode}"
        + (f", rolling shutter compensated on {len(rolling_shutter)} images"
           if rolling_shutter is not None else ""))
    result = adjust(rec, p.calibration.mode, control_points, p.gcps.marking_sigma_px, priors,
                    rolling_shutter=rolling_shutter)
    log(f"adjusted: sigma0 {result.sigma0:.3f}, {result.iterations} iterations "
        f"({result.termination})")
    if p.gcps.mode == "similarity":
        sim_info = _gcp_similarity(rec, by_id, marks, control, offset, log, source)
    return result, sim_info


def _gcp_similarity(rec, by_id, marks, control, offset, log, source: str) -> dict:
    points, seen = triangulate_gcps(rec, marks)
    used = sorted(g for g in control if g in points)
    if len(used) < 3:
        few = ", ".join(f"{g} in {seen.get(g, 0)} images" for g in sorted(control)
                        if g not in points)
        raise DesignerError(
            f"{source}: only {len(used)} control GCPs are seen in 2 or more registered "
            f"images ({few or 'no other control GCPs'}); georeferencing needs at least 3")
    src = np.array([points[g] for g in used])
    tgt = np.array([by_id[g].surveyed_xyz for g in used]) - offset
    # nearly collinear control leaves the rotation about its line to the noise: RANSAC
    # then returns a similarity silently off by degrees (docs/hard-cases.md)
    problem = collinear_problem(tgt, "control GCPs")
    if problem:
        raise DesignerError(f"{source}: {problem}")
    sim = fit_similarity(src, tgt, GCP_SIMILARITY_MAX_ERROR_M, "control GCPs")
    rec.transform(sim)
    log(f"georeferenced on {len(used)} control GCPs (scale {sim.scale:.6f})")
    return {"scale": float(sim.scale), "control_gcps": used}
