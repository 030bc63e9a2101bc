"""``designer render``: project → job → images (local workers) → ground truth + manifest.

Output folder layout (:mod:`designer.core.layout`)::

    OUT/images/IMAGE_NAME…     only the images, each renamed in when complete
    OUT/ground-truth/…         COLMAP, OpenDroneMap, Metashape, OPK and GCP tables
    OUT/manifest.json          versions, settings, per-image render seconds, void share and inputs
    OUT/README.txt             which file each program takes
    OUT/.designer-job/         the job the workers read (scene files, logs, partial images)

A folder rendered before ``images/`` existed (images at OUT's top level) has its images
moved into ``images/`` by the next render of it, so ``--resume`` keeps them.

Ground truth comes from the project's exact poses and GCP coordinates, never from
what Blender reports back. The manifest records, per image, the hashes of what it was
rendered from (:mod:`designer.render.provenance`), updated as each image lands, and the
hash of the ground truth: ``--resume`` keeps an image only if its inputs are unchanged,
and :func:`check_output` tells whether a folder's images and ground truth still belong
to its project.
"""

from __future__ import annotations

import re
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from designer.core.layout import GROUND_TRUTH_DIR, move_old_layout_images
from designer.core.truth import GcpObservation, GroundControlPoint, ImageTime
from designer.errors import DesignerError
from designer.export.dispatch import write_all
from designer.export.odm import odm_crs
from designer.project import load_project
from designer.project import model as m
from designer.render.job import PreparedJob, prepare_job
from designer.render.manifest import Manifest
from designer.render.provenance import job_provenance
from designer.render.readme import write_readme
from designer.render.runner import (
    ProgressCallback,
    RenderReport,
    image_size_px,
    render_frames,
)
from designer.render.void_share import VoidSummary
from designer.render_time.timing import RenderTimes

DEFAULT_FORMATS = ("colmap", "odm", "metashape", "opk", "gcp")


@dataclass(frozen=True)
class RenderSummary:
    out_dir: Path
    prepared: PreparedJob
    report: RenderReport
    ground_truth: dict[str, Path]
    manifest: Path
    #: frames re-rendered although complete, with the parts of their inputs that changed
    stale: dict[int, list[str]] = field(default_factory=dict)
    #: the void of the folder's images (the manifest's ``void``: this run's and earlier)
    void: VoidSummary | None = None
    #: this run's timings, each named for what it counts
    times: RenderTimes | None = None

    @property
    def images_dir(self) -> Path:
        """OUT/images: the rendered images and nothing else."""
        return Path(self.prepared.job.output_dir)


@dataclass(frozen=True)
class ImagesKept:
    """What a stopped render leaves in its images folder, image by image: up to date
    (rendered from the project as it is now; ``rendered_now`` of them by the stopped
    run), out of date (on disk, rendered from other inputs: replaced when rendered
    again) and not rendered."""

    total: int
    up_to_date: int
    rendered_now: int
    out_of_date: int
    not_rendered: int

    def text(self, resume: bool, *, resume_option: str = "--resume",
             rerun: str = "run the same command") -> str:
        """One line: the counts, then how to continue (when anything is left).
        ``resume``: whether the stopped run had resume on (then the same run continues);
        ``resume_option`` and ``rerun`` name the option and the action in the caller's
        words (the Render panel: "'resume' ticked", "start the render")."""
        if self.up_to_date == self.total:  # stopped after the last image: no rest
            return (f"all {self.total} images up to date ({self.rendered_now} rendered by "
                    "this run); nothing is left to render")
        parts = [f"{self.up_to_date} of {self.total} images up to date "
                 f"({self.rendered_now} rendered by this run)"]
        if self.out_of_date:
            parts.append(f"{self.out_of_date} out of date (rendered from other inputs, "
                         "replaced when rendered again)")
        if self.not_rendered:
            parts.append(f"{self.not_rendered} not rendered")
        return "; ".join(parts) + "; " + continue_hint(resume, resume_option=resume_option,
                                                       rerun=rerun)

    def to_json(self) -> dict:
        return {"total": self.total, "up_to_date": self.up_to_date,
                "rendered_now": self.rendered_now, "out_of_date": self.out_of_date,
                "not_rendered": self.not_rendered}


def continue_hint(resume: bool, *, resume_option: str = "--resume",
                  rerun: str = "run the same command") -> str:
    """How to continue a stopped render: with resume on, the same run again; without,
    the same run with resume on (only then are finished images kept)."""
    if resume:
        return f"{rerun} again to render only the rest"
    return f"{rerun} with {resume_option} to render only the rest"


def images_kept(manifest: Manifest, wanted_names: dict[int, str], images: Path,
                rendered_now: int) -> ImagesKept:
    """Count the images folder against the manifest: an image is up to date when its
    file is there and its record's inputs are the project's now (the file is renamed in
    only when complete, and its size is part of those inputs: nothing is decoded)."""
    up_to_date = out_of_date = 0
    for index, name in wanted_names.items():
        if not (images / name).is_file():
            continue
        if manifest.changed_parts(index):
            out_of_date += 1
        else:
            up_to_date += 1
    total = len(wanted_names)
    return ImagesKept(total, up_to_date, rendered_now, out_of_date,
                      total - up_to_date - out_of_date)


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
    from designer.core.raycast import TerrainRaycaster
    from designer.survey.visibility import visible_pairs

    targets = prepared.scene.targets
    if not targets:
        return []
    points = np.array([t.true_xyz for t in targets])
    hf = prepared.scene.heightfield
    raycaster = TerrainRaycaster(hf) if hf is not None else None
    if prepared.buildings:
        # a target hidden behind a building is not observed in that image
        from designer.survey.mesh_occlusion import MeshOccluder, OccluderStack

        raycaster = OccluderStack(raycaster, [MeshOccluder(b.vertices_world, b.faces)
                                              for b in prepared.buildings])
    # one pass per physical camera (a rig has several), then in (GCP, image) order
    groups: dict[int, list[int]] = {}
    for k, pose in enumerate(prepared.poses):
        groups.setdefault(id(prepared.interior_of(pose.image_name)), []).append(k)
    image_index, point_index, uv = [], [], []
    for members in groups.values():
        members = np.array(members)
        interior = prepared.interior_of(prepared.poses[members[0]].image_name)
        C = np.array([prepared.poses[k].C_world for k in members])
        R = np.array([prepared.poses[k].R_cam_to_world for k in members])
        pairs = visible_pairs(points, C, R, interior, raycaster)
        pair_camera, pair_point, pair_uv = pairs.camera, pairs.point, pairs.uv_px
        if prepared.frame_shutters and prepared.frame_shutters[members[0]] is not None:
            # a rolling-shutter camera: where its images show the targets (the rows' own
            # poses); a target they move out of the image is not observed
            from designer.render.rolling_truth import rolling_shutter_uv

            pair_uv = rolling_shutter_uv(prepared, members[pair_camera], pair_point, points)
            W, H = interior.image_size_px
            inside = ((pair_uv[:, 0] >= 0) & (pair_uv[:, 0] < W) & (pair_uv[:, 1] >= 0)
                      & (pair_uv[:, 1] < H))
            pair_camera, pair_point, pair_uv = (pair_camera[inside], pair_point[inside],
                                                pair_uv[inside])
        image_index.append(members[pair_camera])
        point_index.append(pair_point)
        uv.append(pair_uv)
    image_index, point_index = np.concatenate(image_index), np.concatenate(point_index)
    uv = np.concatenate(uv)
    order = np.lexsort((image_index, point_index))
    return [GcpObservation(targets[point_index[k]].target.id,
                           prepared.poses[image_index[k]].image_name, uv[k])
            for k in order]


def write_ground_truth(project, prepared: PreparedJob, out_dir: Path,
                       colmap_offset: str = "local") -> dict[str, Path]:
    """Every ground-truth format of the project under OUT/ground-truth/; ``colmap_offset``
    is ``--colmap-offset`` (``local``, ``none`` or ``E,N,H``)."""
    gcps = [GroundControlPoint(t.target.id, t.target.role, t.true_xyz, t.surveyed_xyz,
                               t.sigma_xyz) for t in prepared.scene.targets]
    formats = project.outputs.ground_truth or DEFAULT_FORMATS
    written = write_all(out_dir / GROUND_TRUTH_DIR, prepared.camera_model, prepared.poses, gcps,
                        ground_truth_observations(prepared), odm_crs(project.crs),
                        formats=formats, image_times=image_times(prepared),
                        colmap_offset=colmap_offset)
    if "colmap" in written:  # the pairs to match (COLMAP's matches_importer)
        path = out_dir / GROUND_TRUTH_DIR / "colmap" / COLMAP_PAIRS
        from designer.atomic import write_text_atomic

        write_text_atomic(path, "".join(f"{a} {b}\n" for a, b in overlapping_pairs(prepared)))
        written["colmap_pairs"] = path
    # masks of a rolling-shutter image: each row sees from its own pose
    rolling = None
    if prepared.frame_shutters:
        rolling = [None if rs is None else (rs.readout_s, rs.direction, v)
                   for rs, v in zip(prepared.frame_shutters, prepared.velocities_m_s,
                                    strict=True)]
    if prepared.moving_poses:
        from designer.render.moving_truth import write_moving_truth

        written = {**written, **write_moving_truth(
            out_dir / GROUND_TRUTH_DIR, prepared.camera_model, prepared.poses,
            prepared.moving_poses, prepared.moving_meshes, rolling)}
    if prepared.buildings:
        from designer.render.building_truth import write_building_truth

        written = {**written, **write_building_truth(
            out_dir / GROUND_TRUTH_DIR, prepared.camera_model, prepared.poses,
            prepared.buildings, rolling)}
    if project.scene.vegetation is not None:
        from designer.render.vegetation_truth import write_vegetation_truth

        times = ([t.time_s for t in prepared.times] if prepared.times is not None
                 else [None] * len(prepared.poses))
        written = {**written, **write_vegetation_truth(
            out_dir / GROUND_TRUTH_DIR, prepared.camera_model, prepared.poses, times,
            list(prepared.plants), project.scene.vegetation.wind, rolling)}
    if prepared.frame_shutters:
        from designer.atomic import write_text_atomic
        from designer.render.rolling_truth import ROLLING_SHUTTER_CSV, rolling_shutter_csv

        path = out_dir / GROUND_TRUTH_DIR / ROLLING_SHUTTER_CSV
        write_text_atomic(path, rolling_shutter_csv(prepared))
        written["rolling_shutter"] = path
    clouds = project.scene.lighting.clouds
    if clouds is not None:
        from designer.atomic import write_text_atomic

        path = out_dir / GROUND_TRUTH_DIR / CLOUD_SHADOWS_CSV
        write_text_atomic(path, cloud_shadows_csv(clouds, prepared))
        written["cloud_shadows"] = path
    return written


CLOUD_SHADOWS_CSV = "cloud_shadows.csv"
#: the image pairs COLMAP should match, one "NAME1 NAME2" per line
COLMAP_PAIRS = "pairs.txt"


def overlapping_pairs(prepared: PreparedJob) -> list[tuple[str, str]]:
    """The pairs of images whose true ground footprints overlap
    (:func:`designer.survey.pairs.footprint_pairs`: on the plane at the terrain's median
    height, each image with its most overlapping partners)."""
    from designer.core.projection import R_cv_from_world
    from designer.survey.pairs import footprint_pairs, footprint_xy

    poses = prepared.poses
    if len(poses) < 2:
        return []
    C = np.array([p.C_world for p in poses])
    centre = C.mean(axis=0)  # local coordinates: OpenCV's float32 polygons stay exact
    hf = prepared.scene.heightfield
    ground = (float(np.median(hf.heights_m)) if hf is not None
              else float(np.median(prepared.scene.terrain.vertices_world[:, 2])))
    feet = []
    for pose, c in zip(poses, C - centre, strict=True):
        interior = prepared.interior_of(pose.image_name)
        K = (interior.fx_px, interior.fy_px, interior.cx_px, interior.cy_px)
        feet.append(footprint_xy(c, R_cv_from_world(pose.R_cam_to_world), K,
                                 interior.image_size_px, ground - centre[2]))
    return footprint_pairs([p.image_name for p in poses], feet)


def cloud_shadows_csv(clouds, prepared: PreparedJob) -> str:
    """Per image: its time (s after take-off; 0 without a time line: the clouds stay as
    at take-off), how far the shadows have drifted (m east, m north) and the clouds'
    parameters."""
    from designer.scene.cloud_shadows import wind_shift_m

    head = ("image,time_s,shift_east_m,shift_north_m,cover,size_m,softness_m,depth,"
            "wind_speed_m_s,wind_direction_deg,seed")
    params = (f"{clouds.cover!r},{clouds.size_m!r},{clouds.softness_m!r},{clouds.depth!r},"
              f"{clouds.wind_speed_m_s!r},{clouds.wind_direction_deg!r},{clouds.seed}")
    times = ([t.time_s for t in prepared.times] if prepared.times is not None
             else [0.0] * len(prepared.poses))
    rows = [head]
    for pose, t in zip(prepared.poses, times, strict=True):
        east, north = wind_shift_m(clouds, t)
        rows.append(f"{pose.image_name},{t!r},{east:.6f},{north:.6f},{params}")
    return "\n".join(rows) + "\n"


def image_times(prepared: PreparedJob) -> list[ImageTime] | None:
    """When each image is taken and its sun (None: the project has no time line)."""
    if prepared.times is None:
        return None
    return [ImageTime(t.image_name, t.time_s, f.time_utc, *sun)
            for t, f, sun in zip(prepared.times, prepared.job.frames, prepared.suns,
                                 strict=True)]


def _record_speed(prepared: PreparedJob, report: RenderReport, prepare_seconds: float,
                  project=None) -> None:
    """Refine this machine's render-time coefficients from the run (the next estimate
    uses them); a cache folder that cannot be written, or frames the model cannot read
    (a ray grid through a lens it cannot invert), cost only that refinement, with a
    warning."""
    import sys

    from designer.render_time.record import record_render_speed

    try:
        record_render_speed(prepared, report, prepare_seconds, project=project)
    except (OSError, ValueError, ArithmeticError, DesignerError) as error:
        # the images are done: bookkeeping of the speed must not fail the render
        print(f"designer: warning: render speed not recorded ({error})", file=sys.stderr)


@dataclass(frozen=True)
class _Run:
    """One render's prepared state, shared by its steps: the project, the job, the
    manifest updated as images land and the frames asked for."""

    project: m.Project
    project_path: Path
    out_dir: Path
    prepared: PreparedJob
    manifest: Manifest
    wanted: list[int]
    prepare_seconds: float

    @property
    def images(self) -> Path:
        """OUT/images."""
        return Path(self.prepared.job.output_dir)


def _prepare_run(project_path: Path, out_dir: Path, frames: str | None,
                 quality: str | None, t_command: float) -> _Run:
    """Load the project, prepare its job in ``out_dir`` and open its manifest with the
    job's provenance; ``t_command``: when the command started (prepare time counts
    from it)."""
    project_path = Path(project_path).resolve()
    project = load_project(project_path)
    out_dir = Path(out_dir).resolve()  # tasks on cluster workers resolve nothing themselves
    out_dir.mkdir(parents=True, exist_ok=True)
    prepared = prepare_job(project, project_path.parent, out_dir, quality)
    provenance = job_provenance(prepared.job, prepared.job_path.parent, project)
    prepare_seconds = time.perf_counter() - t_command
    wanted = parse_frames(frames, len(prepared.poses))
    manifest = Manifest(out_dir, project_path, prepared, provenance, prepare_seconds,
                        crs=project.crs)
    return _Run(project, project_path, out_dir, prepared, manifest, wanted, prepare_seconds)


def _write_truth_and_readme(run: _Run, colmap_offset: str) -> tuple[dict[str, Path], float]:
    """Write the ground truth (recorded in the manifest) and the folder's README; the
    ground truth's files and the seconds it took."""
    prepared = run.prepared
    t_truth = time.perf_counter()
    ground_truth = write_ground_truth(run.project, prepared, run.out_dir, colmap_offset)
    truth_seconds = time.perf_counter() - t_truth
    run.manifest.ground_truth_seconds(truth_seconds)
    run.manifest.ground_truth_written(colmap_offset)
    names = prepared.job.image_names
    # the readout ODM is told: the first rolling-shutter image's
    rolling = next((rs for rs in prepared.frame_shutters if rs is not None), None)
    sizes = (None if prepared.cameras is None else
             {c: i.image_size_px for c, i in prepared.cameras.interiors.items()})
    write_readme(run.out_dir, list(names.values()), ground_truth,
                 project=run.project_path.name,
                 image_size_px=prepared.interior.image_size_px, camera_sizes_px=sizes,
                 readout_s=rolling.readout_s if rolling is not None else None)
    return ground_truth, truth_seconds


def _stale_images(run: _Run) -> dict[int, list[str]]:
    """Move a folder's old-layout images into images/, then find the wanted frames whose
    complete-looking image was rendered from other inputs (or has no record of them),
    with the parts of their inputs that changed: these are rendered again."""
    names = run.prepared.job.image_names
    move_old_layout_images(run.out_dir, names.values())
    images = run.images
    stale = {i: run.manifest.changed_parts(i) for i in run.wanted
             if (images / names[i]).is_file()}
    # the file's size (a decode) only for those: an image whose inputs are unchanged has
    # the size they give
    return {i: run.manifest.changed_parts(i, image_size_px(images / names[i]))
            for i, parts in stale.items() if parts}


def _recorder(run: _Run, measured: RenderReport,
              progress: ProgressCallback | None) -> ProgressCallback:
    """The progress callback the frames report to: each finished image goes into the
    manifest and into ``measured``, then every event on to ``progress``."""
    manifest = run.manifest

    def record(event: dict) -> None:
        if event.get("event") == "frame_done":
            manifest.image_done(int(event["index"]), float(event["seconds"]),
                                event.get("stages"), event.get("void_share"))
            measured.frame_done(event)
        elif event.get("event") == "worker_started":
            measured.scene_seconds.append(0.0)  # one entry per worker
        if progress is not None:
            progress(event)

    return record


def _dispatch_frames(run: _Run, *, workers: int | None, scheduler: str | None,
                     resume: bool, record: ProgressCallback, keep,
                     keep_raw: Path | None, raw_from: Path | None) -> RenderReport:
    """Render the wanted frames: through the camera effects only from raw renders
    (``raw_from``), on a Dask cluster (``scheduler``), or in local workers."""
    job_path = run.prepared.job_path
    if raw_from is not None:
        from designer.render.effects_job import apply_effects_pass

        return apply_effects_pass(job_path, run.wanted, Path(raw_from),
                                  resume=resume, progress=record, keep=keep)
    if scheduler:
        from designer.render.cluster import render_frames_on_cluster

        return render_frames_on_cluster(job_path, run.wanted, scheduler,
                                        resume=resume, progress=record, keep=keep)
    return render_frames(job_path, run.wanted,
                         workers=workers or run.project.render.workers,
                         resume=resume, progress=record, keep=keep, keep_raw=keep_raw)


def _render_wanted(run: _Run, stale: dict[int, list[str]], *, workers: int | None,
                   scheduler: str | None, resume: bool, progress: ProgressCallback | None,
                   keep_raw: Path | None, raw_from: Path | None) -> RenderReport:
    """Render the wanted frames (keeping complete images unless ``stale``), recording
    each in the manifest as it lands. Interrupted, the exception is given what is kept
    (``stop.kept``) and an ``interrupted`` event is sent; either way this machine's
    render speed is refined with the frames it finished (not on a cluster or from raw
    renders)."""
    def keep(index: int) -> bool:
        return index not in stale

    # what this run measured, kept as it arrives: an interrupted run still refines this
    # machine's render speed with the frames it finished
    measured = RenderReport()
    t_render = time.perf_counter()
    record = _recorder(run, measured, progress)
    try:
        return _dispatch_frames(run, workers=workers, scheduler=scheduler, resume=resume,
                                record=record, keep=keep, keep_raw=keep_raw,
                                raw_from=raw_from)
    except KeyboardInterrupt as stop:  # Ctrl-C, SIGTERM, SIGHUP: say what is kept
        names = run.prepared.job.image_names
        stop.kept = images_kept(run.manifest, {i: names[i] for i in run.wanted},
                                run.images, len(measured.rendered))
        if progress is not None:
            progress({"event": "interrupted", **stop.kept.to_json(), "resume": resume})
        raise
    finally:
        if not scheduler and raw_from is None:  # a cluster's machines are not this one
            measured.wall_seconds = time.perf_counter() - t_render
            _record_speed(run.prepared, measured, run.prepare_seconds, run.project)


def _finish(run: _Run, report: RenderReport, ground_truth: dict[str, Path],
            stale: dict[int, list[str]], *, resume: bool,
            progress: ProgressCallback | None, t_command: float,
            truth_seconds: float) -> RenderSummary:
    """Close the manifest with the run's timings, send the ``finished`` event, fail if
    images failed twice, else the summary (with the stale images this run replaced)."""
    times = RenderTimes.measured(report, time.perf_counter() - t_command,
                                 run.prepare_seconds, truth_seconds)
    manifest_path = run.manifest.finish(report, times)
    if progress is not None:
        progress({"event": "finished", **times.to_json()})
    if report.failed:
        raise DesignerError(
            f"{len(report.failed)} of {len(run.wanted)} images failed twice (frames "
            f"{report.failed[:10]}); see {run.prepared.job_path.parent / 'logs'}; rerun "
            "with --resume to retry only those")
    resumed = [i for i in stale if resume and i in report.rendered]
    return RenderSummary(run.out_dir, run.prepared, report, ground_truth, manifest_path,
                         stale={i: stale[i] for i in resumed},
                         void=run.manifest.void_summary(), times=times)


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
    colmap_offset: str = "local",
    keep_raw: Path | None = None,
    raw_from: Path | None = None,
) -> RenderSummary:
    """Render a project into ``out_dir``; on a Dask cluster when ``scheduler`` is given.

    ``colmap_offset``: the COLMAP ground truth's frame (``local``: world minus the mean
    camera centre rounded to metres; ``none``: world; ``E,N,H``: world minus that).
    ``keep_raw``: also keep each raw render (Blender's image, before the camera effects)
    in that folder, with its void map (``STEM.void-map.png``); ``raw_from``: no Cycles
    at all — finish the images from the raw renders kept there by a render of the same
    scene, poses and camera, through this project's camera effects
    (:func:`designer.render.effects_job.apply_effects_pass`).
    """
    t_command = time.perf_counter()
    run = _prepare_run(project_path, out_dir, frames, quality, t_command)
    ground_truth, truth_seconds = _write_truth_and_readme(run, colmap_offset)
    stale = _stale_images(run)
    report = _render_wanted(run, stale, workers=workers, scheduler=scheduler,
                            resume=resume, progress=progress, keep_raw=keep_raw,
                            raw_from=raw_from)
    return _finish(run, report, ground_truth, stale, resume=resume, progress=progress,
                   t_command=t_command, truth_seconds=truth_seconds)
