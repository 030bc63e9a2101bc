"""The results of a reconstruction: GCP errors, estimated cameras against the truth, the
files written (``model/``, ``cloud.ply`` = ``sparse.ply``, ``gcp_residuals.csv``) and the
content of ``summary.json`` (designer.sfm.report formats the parts). Errors are
estimated − true, world metres; image residuals and reprojection errors in px.
"""

from __future__ import annotations

import dataclasses
import shutil
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from designer.sfm import report
from designer.sfm.features import Matches
from designer.sfm.georeference import image_residuals_px, translation, triangulate_gcps
from designer.sfm.inputs import SurveyCamera, SurveyInputs, full_opencv
from designer.sfm.mapping import tied_images
from designer.sfm.settings import settings_dict
from designer.sfm.tie_points import AdjustedBlock, mean_reprojection_error_px


@dataclass(frozen=True)
class Evaluated:
    """The block measured against the truth, local frame, before the model is written:
    ``rows`` / ``skipped``: the GCPs triangulated / seen by fewer than two images;
    ``sensors``: the cameras as processing calibrated them, with their start parameters;
    ``tied``: the registered images with tie points; ``est_by_label``: estimated
    FULL_OPENCV parameters by camera label, ``est_params`` those of the first camera;
    ``est_cams`` / ``true_cams``: image name → (centre, world, m; R world → camera)."""

    rows: list[dict]
    skipped: list[dict]
    sensors: list[tuple[SurveyCamera, np.ndarray]]
    tied: set[str]
    est_by_label: dict[str, np.ndarray]
    est_params: np.ndarray
    est_cams: dict
    true_cams: dict


def evaluate_block(rec, inputs: SurveyInputs, block: AdjustedBlock, layout) -> Evaluated:
    """The GCPs triangulated with the final cameras (compensated rolling-shutter images
    each mark from its row's centre), and the cameras estimated against the truth."""
    rolling = inputs.rolling
    moved = None
    if block.adjustment is not None and block.adjustment.velocities is not None:
        moved = {n: (v, rolling[n]) for n, v in block.adjustment.velocities.items()
                 if n in rolling}
    rows, skipped = gcp_rows(rec, inputs.gcps, inputs.marks, inputs.control, inputs.offset,
                             moved)
    cams, offset, truth = inputs.cams, inputs.offset, inputs.truth
    sensors = calibrated_sensors(cams, inputs.starts, layout)
    tied = tied_images(rec)
    est_by_label = estimated_cameras(rec, sensors, tied)
    est_params = est_by_label.get(sensors[0][0].label, cams[0].true_params) \
        if len(sensors) > 1 else full_opencv(next(iter(rec.cameras.values())))
    est_cams = {img.name: (img.projection_center() + offset,
                           img.cam_from_world().rotation.matrix())
                for img in rec.images.values() if img.name in tied}
    true_cams = {n: (inputs.true_C[n] + offset,
                     truth.find_image_with_name(n).cam_from_world().rotation.matrix())
                 for n in inputs.names}
    return Evaluated(rows, skipped, sensors, tied, est_by_label, est_params, est_cams,
                     true_cams)


@dataclass(frozen=True)
class Written:
    """The files a reconstruction wrote: the COLMAP text model's folder, the tie-point
    cloud (also copied to ``sparse.ply``) and the GCP residuals."""

    model_dir: Path
    cloud_ply: Path
    gcp_residuals_csv: Path


def write_model(rec, offset: np.ndarray, rows: list[dict], out: Path) -> Written:
    """``rec`` moved to the world frame (in place: world = local + ``offset``) and written
    into ``out`` with its tie-point cloud (doubles) and the GCP residuals."""
    rec.transform(translation(offset))
    model_dir = out / "model"
    model_dir.mkdir(exist_ok=True)
    rec.write_text(str(model_dir))
    cloud = out / "cloud.ply"
    report.write_cloud_ply(rec, cloud, np.zeros(3))
    shutil.copyfile(cloud, out / "sparse.ply")
    residuals = out / "gcp_residuals.csv"
    report.write_gcp_residuals(rows, residuals)
    return Written(model_dir, cloud, residuals)


def summary_of(rec, inputs: SurveyInputs, evaluated: Evaluated, block: AdjustedBlock, layout,
               matches: Matches, reused: dict, timings: dict) -> dict:
    """The content of summary.json for the world-frame model ``rec`` (the dense section
    off; designer.sfm.dense_stage adds it)."""
    e, p, cams = evaluated, inputs.processing, inputs.cams
    rows, est_cams = e.rows, e.est_cams
    return {
        "mode": inputs.mode, "images": len(inputs.names), "registered": len(e.tied),
        "points": rec.num_points3D(),
        "mean_reprojection_error_px": mean_reprojection_error_px(rec, block.errors),
        "settings": settings_dict(p), "local_offset_m": inputs.offset.tolist(),
        "control": report.rmse_stats([r for r in rows if r["role"] == "control"]),
        "check": report.rmse_stats([r for r in rows if r["role"] == "check"]),
        "gcps_not_triangulated": e.skipped,
        "intrinsics": report.intrinsics_report(e.est_params, cams[0].true_params,
                                               inputs.starts[0], cams[0].size_px),
        "intrinsics_by_camera": {
            c.label: {"camera_id": c.truth_id, "images": len(c.names),
                      "registered": sum(1 for n in c.names if n in est_cams),
                      **report.intrinsics_report(e.est_by_label.get(c.label, start),
                                                 c.true_params, start, c.size_px)}
            for c, start in e.sensors},
        "rigs": None if layout is None or not layout.frames else {
            name: {"stations": len(frames), "relative_orientation": "fixed",
                   "stations_registered": sum(
                       1 for f in frames.values() if any(n in est_cams for n in f.values()))}
            for name, frames in layout.frames.items()},
        "cameras": report.camera_errors(est_cams, e.true_cams),
        "adjustment": None if block.adjustment is None else block.adjustment.as_dict(),
        "tie_points": block.tie, "pairs": len(matches.pairs), "reused_from_cache": reused,
        "similarity": block.similarity, "gcps": rows, "timings": timings,
        "stage_seconds": timings,
        "dense": {"mode": p.dense, "status": "off", "dome_amplitude_m": None},
    }


def gcp_rows(rec, gcps, marks, control: set[str], offset, rolling=None):
    """One row per GCP seen in ≥ 2 registered images (triangulated from its marks with
    the final cameras; compensated rolling-shutter images: each mark from its row's
    centre), and the ids seen by fewer."""
    points, seen = triangulate_gcps(rec, marks, rolling)
    rows, skipped = [], []
    for g in gcps:
        if g.gcp_id not in points:
            skipped.append({"id": g.gcp_id, "images": seen.get(g.gcp_id, 0)})
            continue
        local = points[g.gcp_id]
        own = [(o.image_name, o.uv_px) for o in marks if o.gcp_id == g.gcp_id]
        px = image_residuals_px(rec, local, own)
        estimated = local + offset
        d = estimated - g.true_xyz
        rows.append({"id": g.gcp_id, "role": "control" if g.gcp_id in control else "check",
                     "images": seen[g.gcp_id], "estimated": [float(v) for v in estimated],
                     "dx_m": float(d[0]), "dy_m": float(d[1]), "dz_m": float(d[2]),
                     "image_residuals_px": px.tolist()})
    return rows, skipped


def calibrated_sensors(cams: list[SurveyCamera], starts: list,
                       layout) -> list[tuple[SurveyCamera, object]]:
    """The cameras as processing calibrates them, each with its start parameters: a
    survey camera, or for a camera carried by several mounts of a rig one per mount
    (labelled ``camera suffix``; designer.sfm.rigs)."""
    out = []
    for c, start in zip(cams, starts, strict=True):
        by_sensor: dict[str, list[str]] = {}
        for n in c.names:
            by_sensor.setdefault(layout.sensor_of.get(n, c.label) if layout else c.label,
                                 []).append(n)
        if len(by_sensor) == 1:
            out.append((c, start))
            continue
        out.extend((dataclasses.replace(c, label=label, names=tuple(own)), start)
                   for label, own in by_sensor.items())
    return out


def estimated_cameras(rec, sensors, tied: set[str]) -> dict[str, np.ndarray]:
    """Estimated FULL_OPENCV parameters by camera label (cameras with an image in ``tied``,
    the registered images with tie points of their own)."""
    label = {n: c.label for c, _ in sensors for n in c.names}
    out = {}
    for img in rec.images.values():
        if img.name in tied and img.name in label and label[img.name] not in out:
            out[label[img.name]] = full_opencv(rec.cameras[img.camera_id])
    return out


def gsd_m(inputs: SurveyInputs, rec) -> float:
    """Median ground sample distance (m) of the first camera over the world-frame model
    ``rec``: camera height over the median tie-point height, divided by the focal length
    in pixels (nadir approximation)."""
    C = np.array([img.projection_center() for img in inputs.truth.images.values()]) \
        + inputs.offset
    if rec.num_points3D():
        ground = float(np.median([p.xyz[2] for p in rec.points3D.values()]))
    else:
        ground = float(np.min(C[:, 2])) - 100.0
    return float(np.median(np.abs(C[:, 2] - ground)) / inputs.cams[0].camera.focal_length_x)
