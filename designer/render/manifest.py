"""OUT/manifest.json: versions, settings, per-image seconds, void share and inputs.

The manifest is rewritten (atomically) as soon as the ground truth is written and again
as each image lands, so an interrupted run leaves a record of exactly the images it
finished; ``--resume`` then keeps those and re-renders only what is missing or was
rendered from other inputs.

Several processes may render slices of one folder at once (a cluster job array with
``--frames … --resume``): each write locks ``.designer-job/manifest.lock``, re-reads the file and
adds only the images this process finished, so no process erases another's record.
"""

from __future__ import annotations

import fcntl
import json
import platform
from dataclasses import asdict
from pathlib import Path

from designer import __version__
from designer.atomic import write_text_atomic
from designer.core.layout import GROUND_TRUTH_DIR, IMAGES_DIR, MANIFEST
from designer.export.colmap_read import OFFSET_FILE, model_offset_world
from designer.render.job import PreparedJob
from designer.render.job_spec import SKY_RGB
from designer.render.provenance import ImageProvenance, ground_truth_digest
from designer.render.runner import RenderReport
from designer.render.void_share import VoidSummary, round_void_share, void_summary
from designer.render_time.stages import round_stages

__all__ = ["GROUND_TRUTH_DIR", "MANIFEST", "Manifest", "read_manifest"]


def read_manifest(out_dir: Path) -> dict:
    """The manifest of an output folder, or {} when it has none (or an unreadable one)."""
    path = Path(out_dir) / MANIFEST
    try:
        data = json.loads(path.read_text())
    except (OSError, ValueError):
        return {}
    return data if isinstance(data, dict) else {}


class Manifest:
    """The manifest of one render run, merged with what the folder already holds."""

    def __init__(self, out_dir: Path, project_path: Path, prepared: PreparedJob,
                 provenance: dict[int, ImageProvenance], prepare_seconds: float,
                 crs: str | None = None) -> None:
        self.path = Path(out_dir) / MANIFEST
        self.out_dir = Path(out_dir)
        self.prepared = prepared
        self.provenance = provenance
        previous = read_manifest(out_dir)
        names = prepared.job.image_names
        old_images = previous.get("images", {}) if isinstance(previous.get("images"), dict) \
            else {}
        # entries of images this project no longer has are dropped: their files are not
        # part of this survey (check-output lists such files)
        self.names = set(names.values())
        self.recorded = {name: entry for name, entry in old_images.items()
                         if name in self.names and isinstance(entry, dict)}
        self.finished: dict[str, dict] = {}  # images this process rendered
        job = prepared.job
        self.data = {
            "designer_version": __version__,
            "blender_version": previous.get("blender_version"),
            "python": platform.python_version(),
            "project": str(Path(project_path).resolve()),
            "crs": crs,
            "origin_world": list(job.origin_world),
            "render": asdict(job.render),
            "camera_blender": asdict(job.camera),
            "image_size_px": list(prepared.interior.image_size_px),
            "frames_total": len(names),
            "prepare_seconds": round(prepare_seconds, 3),
            "ground_truth": previous.get("ground_truth"),
            "images_folder": IMAGES_DIR,
            "void": None,  # the images' void summary (VoidSummary), kept up to date
            # what an image's void shows: "black" background, or the "sky" above the
            # horizon of images that look towards it (render.terrain_bake.SKY_RGB)
            "background": "sky" if tuple(job.background_rgb) == SKY_RGB else (
                "black" if not any(job.background_rgb) else list(job.background_rgb)),
            "images": {},
        }
        if prepared.cameras is not None:  # a rig: each camera's image size (image_size_px
            # is the first camera's)
            self.data["image_size_px_by_camera"] = {
                c: list(i.image_size_px) for c, i in prepared.cameras.interiors.items()}

    def changed_parts(self, index: int, size_on_disk_px: tuple[int, int] | None = None
                      ) -> list[str]:
        """What changed since the image of frame ``index`` was rendered ([] = nothing);
        ``size_on_disk_px``: the (W, H) of its file now (a size the job no longer makes
        is a change even when the record is lost)."""
        from designer.render.provenance import size_reason

        name = self.prepared.job.image_names[index]
        inputs = self.recorded.get(name, {}).get("inputs")
        current = self.provenance[index]
        size_now = tuple(self.prepared.job.frame_size_px(index))
        sized = size_on_disk_px is not None and tuple(size_on_disk_px) != size_now
        if inputs and inputs.get("digest") == current.digest and not sized:
            return []
        return (current.changed_parts(inputs, size_on_disk_px)
                or [size_reason(size_on_disk_px, size_now)])

    def ground_truth_written(self, colmap_offset: str = "local") -> None:
        """Record the ground truth's digest and the COLMAP model's offset: ``colmap_offset``
        as given (``--colmap-offset``) and ``colmap_offset_world_m`` [E0, N0, H0] as written
        in ground-truth/colmap/offset.json (world = model + offset)."""
        folder = self.out_dir / GROUND_TRUTH_DIR
        record = {"digest": ground_truth_digest(folder), "folder": GROUND_TRUTH_DIR,
                  "colmap_offset": str(colmap_offset)}
        offset_file = folder / "colmap" / OFFSET_FILE
        if offset_file.is_file():
            record["colmap_offset_world_m"] = model_offset_world(offset_file.parent).tolist()
        self.data["ground_truth"] = record
        self._write()

    def image_done(self, index: int, seconds: float, stages: dict | None = None,
                   void_share: float | None = None) -> None:
        """Record a finished image: its seconds in the worker (``render_seconds``, the
        whole frame) and, when the worker reported them, each stage's seconds
        (:data:`designer.render_time.stages.FRAME_STAGES`) and the share of the image that
        sees no object (``void_share``, 0..1: :mod:`designer.render.void_share`)."""
        name = self.prepared.job.image_names[index]
        entry = {"frame": index, "render_seconds": round(seconds, 4)}
        if stages:
            entry["stages"] = round_stages(stages)
        if void_share is not None:
            entry["void_share"] = round_void_share(void_share)
        entry["inputs"] = self.provenance[index].to_json()
        self.finished[name] = entry
        self._write()

    def void_summary(self) -> VoidSummary:
        """The void of every image the manifest records (this run's and earlier ones')."""
        shares = {name: entry.get("void_share") for name, entry in self.data["images"].items()}
        return void_summary({name: s if isinstance(s, float | int) and not isinstance(s, bool)
                             else None for name, s in shares.items()})

    def ground_truth_seconds(self, seconds: float) -> None:
        """How long writing the ground truth (tables, masks) took in this run."""
        self.data["ground_truth_seconds"] = round(seconds, 3)

    def finish(self, report: RenderReport, times=None) -> Path:
        """The run's last record: its report and its timings
        (:class:`designer.render_time.timing.RenderTimes`, ``times_last_run``)."""
        if times is not None:
            self.data["times_last_run"] = times.to_json()
        if report.blender_version:
            self.data["blender_version"] = report.blender_version
        self.data.update(scene_build_seconds=report.scene_seconds,
                         wall_seconds_last_run=round(report.wall_seconds, 3),
                         failed_frames=report.failed)
        self._write()
        return self.path

    def _write(self) -> None:
        self.path.parent.mkdir(parents=True, exist_ok=True)
        with open(self.prepared.job_path.parent / "manifest.lock", "a") as lock:
            fcntl.flock(lock, fcntl.LOCK_EX)
            on_disk = read_manifest(self.out_dir).get("images")
            if isinstance(on_disk, dict):  # what other processes recorded meanwhile
                self.recorded.update({k: v for k, v in on_disk.items()
                                      if k in self.names and isinstance(v, dict)})
            self.recorded.update(self.finished)
            self.data["images"] = dict(sorted(self.recorded.items()))
            self.data["void"] = asdict(self.void_summary())
            write_text_atomic(self.path, json.dumps(self.data, indent=1))
