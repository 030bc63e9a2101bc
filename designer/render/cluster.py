"""Rendering on an existing Dask cluster (``designer render --scheduler tcp://HOST:PORT``).

One Dask task per batch of frames. Each task runs the same worker process a local run
uses (``python -m designer.render.worker``) on whichever Dask worker picks it up, so the
job folder (OUT/.designer-job) and OUT itself must be on storage every machine sees
under the same path. Images are written in OUT/.designer-job/partial and renamed into
OUT/images when complete, exactly as locally,
so ``--resume`` works the same way; a failed task is retried once by this client.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import time
from collections.abc import Callable
from pathlib import Path

from designer.errors import DesignerError
from designer.render.job_spec import RenderJob
from designer.render.runner import (
    ProgressCallback,
    RenderReport,
    image_is_complete,
    remove_partial_files,
)


def render_batch(job_path: str, frames: list[int], threads: int = 0) -> dict:
    """Render ``frames`` of a job in a worker process here; runs inside a Dask task."""
    read_fd, write_fd = os.pipe()
    cmd = [sys.executable, "-m", "designer.render.worker", job_path,
           "--frames", ",".join(map(str, frames)), "--progress-fd", str(write_fd),
           "--threads", str(threads),
           # Blender dies with the Dask worker that started it (a killed or lost worker
           # leaves no render running on its own)
           "--parent-pid", str(os.getpid())]
    log_dir = Path(job_path).parent / "logs"
    log_dir.mkdir(exist_ok=True)
    log_path = log_dir / f"dask-{os.getpid()}-{frames[0]}.log"
    with open(log_path, "ab") as log:
        proc = subprocess.Popen(cmd, stdout=log, stderr=subprocess.STDOUT, pass_fds=(write_fd,))
    os.close(write_fd)
    events = []
    with os.fdopen(read_fd) as stream:
        events = [json.loads(line) for line in stream]
    proc.wait()
    return {"returncode": proc.returncode, "events": events, "host": os.uname().nodename}


def render_frames_on_cluster(
    job_path: Path,
    frames: list[int],
    scheduler: str,
    batch_size: int = 4,
    resume: bool = False,
    progress: ProgressCallback | None = None,
    retries: int = 1,
    keep: Callable[[int], bool] | None = None,
) -> RenderReport:
    """Render ``frames`` on the Dask cluster at ``scheduler`` (e.g. tcp://10.0.0.5:8786)."""
    try:
        from distributed import Client, as_completed
    except ImportError as error:  # pragma: no cover - the extra is part of 'all'
        raise DesignerError("--scheduler needs dask.distributed: pip install "
                            "'designer[cluster]'") from error
    job_path = Path(job_path).resolve()
    job = RenderJob.read(job_path)
    out_dir = Path(job.output_dir)
    names = job.image_names
    report = RenderReport()
    t0 = time.perf_counter()
    todo = list(frames)
    if resume:
        report.skipped = [i for i in todo
                          if image_is_complete(out_dir / names[i], *job.frame_size_px(i))
                          and (keep is None or keep(i))]
        todo = [i for i in todo if i not in set(report.skipped)]
    try:
        client = Client(scheduler, timeout="10s")
    except OSError as error:
        raise DesignerError(f"cannot reach the Dask scheduler at {scheduler}: {error}; check "
                            "the address and that the scheduler is running") from error
    try:
        attempt = 0
        while todo and attempt <= retries:
            batches = [todo[k:k + batch_size] for k in range(0, len(todo), batch_size)]
            futures = [client.submit(render_batch, str(job_path), b, pure=False)
                       for b in batches]
            for future in as_completed(futures):
                result = future.result()
                for event in result["events"]:
                    event["host"] = result["host"]
                    if event["event"] == "frame_done":
                        report.frame_done(event)
                    elif event["event"] == "scene_ready":
                        report.scene_seconds.append(float(event["seconds"]))
                    elif event["event"] == "worker_done":
                        report.blender_version = event.get("blender")
                    if progress is not None:
                        progress(event)
            todo = [i for i in todo if i not in report.rendered]
            attempt += 1
    finally:
        client.close()
        remove_partial_files(job_path.parent, out_dir)
    report.failed = todo
    report.wall_seconds = time.perf_counter() - t0
    return report
