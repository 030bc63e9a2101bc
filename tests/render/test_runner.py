"""Cancel, resume and crash recovery of the local render runner, with real workers."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys

import cv2
import pytest

from designer.project import load_project
from designer.render.job import prepare_job
from designer.render.pipeline import render_project
from designer.render.runner import render_frames
from tests.synthetic import small_survey, write_project_file

pytestmark = [pytest.mark.blender, pytest.mark.slow]


def complete_images(folder, size=(320, 240)):
    names = sorted(p.name for p in folder.glob("IMG_*.png"))
    for name in names:
        image = cv2.imread(str(folder / name))
        assert image is not None and image.shape[1::-1] == size, f"{name} is incomplete"
    return names


def test_ctrl_c_leaves_only_complete_images_and_resume_finishes(tmp_path):
    # ~1 s of CPU per image (32 samples), hundreds of times the Ctrl-C's way from the first
    # image's progress line to the worker, so it always lands mid-job
    project = write_project_file(small_survey(n_photos=4, samples=32, size_px=(320, 240)),
                                 tmp_path)
    out = tmp_path / "out"
    cmd = [sys.executable, "-m", "designer", "render", str(project), "-o", str(out),
           "--workers", "1", "--progress", "json"]
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    for line in proc.stdout:
        if json.loads(line)["event"] == "frame_done":
            proc.send_signal(signal.SIGINT)
            break
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == 130, err
    assert "interrupted" in err and "Traceback" not in err
    done = complete_images(out / "images")
    assert 1 <= len(done) < 4
    # the images folder holds the finished images and nothing else; no partial file stays
    assert sorted(p.name for p in (out / "images").iterdir()) == done
    assert [p.name for p in out.glob(".*")] == [".designer-job"]
    assert list((out / ".designer-job" / "partial").iterdir()) == []

    summary = render_project(project, out, workers=1, resume=True)
    assert sorted(summary.report.skipped) == list(range(len(done)))
    assert len(summary.report.rendered) == 4 - len(done)
    assert len(complete_images(out / "images")) == 4


def test_a_killed_worker_has_its_frames_retried(tmp_path):
    project = write_project_file(small_survey(n_photos=4, samples=64, size_px=(320, 240)), tmp_path)
    # the job prepared as a render prepares it (no frame rendered before the one under test)
    job = prepare_job(load_project(project), project.parent, tmp_path / "out").job_path
    events = []

    def kill_first_worker(event):
        events.append(event)
        if event["event"] == "frame_done" and event["worker"] == 0 and not any(
                e["event"] == "retry" for e in events):
            os.kill(worker_pids[0], signal.SIGKILL)
        if event["event"] == "worker_started":
            worker_pids.append(event["pid"])

    worker_pids: list[int] = []
    report = render_frames(job, [0, 1, 2, 3], workers=1, progress=kill_first_worker)
    assert any(e["event"] == "retry" for e in events)
    assert report.failed == []
    assert sorted(report.rendered) == [0, 1, 2, 3]
    assert len(complete_images(tmp_path / "out" / "images")) == 4


def test_ctrl_c_works_even_when_started_ignoring_it(tmp_path):
    """Started the way a script's `cmd &` starts it (SIGINT ignored), designer render still
    stops cleanly on SIGINT."""
    project = write_project_file(small_survey(n_photos=4, samples=32, size_px=(320, 240)),
                                 tmp_path)
    cmd = [sys.executable, "-m", "designer", "render", str(project), "-o",
           str(tmp_path / "out"), "--workers", "1", "--progress", "json"]
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_IGN))
    for line in proc.stdout:
        if json.loads(line)["event"] == "frame_done":
            proc.send_signal(signal.SIGINT)
            break
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == 130, err
    assert 1 <= len(complete_images(tmp_path / "out" / "images")) < 4
