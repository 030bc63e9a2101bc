"""Reconstruct a rendered survey with COLMAP (pycolmap) and georeference it by its GCPs.

Input: an output folder of ``designer render`` (images + ``ground-truth/``).
Modes:

* ``known-poses`` — the ideal case: SIFT features and matches, then triangulation with
  the true interior and exterior orientations (nothing is estimated but points);
* ``free`` — full incremental SfM from the images alone (intrinsics fixed to the
  camera's, as a calibrated survey camera would be), then georeferencing: each GCP is
  triangulated from its observations in the registered images and a robust
  7-parameter similarity maps the control points onto their surveyed coordinates.

Image pairs are chosen by where the cameras are (the k nearest camera centres), as
GPS-tagged survey images allow. Coordinates stay float64 throughout; COLMAP keeps
poses and points in double precision, and the written PLY stores doubles.
Only CPU features are used; dense patch-match stereo needs CUDA and is skipped.
"""

from __future__ import annotations

import json
import shutil
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from designer.atomic import atomic_path, write_text_atomic
from designer.errors import DesignerError
from designer.export.tables import read_gcp_observations_csv, read_gcp_truth_csv

MODES = ("known-poses", "free")
#: neighbours each image is matched with (by camera-centre distance)
PAIR_NEIGHBOURS = 12


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


def check_survey_folder(survey: Path) -> tuple[Path, list[str]]:
    """The ground-truth COLMAP folder and image names of a rendered survey, or a clear error."""
    gt = survey / "ground-truth" / "colmap"
    if not (gt / "images.txt").is_file() or not (gt / "cameras.txt").is_file():
        raise DesignerError(
            f"{survey}: no ground truth (ground-truth/colmap/images.txt); give the output "
            "folder of 'designer render' with its colmap ground truth")
    names = []
    for line in (gt / "images.txt").read_text().splitlines():
        parts = line.split()
        if len(parts) >= 10 and not line.startswith("#") and parts[0].isdigit():
            names.append(parts[9])
    present = [n for n in names if (survey / n).is_file()]
    if len(present) < 3:
        raise DesignerError(
            f"{survey}: {len(present)} of {len(names)} images are present; at least 3 "
            "overlapping images are needed (render them first, or finish with --resume)")
    return gt, present


def reconstruct(
    survey_dir: Path,
    out_dir: Path,
    mode: str = "known-poses",
    max_features: int = 8192,
    log: Callable[[str], None] = _log_default,
) -> ReconstructionResult:
    """Run features, matching and triangulation or SfM; write the model, cloud and residuals."""
    import pycolmap

    if mode not in MODES:
        raise DesignerError(f"--mode {mode!r}: use one of {', '.join(MODES)}")
    survey, out = Path(survey_dir), Path(out_dir)
    gt_dir, names = check_survey_folder(survey)
    truth = pycolmap.Reconstruction(str(gt_dir))
    # COLMAP triangulates on homogeneous coordinates: with UTM-sized values that loses
    # centimetres. Work in a local frame (world − offset) and shift back at the end.
    offset = np.round(np.mean([img.projection_center() for img in truth.images.values()],
                              axis=0))
    truth.transform(_translation(pycolmap, -offset))
    out.mkdir(parents=True, exist_ok=True)
    timings: dict[str, float] = {}
    t = time.perf_counter()

    db_path = out / "database.db"
    db_path.unlink(missing_ok=True)
    camera = next(iter(truth.cameras.values()))
    reader = pycolmap.ImageReaderOptions()
    reader.camera_model = camera.model.name
    reader.camera_params = ",".join(repr(float(v)) for v in camera.params)
    extraction = pycolmap.FeatureExtractionOptions()
    extraction.sift.max_num_features = max_features
    extraction.use_gpu = False
    log(f"features: {len(names)} images")
    pycolmap.extract_features(db_path, survey, image_names=names,
                              camera_mode=pycolmap.CameraMode.SINGLE, reader_options=reader,
                              extraction_options=extraction, device=pycolmap.Device.cpu)
    timings["features_s"] = time.perf_counter() - t

    t = time.perf_counter()
    pairs = _neighbour_pairs(truth, names)
    pairs_file = out / "pairs.txt"
    write_text_atomic(pairs_file, "".join(f"{a} {b}\n" for a, b in pairs))
    pairing = pycolmap.ImportedPairingOptions()
    pairing.match_list_path = str(pairs_file)
    matching = pycolmap.FeatureMatchingOptions()
    matching.use_gpu = False
    log(f"matching: {len(pairs)} image pairs")
    pycolmap.match_image_pairs(db_path, matching_options=matching, pairing_options=pairing,
                               device=pycolmap.Device.cpu)
    timings["matching_s"] = time.perf_counter() - t

    t = time.perf_counter()
    sparse = out / "sparse"
    if sparse.exists():
        shutil.rmtree(sparse)
    sparse.mkdir()
    if mode == "known-poses":
        log("triangulating with the true poses")
        rec = _known_pose_reconstruction(pycolmap, truth, db_path)
        rec = pycolmap.triangulate_points(rec, db_path, survey, sparse)
    else:
        log("incremental SfM")
        options = pycolmap.IncrementalPipelineOptions()
        options.num_threads = -1
        # Nadir survey images have small baselines: the default 16° initial triangulation
        # angle rejects every pair of a typical 80 % overlap flight.
        options.mapper.init_min_tri_angle = 4.0
        options.mapper.init_min_num_inliers = 50
        # A calibrated survey camera: keep the interior orientation fixed.
        options.ba_refine_focal_length = False
        options.ba_refine_principal_point = False
        options.ba_refine_extra_params = False
        maps = pycolmap.incremental_mapping(db_path, survey, sparse, options=options)
        if not maps:
            raise DesignerError(
                f"{survey}: COLMAP could not start a reconstruction: the images do not "
                "overlap enough or show too little texture")
        rec = max(maps.values(), key=lambda r: r.num_reg_images())
    timings["reconstruction_s"] = time.perf_counter() - t

    t = time.perf_counter()
    gcp_rows, sim = _georeference(pycolmap, rec, survey, mode, offset, log)
    rec.transform(_translation(pycolmap, offset))
    timings["georeference_s"] = time.perf_counter() - t

    model_dir = out / "model"
    model_dir.mkdir(exist_ok=True)
    rec.write_text(str(model_dir))
    cloud = out / "cloud.ply"
    write_cloud_ply(rec, cloud)
    residuals = out / "gcp_residuals.csv"
    write_gcp_residuals(gcp_rows, residuals)
    summary = {
        "mode": mode, "images": len(names), "registered": rec.num_reg_images(),
        "points": rec.num_points3D(),
        "mean_reprojection_error_px": float(rec.compute_mean_reprojection_error()),
        "similarity": sim, "gcps": gcp_rows, "timings": timings,
        "dense": "skipped: patch-match stereo needs CUDA, not available here",
    }
    write_text_atomic(out / "summary.json", json.dumps(summary, indent=1))
    log(f"{rec.num_reg_images()}/{len(names)} images registered, {rec.num_points3D()} points")
    return ReconstructionResult(out, mode, len(names), rec.num_reg_images(),
                                rec.num_points3D(), cloud, residuals, summary)


def _neighbour_pairs(truth, names: list[str]) -> list[tuple[str, str]]:
    """Each image with its PAIR_NEIGHBOURS nearest cameras (by centre), no duplicates."""
    centres = []
    for name in names:
        centres.append(truth.find_image_with_name(name).projection_center())
    C = np.array(centres)
    d2 = ((C[:, None, :] - C[None, :, :]) ** 2).sum(axis=-1)
    k = min(PAIR_NEIGHBOURS, len(names) - 1)
    pairs = set()
    for i in range(len(names)):
        for j in np.argsort(d2[i])[1:k + 1]:
            pairs.add((min(i, int(j)), max(i, int(j))))
    return [(names[i], names[j]) for i, j in sorted(pairs)]


def _known_pose_reconstruction(pycolmap, truth, db_path: Path):
    """The true model for the images in the database, with the database's ids."""
    rec = pycolmap.Reconstruction()
    db = pycolmap.Database.open(str(db_path))
    try:
        cameras = {c.camera_id: c for c in db.read_all_cameras()}
        for camera_id in cameras:
            true_camera = next(iter(truth.cameras.values()))
            true_camera.camera_id = camera_id
            rec.add_camera_with_trivial_rig(true_camera)
        for db_image in sorted(db.read_all_images(), key=lambda i: i.image_id):
            src = truth.find_image_with_name(db_image.name)
            image = pycolmap.Image(name=db_image.name, camera_id=db_image.camera_id,
                                   image_id=db_image.image_id)
            rec.add_image_with_trivial_frame(image, src.cam_from_world())
    finally:
        db.close()
    return rec


def _translation(pycolmap, t: np.ndarray):
    return pycolmap.Sim3d(1.0, pycolmap.Rotation3d(), np.asarray(t, dtype=float))


def _georeference(pycolmap, rec, survey: Path, mode: str, offset: np.ndarray, log):
    """Triangulate GCPs; in free mode fit a similarity on the control points first.

    ``rec`` is in local coordinates (world − offset); the rows report world coordinates.
    """
    gt = survey / "ground-truth"
    truth = {g.gcp_id: g for g in read_gcp_truth_csv(gt / "gcp_truth.csv")}
    observations = read_gcp_observations_csv(gt / "gcp_observations.csv")
    sim_info = None
    points = _triangulate_gcps(pycolmap, rec, observations)
    if mode == "free":
        control = [g for g in truth if truth[g].role == "control" and g in points]
        if len(control) < 3:
            raise DesignerError(
                f"{survey}: only {len(control)} control GCPs are seen in registered images; "
                "georeferencing needs at least 3")
        src = np.array([points[g] for g in control])
        tgt = np.array([truth[g].surveyed_xyz for g in control]) - offset
        ransac = pycolmap.RANSACOptions()
        ransac.max_error = 0.5
        sim = pycolmap.estimate_sim3d_robust(src, tgt, ransac)
        if sim is None:
            raise DesignerError(f"{survey}: no similarity fits the control GCPs")
        sim = sim["tgt_from_src"] if isinstance(sim, dict) else sim
        rec.transform(sim)
        sim_info = {"scale": float(sim.scale), "control_gcps": control}
        points = _triangulate_gcps(pycolmap, rec, observations)
        log(f"georeferenced on {len(control)} control GCPs (scale {sim.scale:.6f})")
    rows = []
    for gcp_id, g in truth.items():
        if gcp_id not in points:
            continue
        estimated = points[gcp_id] + offset
        d = estimated - g.true_xyz
        rows.append({"id": gcp_id, "role": g.role,
                     "estimated": [float(v) for v in estimated],
                     "dx_m": float(d[0]), "dy_m": float(d[1]), "dz_m": float(d[2])})
    return rows, sim_info


def _triangulate_gcps(pycolmap, rec, observations) -> dict[str, np.ndarray]:
    """World coordinates of each GCP from its observations in registered images."""
    by_name = {img.name: img for img in rec.images.values() if img.has_pose}
    grouped: dict[str, list] = {}
    for o in observations:
        if o.image_name in by_name:
            grouped.setdefault(o.gcp_id, []).append(o)
    out = {}
    for gcp_id, obs in grouped.items():
        if len(obs) < 2:
            continue
        images = [by_name[o.image_name] for o in obs]
        cams = [rec.cameras[img.camera_id] for img in images]
        uv = np.array([o.uv_px for o in obs], dtype=float)
        result = pycolmap.estimate_triangulation(
            uv, [img.cam_from_world() for img in images], cams)
        if result is not None:
            out[gcp_id] = np.asarray(result["xyz"], dtype=float).reshape(3)
    return out


def write_cloud_ply(rec, path: Path) -> None:
    """The sparse cloud as binary PLY with double coordinates and uchar colours."""
    from plyfile import PlyData, PlyElement

    pts = list(rec.points3D.values())
    data = np.empty(len(pts), dtype=[("x", "f8"), ("y", "f8"), ("z", "f8"),
                                     ("red", "u1"), ("green", "u1"), ("blue", "u1")])
    if pts:
        xyz = np.array([p.xyz for p in pts])
        rgb = np.array([p.color for p in pts])
        data["x"], data["y"], data["z"] = xyz.T
        data["red"], data["green"], data["blue"] = rgb.T
    with atomic_path(path) as tmp:
        PlyData([PlyElement.describe(data, "vertex")]).write(str(tmp))


def write_gcp_residuals(rows: list[dict], path: Path) -> None:
    lines = ["# GCP residuals: estimated (triangulated) minus true coordinates, world m",
             "id,role,X,Y,Z,dX,dY,dZ"]
    for r in rows:
        X, Y, Z = r["estimated"]
        lines.append(f"{r['id']},{r['role']},{X!r},{Y!r},{Z!r},{r['dx_m']!r},{r['dy_m']!r},"
                     f"{r['dz_m']!r}")
    write_text_atomic(path, "\n".join(lines) + "\n")
