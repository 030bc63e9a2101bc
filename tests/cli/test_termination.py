"""SIGTERM is Ctrl-C everywhere, and no process outlives designer: a command stopped by
SIGTERM (as ``timeout`` and batch systems send it, to the main process only) exits 130
with its finished work kept, and a command killed outright (SIGKILL) takes its workers
with it."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from designer.render.pipeline import render_project
from tests.synthetic import small_survey, write_project_file

ROOT = Path(__file__).resolve().parents[2]

pytestmark = [pytest.mark.blender, pytest.mark.slow]


def _alive(pid: int) -> bool:
    """True while ``pid`` runs (a zombie waiting to be reaped counts as ended)."""
    try:
        state = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
    except (FileNotFoundError, ProcessLookupError, IndexError):
        return False
    return state not in ("Z", "X")


def _group(pgid: int) -> list[int]:
    """Live processes of process group ``pgid``."""
    out = []
    for stat in Path("/proc").glob("[0-9]*/stat"):
        try:
            fields = stat.read_text().rsplit(")", 1)[1].split()
        except OSError:
            continue
        if int(fields[2]) == pgid and fields[0] not in ("Z", "X"):
            out.append(int(stat.parent.name))
    return out


def _wait_until(condition, timeout_s: float = 20.0) -> bool:
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        if condition():
            return True
        time.sleep(0.1)
    return condition()


def _start(*args: str) -> subprocess.Popen:
    # its own session: the test can find every process it starts (one process group)
    return subprocess.Popen([sys.executable, "-m", "designer", *args], cwd=ROOT,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            start_new_session=True)


#: photos of the slow project: a signal after the first lands with images still to render
N = 4


def _slow_project(tmp_path: Path) -> Path:
    # seconds per image: a signal after the first image always lands mid-job
    return write_project_file(small_survey(n_photos=N, samples=128, size_px=(320, 240)),
                              tmp_path)


def _render_until_first_image(tmp_path: Path):
    project = _slow_project(tmp_path)
    out = tmp_path / "out"
    proc = _start("render", str(project), "-o", str(out), "--workers", "1",
                  "--progress", "json")
    workers = []
    for line in proc.stdout:
        event = json.loads(line)
        if event["event"] == "worker_started":
            workers.append(event["pid"])
        if event["event"] == "frame_done":
            break
    return project, out, proc, workers


def test_sigterm_stops_a_render_like_ctrl_c_and_resume_redoes_nothing(tmp_path):
    project, out, proc, workers = _render_until_first_image(tmp_path)
    proc.send_signal(signal.SIGTERM)  # the main process only, as timeout(1) does
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == 130, err
    lines = [x for x in err.splitlines() if x.strip()]
    assert lines[-1].startswith("designer: interrupted by SIGTERM: ") and "--resume" in lines[-1]
    assert "Traceback" not in err
    assert workers and _wait_until(lambda: not any(_alive(p) for p in workers), 10)
    assert _group(proc.pid) == []
    done = sorted(p.name for p in (out / "images").iterdir())
    assert 1 <= len(done) < N
    mtimes = {name: (out / "images" / name).stat().st_mtime_ns for name in done}
    summary = render_project(project, out, workers=1, resume=True)
    assert len(summary.report.skipped) == len(done)
    assert len(summary.report.rendered) == N - len(done)
    assert {n: (out / "images" / n).stat().st_mtime_ns for n in done} == mtimes


def test_a_killed_render_takes_its_workers_with_it(tmp_path):
    _, _, proc, workers = _render_until_first_image(tmp_path)
    proc.kill()  # SIGKILL: no clean-up runs in the main process
    proc.communicate(timeout=30)
    # at once: the worker still had images (seconds each) to render on its own
    assert workers and _wait_until(lambda: not any(_alive(p) for p in workers), 3), \
        "a render worker outlived its killed parent"
    assert _wait_until(lambda: _group(proc.pid) == [], 10)


def _study(tmp_path: Path) -> Path:
    from designer.study.templates import write_template

    write_template("tiny", tmp_path / "tiny.xml")
    return tmp_path / "tiny.xml"


@pytest.mark.parametrize("how", ["SIGTERM", "SIGKILL"])
def test_a_stopped_study_leaves_no_process(tmp_path, how):
    study = _study(tmp_path)
    out = tmp_path / "out"
    proc = _start("study", "run", str(study), "-o", str(out), "--workers", "2",
                  "--progress", "json")
    for line in proc.stdout:  # a render worker is running once a render started
        if json.loads(line).get("event") == "render_started":
            break
    assert _wait_until(lambda: len(_group(proc.pid)) >= 3, 60), _group(proc.pid)
    if how == "SIGTERM":
        proc.send_signal(signal.SIGTERM)
        _, err = proc.communicate(timeout=120)
        assert proc.returncode == 130, err
        assert "Traceback" not in err
        assert "interrupted by SIGTERM: the finished runs are kept" in err and "--resume" in err
    else:
        proc.kill()
        proc.communicate(timeout=30)
    assert _wait_until(lambda: _group(proc.pid) == [], 30), \
        f"left running after {how}: {_group(proc.pid)}"


def test_a_bench_cut_short_keeps_its_measured_rows(tmp_path):
    env = {**os.environ, "TMPDIR": str(tmp_path)}
    # --scale 0.05: one frame per row (the first row is all the test waits for)
    proc = subprocess.Popen(
        [sys.executable, "-m", "designer", "bench", "render", "--repeats", "1",
         "--scale", "0.05"], cwd=ROOT, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
        text=True, start_new_session=True, env=env)
    first = ""
    for line in proc.stderr:  # the measured rows come on stderr as they finish
        if line.startswith("demo "):
            first = line
            break
    assert first, "no row printed before the end"
    proc.send_signal(signal.SIGTERM)
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == 130, err
    assert "interrupted by SIGTERM: the rows printed above were measured" in err
    assert _wait_until(lambda: _group(proc.pid) == [], 20), _group(proc.pid)
    assert list(tmp_path.iterdir()) == []  # its temporary folder removed


def test_a_stopped_resume_counts_up_to_date_and_out_of_date_images_apart(tmp_path):
    """N images rendered, then the render settings change and a --resume run is
    stopped after its first image: one image is up to date, the others are on disk from
    the old settings; the message says so (not 'N finished images kept') and, --resume being
    given already, does not ask for it."""
    quick = small_survey(n_photos=N, samples=1, size_px=(320, 240))
    project = write_project_file(quick, tmp_path)
    out = tmp_path / "out"
    render_project(project, out, workers=1)
    project = _slow_project(tmp_path)  # the same survey at 128 samples
    proc = _start("render", str(project), "-o", str(out), "--workers", "1", "--resume",
                  "--progress", "json")
    for line in proc.stdout:
        if json.loads(line)["event"] == "frame_done":
            break
    proc.send_signal(signal.SIGTERM)
    rest, err = proc.communicate(timeout=120)
    assert proc.returncode == 130, err
    events = [json.loads(x) for x in rest.splitlines() if x.strip()]
    stopped = [e for e in events if e["event"] == "interrupted"]
    assert len(stopped) == 1
    n = stopped[0]["up_to_date"]
    assert 1 <= n < N
    assert stopped[0] == {"event": "interrupted", "total": N, "up_to_date": n,
                          "rendered_now": n, "out_of_date": N - n, "not_rendered": 0,
                          "resume": True}
    last = [x for x in err.splitlines() if x.strip()][-1]
    assert last.startswith("designer: interrupted by SIGTERM: ")
    assert f"{n} of {N} images up to date ({n} rendered by this run)" in last
    assert f"{N - n} out of date" in last
    assert "run the same command again" in last and "with --resume" not in last
    assert "finished images kept" not in last
