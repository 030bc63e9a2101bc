"""One render, one set of timings: the command's last line and the ``finished`` event a
program (the desktop designer) reads give the same figures, each labelled with what it
counts (the whole command's wall time, its parts, and Cycles per image)."""

from __future__ import annotations

import json
import re
import subprocess
import sys
from pathlib import Path

import pytest

from tests.synthetic import small_survey, write_project_file

ROOT = Path(__file__).resolve().parents[2]

pytestmark = [pytest.mark.blender]


def test_the_summary_line_and_the_finished_event_give_the_same_labelled_times(tmp_path):
    project = write_project_file(small_survey(n_photos=3, samples=1, size_px=(96, 72)),
                                 tmp_path)
    out = tmp_path / "out"
    done = subprocess.run([sys.executable, "-m", "designer", "render", str(project), "-o",
                           str(out), "--workers", "1", "--progress", "json"], cwd=ROOT,
                          capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr
    lines = done.stdout.splitlines()
    events = [json.loads(x) for x in lines if x.startswith("{")]
    finished = [e for e in events if e["event"] == "finished"]
    assert len(finished) == 1
    times = finished[0]
    assert times["images"] == 3
    parts = times["prepare_s"] + times["ground_truth_s"] + times["images_wall_s"]
    assert times["command_wall_s"] >= parts > 0
    assert 0 < times["cycles_s_per_image"] <= times["images_wall_s"] / 3
    summary = next(x for x in lines if not x.startswith("{") and "images rendered" in x)
    assert (f"in {times['command_wall_s']:.1f} s wall for the whole command "
            f"(preparing the scene {times['prepare_s']:.1f} s, ground truth "
            f"{times['ground_truth_s']:.1f} s, images {times['images_wall_s']:.1f} s)"
            in summary)
    assert f"Cycles {times['cycles_s_per_image']:.2f} s per image" in summary
    assert not re.search(r"\(\d+\.\d s per image\)", summary)  # the old, unlabelled figure
    manifest = json.loads((out / "manifest.json").read_text())
    assert manifest["times_last_run"] == {k: v for k, v in times.items() if k != "event"}
