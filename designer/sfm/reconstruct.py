"""Reconstruct a rendered survey with COLMAP (pycolmap) as a practitioner processes it.

Input: an output folder of ``designer render`` (``images/`` + ``ground-truth/``); the
processing settings are the project's ``<processing>`` (designer.sfm.settings) with
command-line overrides. Modes:

* ``known-poses`` — the ideal case: SIFT features and matches, then triangulation with
  the true interior and exterior orientations (nothing is estimated but points);
* ``free`` — incremental SfM from the images (starting from the pre-calibration), a
  track-length filter, a first datum (camera-position priors or a similarity on the
  control points), then the final bundle adjustment (designer.sfm.adjustment): control
  points and camera positions as weighted observations, the interior orientation
  estimated as the calibration mode says. With ``gcps = similarity`` a 7-parameter
  similarity on the control points follows the adjustment instead.

Several cameras (a rig, or flights with different cameras): each ground-truth CAMERA_ID
is its own database camera with its own interior orientation (true in ``known-poses``,
its own pre-calibration and self-calibration in ``free``). In ``free`` mode a rig of the
project is a COLMAP rig (designer.sfm.rigs): one database camera per mount (its own
self-calibration), one frame per station, the mounts' relative orientation fixed at the
project's values, so a station has one pose.

Check points are marked (with the same marking error) but only triangulated with the
final cameras, never used. Everything is computed in a local frame (world − offset,
offset = the rounded mean camera centre) in float64; outputs are in world coordinates:
``summary.json``, ``sparse.ply`` (= ``cloud.ply``, doubles), ``gcp_residuals.csv``,
``model/`` (COLMAP text model). Dense matching is another stage (``dense`` setting).
"""

from __future__ import annotations

import contextlib
import copy
import json
import shutil
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from designer.atomic import write_text_atomic
from designer.core.layout import GROUND_TRUTH_DIR, images_dir
from designer.errors import DesignerError
from designer.export.colmap_read import model_offset_world
from designer.export.tables import read_gcp_observations_csv, read_gcp_truth_csv
from designer.project import model as m
from designer.sfm import report
from designer.sfm.feature_cache import FeatureCache, images_digest
from designer.sfm.feature_cache import key as fc_key
from designer.sfm.georeference import (
    image_residuals_px,
    translation,
    triangulate_gcps,
)
from designer.sfm.settings import (
    control_ids,
    flight_positions,
    marked_observations,
    settings_dict,
    start_params,
)
from designer.survey import pairs as matching

MODES = ("known-poses", "free")
#: tie points whose mean reprojection error exceeds this after the adjustment are outliers
OUTLIER_PX = 4.0


@dataclass(frozen=True)
class ReconstructionResult:
    out_dir: Path
    mode: str
    n_images: int
    n_registered: int
    n_points: int
    cloud_ply: Path
    gcp_residuals_csv: Path
    summary: dict


def _log_default(message: str) -> None:
    print(message, flush=True)


def check_survey_folder(survey: Path) -> tuple[Path, Path, list[str]]:
    """The ground-truth COLMAP folder, the images folder and the names of the images present
    of a rendered survey (an output folder of 'designer render', :mod:`designer.core.layout`;
    one in the old layout, images at its top level, too), or a clear error."""
    survey = Path(survey)
    gt = survey / GROUND_TRUTH_DIR / "colmap"
    if not (gt / "images.txt").is_file() or not (gt / "cameras.txt").is_file():
        raise DesignerError(
            f"{survey}: no ground truth (ground-truth/colmap/images.txt); give the output "
            "folder of 'designer render' with its colmap ground truth")
    names = []
    for line in (gt / "images.txt").read_text().splitlines():
        parts = line.split()
        if len(parts) >= 10 and not line.startswith("#") and parts[0].isdigit():
            names.append(parts[9])
    folder = images_dir(survey)
    present = [n for n in names if (folder / n).is_file()]
    if len(present) < 3:
        raise DesignerError(
            f"{folder}: {len(present)} of {len(names)} images are present; at least 3 "
            "overlapping images are needed (render them first, or finish with --resume)")
    return gt, folder, present


@dataclass(frozen=True)
class SurveyCamera:
    """One physical camera of a survey: its ground-truth CAMERA_ID, designer camera id
    (``label``), the true pycolmap camera, its FULL_OPENCV parameters, and the names of
    the present images it took."""

    truth_id: int
    label: str
    camera: object
    true_params: np.ndarray
    names: tuple[str, ...]

    @property
    def size_px(self) -> tuple[int, int]:
        return (int(self.camera.width), int(self.camera.height))


def survey_cameras(truth, names: list[str], gt_dir: Path) -> list[SurveyCamera]:
    """The cameras that took the present images, by ground-truth CAMERA_ID (each camera
    of a rig its own interior orientation), named as the ground truth's comment names
    them (``# designer cameras: 1 = nadir, 2 = oblique``)."""
    labels = _camera_labels(gt_dir / "cameras.txt")
    by_id: dict[int, list[str]] = {}
    for n in names:
        by_id.setdefault(int(truth.find_image_with_name(n).camera_id), []).append(n)
    return [SurveyCamera(cid, labels.get(cid, f"camera {cid}"), truth.cameras[cid],
                         _full_opencv(truth.cameras[cid]), tuple(own))
            for cid, own in sorted(by_id.items())]


def _camera_labels(cameras_txt: Path) -> dict[int, str]:
    for line in cameras_txt.read_text().splitlines():
        if line.startswith("# designer cameras:"):
            pairs = (item.split("=", 1) for item in line.split(":", 1)[1].split(","))
            return {int(k): v.strip() for k, v in pairs if k.strip().isdigit()}
    return {}


def _full_opencv(camera) -> np.ndarray:
    """The true camera's parameters in FULL_OPENCV order."""
    params = np.zeros(12)
    p = np.asarray(camera.params, float)
    name = camera.model.name
    if name == "PINHOLE":
        params[:4] = p
    elif name == "OPENCV":
        params[:8] = p
    elif name == "FULL_OPENCV":
        params[:] = p
    else:
        raise DesignerError(f"camera model {name}: processing supports pinhole and "
                            "Brown–Conrady cameras; use a brown-conrady distortion")
    return params


def reconstruct(
    survey_dir: Path,
    out_dir: Path,
    mode: str = "known-poses",
    max_features: int | None = None,
    log: Callable[[str], None] = _log_default,
    processing: m.Processing | None = None,
    project_path: Path | None = None,
    dense_max_image_px: int | None = None,
    feature_cache: Path | None = None,
    rigs: list | None = None,
) -> ReconstructionResult:
    """Features, matching, SfM or triangulation, adjustment; write model, cloud, report;
    with ``dense`` on, the dense cloud, DSM and DEM of difference (designer.sfm.dense_stage;
    ``project_path`` gives the true surface, default: the project the survey names).
    ``feature_cache``: a folder where features and matches are kept and reused by
    reconstructions of the same images (designer.sfm.feature_cache). ``rigs``: the
    designer.sfm.rigs.ProcessingRig list whose relative orientation ``free`` mode fixes
    (default: the rigs of the project, when it is found)."""
    import pycolmap

    if mode not in MODES:
        raise DesignerError(f"--mode {mode!r}: use one of {', '.join(MODES)}")
    survey, out = Path(survey_dir), Path(out_dir)
    gt_dir, image_dir, names = check_survey_folder(survey)
    p = processing or m.Processing()
    rolling = None
    if p.calibration.rolling_shutter == "compensate":
        from designer.sfm.rolling_adjustment import check_compensation, read_rolling_shutter_truth

        if mode != "free":
            raise DesignerError(f"--rolling-shutter compensate with --mode {mode}: the "
                                "compensation is part of the bundle adjustment; use --mode "
                                "free (or --rolling-shutter none)")
        rolling = read_rolling_shutter_truth(survey)
        check_compensation(rolling, names, survey)
    if max_features is not None:
        p = m.Processing(p.calibration, p.gcps, p.position_prior,
                         m.Matching(max_features, p.matching.pairs, p.matching.min_track_length),
                         p.dense, p.sfm)
    truth = pycolmap.Reconstruction(str(gt_dir))
    # Work in a local frame (world − offset): no UTM-sized numbers reach COLMAP. The
    # ground truth is world − written (offset.json; zeros for a world-frame model); the
    # offset is the mean camera centre rounded to metres, as the render's default.
    written = model_offset_world(gt_dir)
    offset = np.round(np.mean([img.projection_center() for img in truth.images.values()],
                              axis=0) + written)
    if np.any(offset != written):
        truth.transform(translation(written - offset))
    cams = survey_cameras(truth, names, gt_dir)
    true_camera, true_params, size_px = cams[0].camera, cams[0].true_params, cams[0].size_px
    # each camera its own pre-calibration error (the seed + its index: camera 1 as before)
    starts = [start_params(c.true_params, _pre_error(p.calibration.pre_calibration_error, k))
              if mode == "free" else c.true_params for k, c in enumerate(cams)]
    params0 = starts[0]
    if len(cams) > 1:
        log(f"{len(cams)} cameras: " + ", ".join(f"{c.label} ({len(c.names)} images)"
                                                 for c in cams))
    gcps, marks = _gcp_inputs(survey, p)
    control = control_ids(gcps, p.gcps.control)
    true_C = {n: truth.find_image_with_name(n).projection_center() for n in names}
    sh, sv = p.position_prior.sigmas_m if p.position_prior.mode != "none" else (2.5, 5.0)
    measured = flight_positions(np.array([true_C[n] for n in names]), sh, sv,
                                p.position_prior.seed)
    flight_C = dict(zip(names, measured, strict=True))  # local frame, m

    out.mkdir(parents=True, exist_ok=True)
    timings: dict[str, float] = {}
    t = time.perf_counter()
    db_path = out / "database.db"
    db_path.unlink(missing_ok=True)
    readers = [_reader(pycolmap, c, start, mode) for c, start in zip(cams, starts, strict=True)]
    reader = readers[0]
    cache = FeatureCache(feature_cache) if feature_cache is not None else None
    camera_key = (reader.camera_model, reader.camera_params) if len(cams) == 1 else \
        ("rig", repr([(c.names, r.camera_model, r.camera_params)
                      for c, r in zip(cams, readers, strict=True)]))
    feature_key = fc_key("features", images_digest(image_dir, names), *camera_key,
                         p.matching.max_features) if cache else ""
    with cache.hold("features", feature_key) if cache else contextlib.nullcontext():
        reused = {"features": bool(cache) and cache.fetch("features", feature_key, db_path)}
        if not reused["features"]:
            log(f"features: {len(names)} images")
            for c, r in zip(cams, readers, strict=True):  # one database camera per camera
                _extract(pycolmap, db_path, image_dir,
                         names if len(cams) == 1 else list(c.names), r,
                         p.matching.max_features)
            if cache:
                cache.store("features", feature_key, db_path)
    timings["features_s"] = time.perf_counter() - t

    t = time.perf_counter()
    K_size = {n: (start, c.size_px) for c, start in zip(cams, starts, strict=True)
              for n in c.names}
    pairs = _pairs(p.matching.pairs, names, truth, flight_C, K_size, gcps, offset)
    if not pairs:
        raise DesignerError(f"{survey}: no two images overlap (by their predicted footprints); "
                            "the images do not overlap enough for a reconstruction")
    pairs_text = "".join(f"{a} {b}\n" for a, b in pairs)
    pairs_file = out / "pairs.txt"
    write_text_atomic(pairs_file, pairs_text)
    match_key = fc_key("matches", feature_key, pairs_text) if cache else ""
    with cache.hold("matches", match_key) if cache else contextlib.nullcontext():
        reused["matches"] = bool(cache) and cache.fetch("matches", match_key, db_path)
        if not reused["matches"]:
            log(f"matching: {len(pairs)} image pairs ({p.matching.pairs})")
            _match(pycolmap, db_path, pairs_file)
            if cache:
                cache.store("matches", match_key, db_path)
    timings["matching_s"] = time.perf_counter() - t

    layout = None
    if mode == "free":
        layout = _apply_rigs(pycolmap, db_path, cams, rigs, project_path, survey, log)
    t = time.perf_counter()
    sparse = out / "sparse"
    if sparse.exists():
        shutil.rmtree(sparse)
    sparse.mkdir()
    if mode == "known-poses":
        log("triangulating with the true poses")
        rec = _known_pose_reconstruction(pycolmap, truth, db_path)
        rec = pycolmap.triangulate_points(rec, db_path, image_dir, sparse)
    else:
        # the mapper's model depends on the matches, the interior it refines, the mapper
        # and the rig layout: runs that differ only after SfM share it
        sfm_key = fc_key("sfm", match_key, p.calibration.mode, p.sfm.mapper,
                         repr(None if layout is None else sorted(layout.frames.items()))
                         ) if cache else ""
        with cache.hold("sfm", sfm_key) if cache else contextlib.nullcontext():
            reused["sfm"] = bool(cache) and cache.fetch_model(sfm_key, sparse / "cached")
            if reused["sfm"]:
                log("SfM model reused from the feature cache")
                rec = pycolmap.Reconstruction(str(sparse / "cached"))
            elif p.sfm.mapper == "global":
                log("global SfM (rotation averaging, global positioning)")
                rec = _global(pycolmap, db_path, image_dir, sparse, p.calibration.mode)
            else:
                log("incremental SfM")
                rec = _incremental(pycolmap, db_path, image_dir, sparse, p.calibration.mode)
            if cache and not reused["sfm"]:
                cache.store_model(sfm_key, rec)
        _check_every_camera_registered(rec, cams, survey)
    timings["reconstruction_s"] = time.perf_counter() - t

    t = time.perf_counter()
    tie = {"points_before_filters": rec.num_points3D()}
    tie["removed_short_tracks"] = _drop_short_tracks(rec, p.matching.min_track_length)
    adjustment = None
    sim_info = None
    if mode == "free":
        from designer.sfm import process_free

        adjustment, sim_info = process_free.georeference_and_adjust(
            rec, p, gcps, marks, control, flight_C, offset, log, str(survey),
            rolling_shutter=rolling)
    errors = adjustment.point_errors_px if adjustment is not None else None
    tie["removed_outliers"] = _drop_outliers(rec, OUTLIER_PX, errors)
    tie["points"] = rec.num_points3D()
    tie["mean_track_length"] = float(rec.compute_mean_track_length()) if rec.num_points3D() \
        else 0.0
    timings["adjustment_s"] = time.perf_counter() - t

    moved = None
    if adjustment is not None and adjustment.velocities is not None:
        moved = {n: (v, rolling[n]) for n, v in adjustment.velocities.items() if n in rolling}
    rows, skipped = _gcp_rows(rec, gcps, marks, control, offset, moved)
    sensors = _sensors(cams, starts, layout)
    tied = tied_images(rec)
    est_by_label = _estimated_cameras(rec, sensors, tied)
    est_params = est_by_label.get(sensors[0][0].label, true_params) if len(sensors) > 1 \
        else _full_opencv(next(iter(rec.cameras.values())))
    est_cams = {img.name: (img.projection_center() + offset,
                           img.cam_from_world().rotation.matrix())
                for img in rec.images.values() if img.name in tied}
    true_cams = {n: (true_C[n] + offset,
                     truth.find_image_with_name(n).cam_from_world().rotation.matrix())
                 for n in names}
    rec.transform(translation(offset))
    model_dir = out / "model"
    model_dir.mkdir(exist_ok=True)
    rec.write_text(str(model_dir))
    cloud = out / "cloud.ply"
    report.write_cloud_ply(rec, cloud, np.zeros(3))
    shutil.copyfile(cloud, out / "sparse.ply")
    residuals = out / "gcp_residuals.csv"
    report.write_gcp_residuals(rows, residuals)
    summary = {
        "mode": mode, "images": len(names), "registered": len(tied),
        "points": rec.num_points3D(),
        "mean_reprojection_error_px": _mean_reprojection_error_px(rec, errors),
        "settings": settings_dict(p), "local_offset_m": offset.tolist(),
        "control": report.rmse_stats([r for r in rows if r["role"] == "control"]),
        "check": report.rmse_stats([r for r in rows if r["role"] == "check"]),
        "gcps_not_triangulated": skipped,
        "intrinsics": report.intrinsics_report(est_params, true_params, params0, size_px),
        "intrinsics_by_camera": {
            c.label: {"camera_id": c.truth_id, "images": len(c.names),
                      "registered": sum(1 for n in c.names if n in est_cams),
                      **report.intrinsics_report(est_by_label.get(c.label, start),
                                                 c.true_params, start, c.size_px)}
            for c, start in sensors},
        "rigs": None if layout is None or not layout.frames else {
            name: {"stations": len(frames), "relative_orientation": "fixed",
                   "stations_registered": sum(
                       1 for f in frames.values() if any(n in est_cams for n in f.values()))}
            for name, frames in layout.frames.items()},
        "cameras": report.camera_errors(est_cams, true_cams),
        "adjustment": None if adjustment is None else adjustment.as_dict(),
        "tie_points": tie, "pairs": len(pairs), "reused_from_cache": reused,
        "similarity": sim_info, "gcps": rows, "timings": timings, "stage_seconds": timings,
        "dense": {"mode": p.dense, "status": "off", "dome_amplitude_m": None},
    }
    from designer.sfm.settings import project_of_survey

    truth_project = project_path or project_of_survey(survey)
    gsd_m = _gsd_m(truth, true_camera, offset, rec)
    summary["sparse_dome"] = _sparse_dome(rec, truth_project, gsd_m, log)
    if p.dense != "none":
        from designer.sfm.dense_stage import run_dense_stage

        dense = run_dense_stage(survey, out, model_dir, truth_project,
                                offset, gsd_m, max_image_size_px=dense_max_image_px, log=log)
        summary["dense"] = {"mode": p.dense, **dense}
        timings["dense_s"] = dense["dense_s"]
        timings["rasters_s"] = dense["rasters_s"]
    write_text_atomic(out / "summary.json", json.dumps(summary, indent=1))
    log(f"{len(tied)}/{len(names)} images registered, {rec.num_points3D()} points")
    return ReconstructionResult(out, mode, len(names), len(tied),
                                rec.num_points3D(), cloud, residuals, summary)


def _sparse_dome(rec, project_path: Path | None, gsd_m: float, log) -> dict | None:
    """The dome of the tie points (world frame) over the survey area
    (designer.sfm.dome), or None without the project or with too few points."""
    if project_path is None or not Path(project_path).is_file():
        return None
    from designer.sfm.dome import sparse_dome

    points = np.array([pt.xyz for pt in rec.points3D.values()]).reshape(-1, 3)
    try:
        dome = sparse_dome(points, project_path, gsd_m)
    except DesignerError as error:
        log(f"tie-point dome not measured: {error}")
        return None
    if dome is not None:
        log(f"tie points: {dome['kind']} {dome['amplitude_m']:+.4f} m "
            f"({dome['amplitude_gsd']:+.2f} GSD) over {dome['area']}")
    return dome


def _pre_error(pre, index: int):
    """The pre-calibration error of the ``index``-th camera: its own draw (seed + index)."""
    if pre is None or index == 0:
        return pre
    import dataclasses

    return dataclasses.replace(pre, seed=pre.seed + index)


def _reader(pycolmap, camera: SurveyCamera, start: np.ndarray, mode: str):
    reader = pycolmap.ImageReaderOptions()
    if mode == "free":
        reader.camera_model = "FULL_OPENCV"
        reader.camera_params = ",".join(repr(float(v)) for v in start)
    else:  # the true camera, exactly as the ground truth states it
        reader.camera_model = camera.camera.model.name
        reader.camera_params = ",".join(repr(float(v)) for v in camera.camera.params)
    return reader


def tied_images(rec) -> set[str]:
    """The names of the registered images that observe a tie point. An image of a rig
    has a pose as soon as its station is registered; it counts only when its own features
    joined the reconstruction."""
    return {img.name for img in rec.images.values()
            if img.has_pose and img.num_points3D > 0}


def _sensors(cams: list[SurveyCamera], starts: list, layout) -> list[tuple[SurveyCamera, object]]:
    """The cameras as processing calibrates them, each with its start parameters: a
    survey camera, or for a camera carried by several mounts of a rig one per mount
    (labelled ``camera suffix``; designer.sfm.rigs)."""
    import dataclasses

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


def _apply_rigs(pycolmap, db_path: Path, cams: list[SurveyCamera], rigs, project_path,
                survey: Path, log):
    """The project's rigs written into the database (designer.sfm.rigs), or None."""
    from designer.sfm import rigs as rig_model

    if rigs is None:
        from designer.project.load import load_project
        from designer.sfm.settings import project_of_survey

        path = project_path or project_of_survey(survey)
        if path is None:
            if len(cams) > 1:
                log("the project is not found: a rig's images are each posed alone")
            return None
        rigs = rig_model.processing_rigs(load_project(path, check_files=False))
    if not rigs:
        return None
    # a one-camera survey's ground truth does not name its camera: its images match a
    # mount by suffix alone
    named = {c.label for c in cams} & {s.camera_label for r in rigs for s in r.sensors}
    layout = rig_model.apply_rigs(pycolmap, db_path, rigs,
                                  {n: c.label if named else None for c in cams for n in c.names})
    for name, frames in layout.frames.items():
        log(f"rig {name}: {len(frames)} stations, the mounts' relative orientation fixed")
    return layout


def _estimated_cameras(rec, sensors, tied: set[str]) -> dict[str, np.ndarray]:
    """Estimated FULL_OPENCV parameters by camera label (cameras with an image in ``tied``,
    the registered images with tie points of their own)."""
    label = {n: c.label for c, _ in sensors for n in c.names}
    out = {}
    for img in rec.images.values():
        if img.name in tied and img.name in label and label[img.name] not in out:
            out[label[img.name]] = _full_opencv(rec.cameras[img.camera_id])
    return out


def _check_every_camera_registered(rec, cams: list[SurveyCamera], survey: Path) -> None:
    """A camera none of whose images joined the reconstruction (a rig whose cameras see
    nothing in common) is a clear error, not a survey of the other cameras."""
    if len(cams) == 1:
        return
    registered = tied_images(rec)
    lost = [c for c in cams if not registered.intersection(c.names)]
    if lost:
        what = ", ".join(f"{c.label!r} ({len(c.names)} images)" for c in lost)
        raise DesignerError(
            f"{survey}: no image of camera {what} registered with the other cameras' "
            "images: the rig's cameras see nothing in common; fly the rig so that each "
            "camera's footprints overlap another camera's (tilt the obliques less, raise the "
            "overlaps) or process each camera's images as a survey of their own")


def _extract(pycolmap, db_path: Path, image_dir: Path, names: list[str], reader,
             max_features: int) -> None:
    extraction = pycolmap.FeatureExtractionOptions()
    extraction.sift.max_num_features = max_features
    extraction.use_gpu = False
    pycolmap.extract_features(db_path, image_dir, image_names=names,
                              camera_mode=pycolmap.CameraMode.SINGLE, reader_options=reader,
                              extraction_options=extraction, device=pycolmap.Device.cpu)


def _match(pycolmap, db_path: Path, pairs_file: Path) -> None:
    pairing = pycolmap.ImportedPairingOptions()
    pairing.match_list_path = str(pairs_file)
    match_options = pycolmap.FeatureMatchingOptions()
    match_options.use_gpu = False
    pycolmap.match_image_pairs(db_path, matching_options=match_options,
                               pairing_options=pairing, device=pycolmap.Device.cpu)


def _gsd_m(truth, camera, offset: np.ndarray, rec) -> float:
    """Median ground sample distance (m): camera height over the median tie-point height,
    divided by the focal length in pixels (nadir approximation)."""
    C = np.array([img.projection_center() for img in truth.images.values()]) + offset
    if rec.num_points3D():
        ground = float(np.median([p.xyz[2] for p in rec.points3D.values()]))
    else:
        ground = float(np.min(C[:, 2])) - 100.0
    return float(np.median(np.abs(C[:, 2] - ground)) / camera.focal_length_x)


def _gcp_inputs(survey: Path, p: m.Processing):
    gt = survey / GROUND_TRUTH_DIR
    if not (gt / "gcp_truth.csv").is_file():
        return [], []
    gcps = read_gcp_truth_csv(gt / "gcp_truth.csv")
    observations = read_gcp_observations_csv(gt / "gcp_observations.csv")
    return gcps, marked_observations(observations, p.gcps.marking_sigma_px, p.gcps.seed)


def _pairs(kind, names, truth, flight_C, K_size, gcps, offset):
    """Image pairs to match; ``K_size``: image name → (its camera's FULL_OPENCV start
    parameters, (W, H) px)."""
    C_local = np.array([flight_C[n] for n in names])
    if kind == "exhaustive":
        return matching.exhaustive_pairs(names)
    if kind == "position":
        return matching.neighbour_pairs(names, C_local)
    ground = (float(np.median([g.true_xyz[2] for g in gcps])) - offset[2] if gcps
              else float(np.min(C_local[:, 2])) - 50.0)
    feet = [matching.footprint_xy(C, truth.find_image_with_name(n).cam_from_world()
                                  .rotation.matrix(), tuple(K_size[n][0][:4]), K_size[n][1],
                                  ground)
            for n, C in zip(names, C_local, strict=True)]
    return matching.footprint_pairs(names, feet)


def _incremental(pycolmap, db_path, image_dir, sparse, calibration: str):
    options = pycolmap.IncrementalPipelineOptions()
    options.num_threads = -1
    options.random_seed = 0  # RANSAC and the mapper's choices seeded: runs repeat closer
    options.ba_refine_sensor_from_rig = False  # a rig's calibration is known (designer.sfm.rigs)
    # Nadir survey images have small baselines: the default 16° initial triangulation
    # angle rejects every pair of a typical 80 % overlap flight.
    options.mapper.init_min_tri_angle = 4.0
    options.mapper.init_min_num_inliers = 50
    (options.ba_refine_focal_length, options.ba_refine_principal_point,
     options.ba_refine_extra_params) = mapper_refines(calibration)
    maps = pycolmap.incremental_mapping(db_path, image_dir, sparse, options=options)
    if not maps:
        raise DesignerError(
            f"{image_dir}: COLMAP could not start a reconstruction: the images do not "
            "overlap enough or show too little texture")
    return max(maps.values(), key=lambda r: r.num_reg_images())


def mapper_refines(calibration: str) -> tuple[bool, bool, bool]:
    """(focal length, principal point, distortion) the mapper's own adjustments refine
    for the calibration mode: at most the focal length (COLMAP's own default); the
    principal point and distortion are estimated in the final adjustment, with exactly
    the mode's terms. A principal point refined while a flat block grows drifts with the
    few images registered so far, and the next images then fail to register."""
    return calibration != "fixed", False, False


def _global(pycolmap, db_path, image_dir, sparse, calibration: str):
    """GLOMAP's global SfM (pycolmap.global_mapping): rotation averaging, global
    positioning, one bundle adjustment, refining the interior as the incremental mapper
    does (distortion in the final adjustment, with exactly the mode's terms)."""
    options = pycolmap.GlobalPipelineOptions()
    options.num_threads = -1
    options.random_seed = 0  # the same images give the same model
    ba = options.mapper.bundle_adjustment
    ba.refine_focal_length, ba.refine_principal_point, ba.refine_extra_params = \
        mapper_refines(calibration)
    ba.refine_sensor_from_rig = False  # a rig's calibration is known (designer.sfm.rigs)
    maps = pycolmap.global_mapping(db_path, image_dir, sparse, options=options)
    if not maps:
        raise DesignerError(
            f"{image_dir}: COLMAP's global mapper found no reconstruction: the images do not "
            "overlap enough or show too little texture")
    return max(maps.values(), key=lambda r: r.num_reg_images())


def _drop_short_tracks(rec, min_length: int) -> int:
    short = [pid for pid, pt in rec.points3D.items() if pt.track.length() < min_length]
    for pid in short:
        rec.delete_point3D(pid)
    return len(short)


def _drop_outliers(rec, max_px: float, errors: dict | None = None) -> int:
    """Delete the tie points whose mean reprojection error exceeds ``max_px``: COLMAP's
    errors, or with rolling-shutter compensation ``errors`` (point id → the errors of its
    observations with the compensation, designer.sfm.rolling_adjustment)."""
    if errors is None:
        rec.update_point_3d_errors()
        bad = [pid for pid, pt in rec.points3D.items() if pt.error > max_px]
    else:
        bad = [pid for pid in rec.points3D if pid in errors and np.mean(errors[pid]) > max_px]
    for pid in bad:
        rec.delete_point3D(pid)
    return len(bad)


def _mean_reprojection_error_px(rec, errors: dict | None) -> float:
    """The mean reprojection error of the tie points kept (px; as COLMAP defines it, the
    mean over points of each point's mean error): COLMAP's, or with rolling-shutter
    compensation the compensated one."""
    if errors is None:
        rec.update_point_3d_errors()
        return float(rec.compute_mean_reprojection_error())
    kept = [np.mean(errors[pid]) for pid in rec.points3D if pid in errors]
    return float(np.mean(kept)) if kept else 0.0


def _gcp_rows(rec, gcps, marks, control: set[str], offset, rolling=None):
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


def _known_pose_reconstruction(pycolmap, truth, db_path: Path):
    """The true model for the images in the database, with the database's ids."""
    rec = pycolmap.Reconstruction()
    db = pycolmap.Database.open(str(db_path))
    try:
        images = sorted(db.read_all_images(), key=lambda i: i.image_id)
        for camera_id in sorted(c.camera_id for c in db.read_all_cameras()):
            # the true camera of the database camera's first image (a rig: each its own)
            first = next((i for i in images if i.camera_id == camera_id), None)
            src = truth.cameras[truth.find_image_with_name(first.name).camera_id] \
                if first is not None else next(iter(truth.cameras.values()))
            true_camera = copy.copy(src)  # the truth keeps its ids
            true_camera.camera_id = camera_id
            rec.add_camera_with_trivial_rig(true_camera)
        for db_image in images:
            src = truth.find_image_with_name(db_image.name)
            image = pycolmap.Image(name=db_image.name, camera_id=db_image.camera_id,
                                   image_id=db_image.image_id)
            rec.add_image_with_trivial_frame(image, src.cam_from_world())
    finally:
        db.close()
    return rec
