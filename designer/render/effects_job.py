"""The camera effects of a render job, outside Blender: the job's spec of them, each
camera's effect chain, and one frame's raw render turned into its finished image.

The render worker applies them right after Cycles; :func:`apply_effects_pass` applies
them to raw renders kept from an earlier run (``render_project(..., raw_from=DIR)``), so
a study whose variants differ only in camera effects (sensor noise, JPEG quality,
vignetting, blur) renders its images in Cycles once.
"""

from __future__ import annotations

import os
from pathlib import Path

from designer.render.job_spec import CameraEffectsSpec, EffectsSpec, FrameSpec, RenderJob


def effects_spec(model, interiors: dict, rendered: dict, job_dir: Path, rig: bool
                 ) -> EffectsSpec | None:
    """The job's camera effects (None: every image is final as rendered): everything the
    worker needs to build each chain, the project's effects ``model``, each camera's
    interior as rendered and its distortion warp (written beside the job). ``interiors``
    and ``rendered`` (pinhole, warp) by camera id; ``rig``: several cameras."""
    from designer.effects.from_model import effects_from_model

    with_effects = [c for c, i in interiors.items()
                    if not effects_from_model(model, i, warp=rendered[c][1]).is_empty]
    if not with_effects:
        return None
    parts: dict[str, CameraEffectsSpec] = {}
    for c in with_effects:
        w, warp_file = rendered[c][1], None
        if w is not None:
            warp_file = "distortion_warp.npz" if not rig else f"distortion_warp_{c}.npz"
            w.save(Path(job_dir) / warp_file)
        parts[c] = CameraEffectsSpec(interior=interiors[c], warp=warp_file)
    return EffectsSpec(model=model, cameras=parts, rig=rig)


def load_effects(job: RenderJob, base: Path) -> dict:
    """The camera-effects chain of each camera: {camera id: chain} for a multi-camera rig
    (cameras whose images are final as rendered are absent), {None: chain} for one camera;
    {} when every image is final as rendered. Built from the job alone (its effects model,
    each camera's interior and the warp files beside it in ``base``)."""
    spec = job.effects
    if spec is None:
        return {}
    from designer.effects.distortion_render import DistortionWarp
    from designer.effects.from_model import effects_from_model

    chains = {}
    for camera_id, camera in spec.cameras.items():
        interior = camera.interior
        warp = DistortionWarp.load(base / camera.warp, interior) if camera.warp else None
        chains[camera_id if spec.rig else None] = effects_from_model(spec.model, interior,
                                                                     warp=warp)
    return chains


def process_frame(raw: Path, staged: Path, frame: FrameSpec, chain,
                  stages: dict | None = None) -> None:
    """Write the finished image of ``frame`` to ``staged`` from its raw render ``raw``
    (Blender's file): through ``chain`` when there is one, else the same pixels (a PNG
    without Blender's text chunks)."""
    from designer.render.png_text import move_without_text

    if chain is None and Path(staged).suffix.lower() == ".png":
        move_without_text(raw, staged)
    elif chain is None:
        os.replace(raw, staged)
    else:
        from designer.effects.base import FrameContext
        from designer.effects.chain import process_file

        context = FrameContext(gsd_m=frame.gsd_m, flight_direction_uv=frame.flight_direction_uv,
                               distance_m=frame.distance_m)
        process_file(raw, staged, chain, frame.index, context, timings=stages)


def keep_raw(raw: Path, kept: Path) -> None:
    """Keep a raw render as ``kept`` (a hard link where the file system allows, else a
    copy), atomically: a kept file is always complete."""
    import shutil

    from designer.atomic import atomic_path

    kept.parent.mkdir(parents=True, exist_ok=True)
    with atomic_path(kept) as tmp:
        tmp.unlink(missing_ok=True)
        try:
            os.link(raw, tmp)
        except OSError:
            shutil.copyfile(raw, tmp)


def apply_effects_pass(job_path: Path, frames: list[int], raw_dir: Path, *,
                       resume: bool = False, progress=None, keep=None):
    """Finish the images of ``frames`` from raw renders kept in ``raw_dir`` (a render of
    the same scene, poses and Blender camera with ``keep_raw``), through this job's
    camera effects: no Cycles. Returns a RenderReport (``rendered``: seconds per image,
    ``stages``: its steps, ``void_share``: from the void maps kept beside the raw
    renders, where there are). Images appear in the job's images folder only when
    complete.
    """
    import time

    from designer.core.layout import PARTIAL_DIR
    from designer.errors import DesignerError
    from designer.render.runner import RenderReport, image_is_complete, remove_partial_files
    from designer.render.void_share import VOID_MAP_SUFFIX, void_share_of_map

    job_path = Path(job_path)
    job = RenderJob.read(job_path)
    base = job_path.parent
    out_dir = Path(job.output_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    ext = job.render.extension
    frames_by_index = {f.index: f for f in job.frames}
    missing = [i for i in frames if not (Path(raw_dir) / f"{Path(job.image_names[i]).stem}{ext}"
                                         ).is_file()]
    if missing:
        raise DesignerError(f"{raw_dir}: no raw render of frames {missing[:5]}; render them "
                            "with Cycles (keep_raw) first")
    report = RenderReport()
    t0 = time.perf_counter()
    todo = list(frames)
    if resume:
        done = [i for i in todo if image_is_complete(out_dir / job.image_names[i],
                                                     *job.frame_size_px(i))
                and (keep is None or keep(i))]
        report.skipped = done
        todo = [i for i in todo if i not in set(done)]
        for i in done:
            if progress is not None:
                progress({"event": "frame_skipped", "index": i})
    chains = load_effects(job, base)
    partial = base / PARTIAL_DIR
    partial.mkdir(parents=True, exist_ok=True)
    exif = job.image_metadata == "exif"
    try:
        for i in todo:
            frame = frames_by_index[i]
            final = out_dir / frame.image_name
            t_frame = time.perf_counter()
            raw = partial / f"{final.stem}.raw{ext}"
            keep_raw(Path(raw_dir) / f"{final.stem}{ext}", raw)  # the cache file stays
            staged = partial / final.name
            stages: dict = {}
            try:
                process_frame(raw, staged, frame, chains.get(frame.camera_id), stages)
                if exif and frame.time_utc is not None:
                    from designer.render.exif import write_time

                    write_time(staged, frame.time_utc)
                os.replace(staged, final)
            finally:
                raw.unlink(missing_ok=True)
                staged.unlink(missing_ok=True)
            void_map = Path(raw_dir) / f"{final.stem}{VOID_MAP_SUFFIX}"
            # the same rendered pixels: the void the raw render's worker measured
            void_share = void_share_of_map(void_map) if void_map.is_file() else None
            seconds = time.perf_counter() - t_frame
            stages["effects_total_s"] = seconds
            event = {"event": "frame_done", "index": i, "path": str(final),
                     "seconds": seconds, "stages": stages, "void_share": void_share,
                     "effects_pass": True}
            report.frame_done(event)
            if progress is not None:
                progress(event)
    finally:
        remove_partial_files(base, out_dir)
    report.wall_seconds = time.perf_counter() - t0
    return report
