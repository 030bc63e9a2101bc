"""Render estimates that hold on this machine: a render calibrates the model, and the
estimate of the next render (``designer plan``'s figure) is checked against that
render's own measured time — a ratio, not seconds."""

from __future__ import annotations

import os
import time

import pytest

from designer.checks.plan_report import plan_project
from designer.render.pipeline import render_project
from designer.render_time.model import load_speed
from tests.synthetic import small_survey, write_project_file


@pytest.mark.blender
@pytest.mark.slow
def test_the_plan_estimate_matches_the_render_it_estimates(tmp_path):
    project = small_survey(n_photos=6, samples=8, size_px=(480, 360))
    path = write_project_file(project, tmp_path / "p")
    assert not load_speed().calibrated  # this test's own cache folder (conftest)
    render_project(path, tmp_path / "first", workers=1)
    speed = load_speed()
    # fitted to 5 frames: the worker's first also builds the scene (the fixed part)
    assert speed.source == "render" and speed.images == 5
    estimate = plan_project(project, path.parent).analysis.render_time_s
    t0 = time.perf_counter()
    summary = render_project(path, tmp_path / "second", workers=1)
    measured = time.perf_counter() - t0
    assert len(summary.report.rendered) == 6
    # the whole render stage as the user waits for it (preparation, Blender, frames,
    # ground truth), within the issue's ±30 % and some slack; the estimate is an idle
    # machine's, so the measured seconds are scaled by the share of the cores this
    # render had (a test worker beside another renders on a busy machine)
    import numpy as np

    from designer.render_time.record import core_share

    threads = max(1, os.cpu_count() or 1)
    share = float(np.median([core_share(st, threads)
                             for st in summary.report.stages.values()]))
    print(f"estimate {estimate:.1f} s, measured {measured:.1f} s at {share:.2f} of the cores")
    assert 0.6 < estimate / (measured * share) < 1.6, (estimate, measured, share, speed)
    # the manifest records each image's stages, the Cycles render among them
    import json

    manifest = json.loads(summary.manifest.read_text())
    stages = [e["stages"] for e in manifest["images"].values()]
    assert all(s["cycles_s"] > 0 and s["cycles_cpu_s"] > 0 for s in stages)
    assert all(s["blender_write_s"] >= 0 for s in stages)
    assert manifest["ground_truth_seconds"] >= 0


@pytest.mark.blender
def test_an_estimate_does_not_follow_a_different_project_rendered_in_between(tmp_path):
    """A's estimate after rendering A, then after rendering B (1 sample per pixel on
    tiny images: a cost per megapixel-sample many times A's) is the same within 10 %:
    B's frames are recorded under B's own kind and do not move A's figures."""
    a = small_survey(n_photos=9, samples=16, size_px=(240, 180))
    b = small_survey(n_photos=9, samples=1, size_px=(64, 48))
    path_a = write_project_file(a, tmp_path / "a")
    path_b = write_project_file(b, tmp_path / "b")
    render_project(path_a, tmp_path / "out-a", workers=1)
    before = plan_project(a, path_a.parent).analysis.render_time_s
    render_project(path_b, tmp_path / "out-b", workers=1)
    after = plan_project(a, path_a.parent).analysis.render_time_s
    print(f"A's estimate {before:.2f} s, after rendering B {after:.2f} s")
    assert 0.9 < after / before < 1.1, (before, after)
