"""Local render runner: splits frames over worker processes, resumes, cancels, retries.

Each worker is ``python -m designer.render.worker JOB --frames …`` and reports progress
as JSON lines on a pipe. Images are written in the job folder's ``partial/`` and renamed
into the images folder (the job's ``output_dir``) only when complete, so an interrupted
run leaves only finished images there; ``resume`` skips those that are complete
and readable. A worker that dies has its unfinished frames retried once in a fresh
process; frames that fail again are reported, not hidden.
"""

from __future__ import annotations

import json
import os
import selectors
import subprocess
import sys
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

from designer.core.layout import PARTIAL_DIR
from designer.errors import DesignerError
from designer.render.job_spec import RenderJob
from designer.render_time.model import default_workers

ProgressCallback = Callable[[dict], None]


@dataclass
class RenderReport:
    """What a run did: frames rendered now, skipped as complete, and failed."""

    rendered: dict[int, float] = field(default_factory=dict)  # index -> render seconds
    skipped: list[int] = field(default_factory=list)
    failed: list[int] = field(default_factory=list)
    scene_seconds: list[float] = field(default_factory=list)
    blender_version: str | None = None
    wall_seconds: float = 0.0
    peak_rss_mb: list[float] = field(default_factory=list)  # one per worker process
    #: index -> seconds of each stage of the frame (designer.render_time.stages.FRAME_STAGES)
    stages: dict[int, dict[str, float]] = field(default_factory=dict)
    #: frames that were the first of their worker process (Cycles builds its copy of the
    #: scene during that render)
    first_frames: set[int] = field(default_factory=set)
    #: index -> share of the image that sees no object (designer.render.void_share), for
    #: the frames whose worker measured it
    void_share: dict[int, float] = field(default_factory=dict)

    def frame_done(self, event: dict) -> None:
        """Record a worker's ``frame_done`` event: seconds, stages and void share."""
        index = int(event["index"])
        self.rendered[index] = float(event["seconds"])
        self.stages[index] = dict(event.get("stages") or {})
        if event.get("void_share") is not None:
            self.void_share[index] = float(event["void_share"])
        if event.get("order") == 0:
            self.first_frames.add(index)


def image_is_complete(path: Path, width_px: int, height_px: int) -> bool:
    """True if ``path`` decodes to an image of the expected size."""
    return image_size_px(path) == (width_px, height_px)


def image_size_px(path: Path) -> tuple[int, int] | None:
    """(W, H) of the image ``path`` decodes to; None when it is absent or unreadable."""
    path = Path(path)
    if not path.is_file() or path.stat().st_size == 0:
        return None
    import cv2

    image = cv2.imread(str(path), cv2.IMREAD_UNCHANGED)
    return None if image is None else (int(image.shape[1]), int(image.shape[0]))


def remove_partial_files(job_dir: Path, images: Path) -> None:
    """Delete what interrupted workers left: the job folder's ``partial/`` files, and
    hidden temporary files older versions of designer wrote beside the images."""
    folder = Path(job_dir) / PARTIAL_DIR
    if folder.is_dir():
        for tmp in folder.iterdir():
            if tmp.is_file():
                tmp.unlink(missing_ok=True)
    if Path(images).is_dir():
        for tmp in Path(images).glob(".*"):
            if tmp.is_file():
                tmp.unlink(missing_ok=True)


def render_frames(
    job_path: Path,
    frames: list[int],
    workers: int | None = None,
    resume: bool = False,
    progress: ProgressCallback | None = None,
    retries: int = 1,
    keep: Callable[[int], bool] | None = None,
    bare: bool = False,
    keep_raw: Path | None = None,
) -> RenderReport:
    """Render ``frames`` of the job at ``job_path`` with local worker processes.

    With ``resume``, a frame whose image is complete is skipped when ``keep(index)`` is
    true (by default always; the pipeline passes its provenance check). ``bare`` renders
    in Cycles only and writes nothing (``designer bench render``'s bare Cycles row);
    ``keep_raw`` keeps each frame's raw render (before the camera effects) in that folder,
    with its void map (:mod:`designer.render.void_share`).
    """
    job_path = Path(job_path)
    job = RenderJob.read(job_path)
    out_dir = Path(job.output_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    remove_partial_files(job_path.parent, out_dir)
    names = job.image_names
    unknown = [i for i in frames if i not in names]
    if unknown:
        raise DesignerError(
            f"frames {unknown[:5]} are not in the project (it has frames 0-{len(names) - 1}); "
            "correct --frames")
    report = RenderReport()
    t0 = time.perf_counter()
    todo = list(frames)
    if resume:
        done = [i for i in todo
                if image_is_complete(out_dir / names[i], *job.frame_size_px(i))
                and (keep is None or keep(i))]
        report.skipped = done
        todo = [i for i in todo if i not in set(done)]
        for i in done:
            _notify(progress, {"event": "frame_skipped", "index": i})
    attempt = 0
    try:
        while todo and attempt <= retries:
            n_workers = workers or default_workers(len(todo))
            n_workers = max(1, min(n_workers, len(todo)))
            threads = max(1, (os.cpu_count() or 1) // n_workers)
            batches = [todo[k::n_workers] for k in range(n_workers)]
            extra = (["--bare"] if bare else []) + (
                ["--keep-raw", str(keep_raw)] if keep_raw is not None else [])
            finished = _run_workers(job_path, batches, threads, report, progress, extra)
            todo = [i for i in todo if i not in finished]
            attempt += 1
            if todo and attempt <= retries:
                _notify(progress, {"event": "retry", "frames": todo})
    finally:
        remove_partial_files(job_path.parent, out_dir)
    report.failed = todo
    report.wall_seconds = time.perf_counter() - t0
    return report


def _notify(progress: ProgressCallback | None, event: dict) -> None:
    if progress is not None:
        progress(event)


def _run_workers(job_path, batches, threads, report, progress, extra=()) -> set[int]:
    selector = selectors.DefaultSelector()
    procs = []
    finished: set[int] = set()
    log_dir = Path(job_path).parent / "logs"
    log_dir.mkdir(exist_ok=True)
    try:
        for k, batch in enumerate(batches):
            read_fd, write_fd = os.pipe()
            log = open(log_dir / f"worker-{k}.log", "ab")  # closed in finally
            cmd = [sys.executable, "-m", "designer.render.worker", str(job_path),
                   "--frames", ",".join(map(str, batch)), "--progress-fd", str(write_fd),
                   "--threads", str(threads), "--parent-pid", str(os.getpid()), *extra]
            proc = subprocess.Popen(cmd, stdout=log, stderr=subprocess.STDOUT,
                                    pass_fds=(write_fd,))
            os.close(write_fd)
            _notify(progress, {"event": "worker_started", "worker": k, "pid": proc.pid,
                               "frames": batch})
            stream = os.fdopen(read_fd, "r")
            selector.register(stream, selectors.EVENT_READ, data=k)
            procs.append((proc, stream, log))
        open_streams = len(procs)
        while open_streams:
            for key, _ in selector.select(timeout=1.0):
                line = key.fileobj.readline()
                if not line:
                    selector.unregister(key.fileobj)
                    open_streams -= 1
                    continue
                event = json.loads(line)
                event["worker"] = key.data
                if event["event"] == "frame_done":
                    finished.add(int(event["index"]))
                    report.frame_done(event)
                elif event["event"] == "scene_ready":
                    report.scene_seconds.append(float(event["seconds"]))
                elif event["event"] == "worker_done":
                    report.blender_version = event.get("blender")
                    report.peak_rss_mb.append(float(event.get("peak_rss_mb", 0.0)))
                _notify(progress, event)
        for proc, _, _ in procs:
            proc.wait()
    except BaseException:
        for proc, _, _ in procs:
            if proc.poll() is None:
                proc.terminate()
        for proc, _, _ in procs:
            try:
                proc.wait(timeout=10)
            except subprocess.TimeoutExpired:
                proc.kill()
        raise
    finally:
        for _, stream, log in procs:
            stream.close()
            log.close()
        selector.close()
    return finished
