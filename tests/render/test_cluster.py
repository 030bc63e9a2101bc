"""Rendering through a real (local) Dask cluster gives the same images as local workers."""

from __future__ import annotations

import cv2
import distributed
import numpy as np
import pytest

from designer.errors import DesignerError
from designer.render.pipeline import render_project
from tests.synthetic import small_survey, write_project_file

pytestmark = [pytest.mark.blender, pytest.mark.slow]


def test_dask_cluster_renders_the_same_images_as_local_workers(tmp_path):
    project = write_project_file(small_survey(n_photos=3, samples=8, size_px=(320, 240)), tmp_path)
    local = render_project(project, tmp_path / "local", workers=1)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster:
        remote = render_project(project, tmp_path / "dask", scheduler=cluster.scheduler_address)
    assert sorted(remote.report.rendered) == [0, 1, 2]
    for pose in local.prepared.poses:
        a = cv2.imread(str(tmp_path / "local" / "images" / pose.image_name))
        b = cv2.imread(str(tmp_path / "dask" / "images" / pose.image_name))
        # Same seed, same scene, same samples: Cycles is deterministic on one machine.
        assert np.array_equal(a, b)


def test_an_unreachable_scheduler_is_a_clear_error(tmp_path, small_project_file):
    project = small_project_file(n_photos=1, samples=1, size_px=(64, 48))
    with pytest.raises(DesignerError, match="cannot reach the Dask scheduler"):
        render_project(project, tmp_path / "out", scheduler="tcp://127.0.0.1:1")


def test_blender_dies_with_the_dask_worker_that_started_it(tmp_path):
    """The task body of a Dask worker (render_batch) in a process killed with SIGKILL:
    the Blender worker it started ends too, instead of rendering on alone."""
    import os
    import signal
    import subprocess
    import sys
    import time
    from pathlib import Path

    from designer.project import load_project
    from designer.render.job import prepare_job

    # slow frames (a minute each): a worker on its own would render on for a minute before
    # its next progress line hit the closed pipe; one Cycles thread (render_batch's
    # threads) burns one core, not all, while the test waits
    path = write_project_file(small_survey(n_photos=2, samples=4096, size_px=(640, 480)),
                              tmp_path)
    prepared = prepare_job(load_project(path), path.parent, tmp_path / "out")
    root = Path(__file__).resolve().parents[2]
    task = subprocess.Popen(
        [sys.executable, "-c", "import sys; from designer.render.cluster import "
         "render_batch; render_batch(sys.argv[1], [0, 1], 1)",
         str(prepared.job_path)], cwd=root, env={**os.environ, "PYTHONPATH": str(root)})
    try:
        blender = None
        deadline = time.monotonic() + 120
        while blender is None and time.monotonic() < deadline:
            children = subprocess.run(["pgrep", "-P", str(task.pid)], capture_output=True,
                                      text=True).stdout.split()
            blender = int(children[0]) if children else None
            time.sleep(0.2)
        assert blender is not None, "render_batch started no worker"
        time.sleep(5.0)  # the worker is up (its death signal set first thing)
        os.kill(task.pid, signal.SIGKILL)
        task.wait()
        deadline = time.monotonic() + 3
        while time.monotonic() < deadline and Path(f"/proc/{blender}").exists():
            status = Path(f"/proc/{blender}/stat").read_text().split()[2] if Path(
                f"/proc/{blender}/stat").exists() else "X"
            if status == "Z":
                break
            time.sleep(0.2)
        alive = Path(f"/proc/{blender}/stat").exists() and Path(
            f"/proc/{blender}/stat").read_text().split()[2] not in ("Z", "X")
        assert not alive, "the Blender worker outlived the Dask worker that started it"
    finally:
        if task.poll() is None:
            task.kill()
