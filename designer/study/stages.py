"""The stages of one study run, as plain functions a worker process (or Dask worker) calls.

* :func:`plan_run` (main process): the run's project file, its prepared render job →
  image-set hash, GSD, image count, flight minutes; its ground truth → the processing
  hash; its GCP counts. Runs that differ only in their processing share one prepared
  job: the later ones copy the first one's ground truth;
* :func:`render_stage`: ``designer render`` of one image set into the render cache, or
  an effect pass over the raw renders of another image set that differs only in its
  camera effects; its wall and CPU seconds;
* :func:`process_stage`: ``designer reconstruct`` (free mode, the project's
  ``<processing>``) and ``designer compare`` (cloud against the true surface); their
  wall and CPU seconds, the CPU of feature extraction, matching and the SfM mapper
  apart.

CPU seconds (:func:`designer.study.cost.cpu_seconds`) are those of the worker process
that runs the stage and of its ended child processes, read before and after: a worker
that runs one stage at a time (the local pool; a Dask worker with one thread) counts
exactly that stage.

Stage outputs land in cache folders named by content hash; ``done.json`` is written
last (atomically), so a folder without it is unfinished and is redone.
"""

from __future__ import annotations

import json
import os
import shutil
import time
import traceback
from dataclasses import replace
from pathlib import Path

import numpy as np

from designer.atomic import write_text_atomic
from designer.core.layout import GROUND_TRUTH_DIR, IMAGES_DIR, images_dir
from designer.errors import DesignerError
from designer.project import model as m

DONE = "done.json"
#: processing mode of every study reconstruction
MODE = "free"


def rebase_files(project: m.Project, from_dir: Path, to_dir: Path) -> m.Project:
    """The project with its file references made relative to ``to_dir``."""
    def fix(file: str) -> str:
        return os.path.relpath(Path(from_dir).resolve() / file, Path(to_dir).resolve())

    scene = project.scene
    source = scene.terrain.source
    if isinstance(source, m.DemTerrain | m.MeshTerrain):
        scene = replace(scene, terrain=replace(scene.terrain, source=replace(
            source, file=fix(source.file))))
    if isinstance(scene.texture.source, m.ImageTexture):
        scene = replace(scene, texture=replace(scene.texture, source=m.ImageTexture(
            fix(scene.texture.source.file))))
    scene = replace(scene, objects=tuple(replace(o, file=fix(o.file)) for o in scene.objects))
    return replace(project, scene=scene)


#: the parts of a run's plan that depend on its images alone (not on its processing)
IMAGE_KEYS = ("images", "image_hash", "raw_hash", "ground_truth_digest", "gsd_m",
              "flight_min", "flight_min_source")


def images_key(project: m.Project) -> str:
    """What a run's images and ground truth depend on: the project without its
    processing (runs of one study share a folder depth, so file references match)."""
    return repr(replace(project, processing=None))


def plan_run(project: m.Project, run_dir: Path,
             same_images: tuple[Path, dict] | None = None) -> dict:
    """Write the run's project and survey ground truth; its hashes, GSD and image count.

    ``same_images``: (run folder, plan) of a run with the same :func:`images_key` — its
    ground truth is copied and its image-set figures kept instead of preparing the
    render job again (the terrain's texture and light bakes take most of a plan)."""
    from designer.project import write_project
    from designer.study.cache import digest, processing_hash
    from designer.study.cost import gcp_counts

    run_dir.mkdir(parents=True, exist_ok=True)
    write_project(project, run_dir / "project.xml")
    gt = run_dir / "survey" / GROUND_TRUTH_DIR
    if gt.exists():
        shutil.rmtree(gt)
    if same_images is None:
        info = _plan_images(project, run_dir)
    else:
        other_dir, other = same_images
        shutil.copytree(other_dir / "survey" / GROUND_TRUTH_DIR, gt)
        info = {k: other[k] for k in IMAGE_KEYS}
    gcps, control_gcps = gcp_counts(project)
    # runs whose reconstructions share features and matches (and the SfM model) through
    # the feature cache, by what that sharing depends on
    processing = project.processing or m.Processing()
    features_group = digest("features", info["image_hash"], repr(processing.matching))
    return {"project": "project.xml", **info,
            "processing_hash": processing_hash(info["image_hash"],
                                               info["ground_truth_digest"],
                                               project.processing, MODE),
            "features_group": features_group,
            "sfm_group": digest("sfm", features_group, processing.calibration.mode,
                                repr(processing.sfm)),
            "gcps": gcps, "control_gcps": control_gcps}


def _plan_images(project: m.Project, run_dir: Path) -> dict:
    """The image-set part of a run's plan (:data:`IMAGE_KEYS`), its ground truth written
    under ``run_dir/survey``."""
    from designer.render.job import prepare_job
    from designer.render.pipeline import write_ground_truth
    from designer.render.provenance import (
        ground_truth_digest,
        job_provenance,
        raw_render_digests,
    )
    from designer.study.cache import image_set_hash, raw_set_hash
    from designer.study.cost import flight_minutes

    survey = run_dir / "survey"
    prepared = prepare_job(project, run_dir, survey)
    provenance = job_provenance(prepared.job, prepared.job_path.parent)
    names = [prepared.job.image_names[i] for i in sorted(prepared.job.image_names)]
    write_ground_truth(project, prepared, survey)
    gsd = [f.gsd_m for f in prepared.job.frames if f.gsd_m is not None]
    shutil.rmtree(prepared.job_path.parent, ignore_errors=True)
    # the images in flight order: a rig's images of one station share its centre
    flight_min, flight_source = flight_minutes(
        np.array([pose.C_world for pose in prepared.poses]),
        None if prepared.times is None else [t.time_s for t in prepared.times])
    return {"images": names,
            "image_hash": image_set_hash(provenance, prepared.job.image_names),
            "raw_hash": raw_set_hash(raw_render_digests(prepared.job, provenance),
                                     prepared.job.image_names),
            "ground_truth_digest": ground_truth_digest(survey / GROUND_TRUTH_DIR),
            "gsd_m": float(np.mean(gsd)) if gsd else None,
            "flight_min": flight_min, "flight_min_source": flight_source}


def render_stage(project_path: str, out_dir: str, workers: int = 1,
                 keep_raw: str | None = None, raw_from: str | None = None) -> dict:
    """Render a project into ``out_dir`` (resuming what is there); seconds taken.
    ``keep_raw``: keep the raw renders there too; ``raw_from``: an effect pass over the
    raw renders kept there (no Cycles)."""
    from designer.render.manifest import read_manifest
    from designer.render.pipeline import render_project
    from designer.study.cost import cpu_seconds

    out = Path(out_dir)
    # images an earlier, killed session finished: their Cycles CPU seconds are added
    # (the rest of that session's CPU — start-up, scene, effects — is not known)
    earlier = _cycles_cpu_s(read_manifest(out))
    t0, cpu0 = time.perf_counter(), cpu_seconds()
    try:
        render_project(Path(project_path), out, workers=workers, resume=True,
                       keep_raw=Path(keep_raw) if keep_raw else None,
                       raw_from=Path(raw_from) if raw_from else None)
        status = "ok"
    except DesignerError as error:
        status = f"failed: render: {error}"
    result = {"status": status, "render_s": time.perf_counter() - t0,
              # this process (scene, ground truth, effects) and its Blender workers
              "render_cpu_s": cpu_seconds() - cpu0 + earlier,
              "render_cycles_cpu_s": _cycles_cpu_s(read_manifest(out)) or None,
              "kind": "effects pass" if raw_from else "cycles"}
    write_text_atomic(out / DONE, json.dumps(result))
    return result


def _cycles_cpu_s(manifest: dict) -> float:
    """The Cycles CPU seconds of every image a render manifest records."""
    images = manifest.get("images") or {}
    return float(sum((entry.get("stages") or {}).get("cycles_cpu_s", 0.0)
                     for entry in images.values() if isinstance(entry, dict)))


def link_images(render_dir: Path, survey: Path, names: list[str]) -> None:
    """Put the images of the render output ``render_dir`` into the run's survey folder,
    ``survey/images/`` (symbolic links, else copies; :mod:`designer.core.layout`)."""
    source = images_dir(render_dir)
    for name in names:
        target = Path(survey) / IMAGES_DIR / name
        if target.is_file():
            continue
        target.parent.mkdir(parents=True, exist_ok=True)
        try:
            os.symlink(os.path.relpath(source / name, target.parent), target)
        except OSError:
            shutil.copyfile(source / name, target)


def process_stage(survey_dir: str, project_path: str, out_dir: str,
                  feature_cache: str | None = None,
                  step_cpu: dict[str, str] | None = None) -> dict:
    """Reconstruct and compare one run; its metrics, or ``failed: reason``. Runs of the
    same images share features, matches and SfM models through ``feature_cache``; what
    computing each cost is kept in the folder ``step_cpu[step]``
    (:func:`designer.study.cost.record_step_cpu`)."""
    # keep COLMAP's per-step log lines out of the study's output (errors still show);
    # read by its logging library when pycolmap loads in this worker
    os.environ.setdefault("GLOG_minloglevel", "2")
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    result: dict = {}
    try:
        result = _process(Path(survey_dir), Path(project_path), out,
                          Path(feature_cache) if feature_cache else None, step_cpu)
        result["status"] = "ok"
    except (DesignerError, ValueError, RuntimeError, np.linalg.LinAlgError) as error:
        result["status"] = f"failed: {type(error).__name__ if not str(error) else error}"
        result["status"] = " ".join(result["status"].split())[:300]
        (out / "error.txt").write_text(traceback.format_exc())
    write_text_atomic(out / DONE, json.dumps(result))
    return result


def _process(survey: Path, project_path: Path, out: Path, feature_cache: Path | None,
             step_cpu: dict[str, str] | None = None) -> dict:
    from designer.evaluate import compare_cloud, read_point_cloud
    from designer.evaluate.compare import reference_meshes
    from designer.project import load_project
    from designer.sfm.reconstruct import reconstruct
    from designer.study.cost import StageClock, cpu_seconds, record_step_cpu

    project = load_project(project_path)
    clock = StageClock(None if not step_cpu else lambda step, cpu_s: record_step_cpu(
        Path(step_cpu[step]), out.name, step, cpu_s))
    t0, cpu0 = time.perf_counter(), cpu_seconds()
    rec = reconstruct(survey, out / "reconstruction", mode=MODE,
                      processing=project.processing, project_path=project_path,
                      log=clock, feature_cache=feature_cache)
    t1, cpu1 = time.perf_counter(), cpu_seconds()
    s = rec.summary
    reused = s.get("reused_from_cache") or {}
    row: dict = {"reconstruct_s": t1 - t0, "registered": rec.n_registered,
                 "images": rec.n_images, "features_reused": reused.get("features", False),
                 "matches_reused": reused.get("matches", False),
                 "sfm_reused": reused.get("sfm", False),
                 # what this reconstruction spent; what it took from the cache cost
                 # it nothing (designer.study.cost.add_reused_cpu)
                 "reconstruct_cpu_spent_s": cpu1 - cpu0,
                 **{f"{step}_cpu_s": clock.step_cpu_s(step, cpu1)
                    for step in ("features", "matching", "sfm")}}
    for role in ("check", "control"):
        stats = s.get(role) or {}
        for key in ("rmse_x_m", "rmse_y_m", "rmse_z_m", "rmse_xy_m", "rmse_xyz_m"):
            row[f"{role}_{key}"] = stats.get(key)
        row[f"{role}_n"] = stats.get("n", 0)
    intr = s.get("intrinsics") or {}
    row["focal_error_px"] = intr.get("delta_f_px")
    row["k1_error"] = intr.get("delta_k1")
    row["k1_error_beyond_focal"] = intr.get("k1_beyond_focal_trade")
    dense = s.get("dense") or {}
    row["dome_amplitude_m"] = dense.get("dome_amplitude_m")
    row["dome_amplitude_gsd"] = dense.get("dome_amplitude_gsd")
    row["sparse_dome_gsd"] = (s.get("sparse_dome") or {}).get("amplitude_gsd")
    if rec.n_points >= 10:
        cloud = read_point_cloud(rec.cloud_ply)
        # both surfaces from one build of the terrain
        truth = reference_meshes(project_path, surfaces=("dsm", "dtm"))
        dsm = truth["dsm"]
        summary = compare_cloud(cloud, dsm, out / "compare")
        d = summary["distances"]
        row.update({"cloud_median_m": d["median"], "cloud_nmad_m": d["nmad"],
                    "cloud_mean_m": d["mean"], "cloud_rmse_m": d["rmse"],
                    "error_map": str((out / "compare" / "error_map.png").relative_to(out))})
        # against the bare earth too, when something stands on it (else the same figures)
        dtm = truth["dtm"]
        if len(dtm.faces) != len(dsm.faces):
            d = compare_cloud(cloud, dtm, out / "compare_dtm")["distances"]
        row.update({"dtm_cloud_median_m": d["median"], "dtm_cloud_nmad_m": d["nmad"],
                    "dtm_cloud_mean_m": d["mean"], "dtm_cloud_rmse_m": d["rmse"]})
    row["compare_s"] = time.perf_counter() - t1
    row["compare_cpu_s"] = cpu_seconds() - cpu1
    return row

