"""``designer render``: project → job → images (local workers) → ground truth + manifest.

Output folder layout::

    OUT/IMAGE_NAME…            the images, each renamed into place when complete
    OUT/ground-truth/…         COLMAP, OpenDroneMap, Metashape, OPK and GCP tables
    OUT/manifest.json          versions, settings and per-image render seconds
    OUT/.designer-job/         the job the workers read (scene files, logs)

Ground truth comes from the project's exact poses and GCP coordinates, never from
what Blender reports back.
"""

from __future__ import annotations

import json
import platform
import re
import time
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np

from designer import __version__
from designer.atomic import write_text_atomic
from designer.core.truth import GcpObservation, GroundControlPoint
from designer.errors import DesignerError
from designer.export.dispatch import write_all
from designer.export.odm import odm_crs
from designer.project import load_project
from designer.render.job import PreparedJob, prepare_job
from designer.render.runner import ProgressCallback, RenderReport, render_frames

GROUND_TRUTH_DIR = "ground-truth"
DEFAULT_FORMATS = ("colmap", "odm", "metashape", "opk", "gcp")


@dataclass(frozen=True)
class RenderSummary:
    out_dir: Path
    prepared: PreparedJob
    report: RenderReport
    ground_truth: dict[str, Path]
    manifest: Path


def parse_frames(text: str | None, n_frames: int) -> list[int]:
    """'0-99,120' → [0, …, 99, 120]; None → every frame. Indices are 0-based."""
    if text is None:
        return list(range(n_frames))
    frames: list[int] = []
    for part in text.split(","):
        part = part.strip()
        match = re.fullmatch(r"(\d+)(?:-(\d+))?", part)
        if not match:
            raise DesignerError(
                f"--frames {text!r}: '{part}' is not a frame number or range; write e.g. 0-99,120")
        lo = int(match.group(1))
        hi = int(match.group(2) or lo)
        if hi < lo:
            raise DesignerError(f"--frames {text!r}: range {part} runs backwards")
        if hi >= n_frames:
            raise DesignerError(
                f"--frames {text!r}: frame {hi} does not exist; the project has frames "
                f"0-{n_frames - 1}")
        frames.extend(range(lo, hi + 1))
    return sorted(set(frames))


def ground_truth_observations(prepared: PreparedJob) -> list[GcpObservation]:
    """Pixel coordinates of every GCP in every image where it is visible and unoccluded."""
    from designer.survey.raycast import TerrainRaycaster
    from designer.survey.visibility import visible_pairs

    targets = prepared.scene.targets
    if not targets:
        return []
    points = np.array([t.true_xyz for t in targets])
    C = np.array([p.C_world for p in prepared.poses])
    R = np.array([p.R_cam_to_world for p in prepared.poses])
    hf = prepared.scene.heightfield
    raycaster = TerrainRaycaster(hf) if hf is not None else None
    pairs = visible_pairs(points, C, R, prepared.interior, raycaster)
    order = np.lexsort((pairs.camera, pairs.point))
    return [GcpObservation(targets[pairs.point[k]].target.id,
                           prepared.poses[pairs.camera[k]].image_name, pairs.uv_px[k])
            for k in order]


def write_ground_truth(project, prepared: PreparedJob, out_dir: Path) -> dict[str, Path]:
    gcps = [GroundControlPoint(t.target.id, t.target.role, t.true_xyz, t.surveyed_xyz,
                               t.sigma_xyz) for t in prepared.scene.targets]
    formats = project.outputs.ground_truth or DEFAULT_FORMATS
    return write_all(out_dir / GROUND_TRUTH_DIR, prepared.interior, prepared.poses, gcps,
                     ground_truth_observations(prepared), odm_crs(project.crs),
                     formats=formats)


def render_project(
    project_path: Path,
    out_dir: Path,
    *,
    workers: int | None = None,
    frames: str | None = None,
    quality: str | None = None,
    resume: bool = False,
    progress: ProgressCallback | None = None,
    scheduler: str | None = None,
) -> RenderSummary:
    """Render a project into ``out_dir``; on a Dask cluster when ``scheduler`` is given."""
    project_path = Path(project_path)
    project = load_project(project_path)
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    prepared = prepare_job(project, project_path.parent, out_dir, quality)
    prepare_seconds = time.perf_counter() - t0
    ground_truth = write_ground_truth(project, prepared, out_dir)
    wanted = parse_frames(frames, len(prepared.poses))
    if scheduler:
        from designer.render.cluster import render_frames_on_cluster

        report = render_frames_on_cluster(prepared.job_path, wanted, scheduler,
                                          resume=resume, progress=progress)
    else:
        report = render_frames(prepared.job_path, wanted,
                               workers=workers or project.render.workers,
                               resume=resume, progress=progress)
    manifest = write_manifest(out_dir, project_path, prepared, report, prepare_seconds)
    if report.failed:
        raise DesignerError(
            f"{len(report.failed)} of {len(wanted)} images failed twice (frames "
            f"{report.failed[:10]}); see {prepared.job_path.parent / 'logs'}; rerun with "
            "--resume to retry only those")
    return RenderSummary(out_dir, prepared, report, ground_truth, manifest)


def write_manifest(out_dir: Path, project_path: Path, prepared: PreparedJob,
                   report: RenderReport, prepare_seconds: float) -> Path:
    """OUT/manifest.json: versions, settings and per-image seconds, merged over resumes."""
    path = out_dir / "manifest.json"
    previous = json.loads(path.read_text()) if path.is_file() else {}
    images = previous.get("images", {})
    job = prepared.job
    names = job.image_names
    for index, seconds in report.rendered.items():
        images[names[index]] = {"frame": index, "render_seconds": round(seconds, 4)}
    manifest = {
        "designer_version": __version__,
        "blender_version": report.blender_version or previous.get("blender_version"),
        "python": platform.python_version(),
        "project": str(project_path.resolve()),
        "render": asdict(job.render),
        "camera_blender": asdict(job.camera),
        "image_size_px": list(prepared.interior.image_size_px),
        "frames_total": len(names),
        "prepare_seconds": round(prepare_seconds, 3),
        "scene_build_seconds": report.scene_seconds,
        "wall_seconds_last_run": round(report.wall_seconds, 3),
        "images": dict(sorted(images.items())),
        "failed_frames": report.failed,
    }
    write_text_atomic(path, json.dumps(manifest, indent=1))
    return path
