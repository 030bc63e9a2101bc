"""``designer bench reconstruct`` at a small scale: the table's content, never its times."""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
STAGES = ("features", "matching", "mapping", "adjustment", "dense", "fusion", "rasters")


def _designer(*args: str, cwd: Path) -> subprocess.CompletedProcess:
    env = dict(os.environ, PYTHONPATH=str(ROOT), GLOG_minloglevel="2")
    return subprocess.run([sys.executable, "-m", "designer", *args], cwd=cwd, env=env,
                          capture_output=True, text=True, timeout=1200)


def _with_features(survey: Path, folder: Path, max_features: int) -> Path:
    """``survey``'s images and ground truth (linked, not copied) under a manifest naming
    a copy of its project whose ``<processing>`` asks for ``max_features`` SIFT features
    an image: what the bench takes from the survey's project."""
    import dataclasses

    from designer.project import load_project, write_project
    from designer.project import model as m

    out = folder / "survey"
    out.mkdir(parents=True)
    for name in ("images", "ground-truth"):
        (out / name).symlink_to(survey / name, target_is_directory=True)
    project = load_project(survey.parent / "project.xml", check_files=False)
    write_project(dataclasses.replace(project, processing=m.Processing(
        matching=m.Matching(max_features))), folder / "project.xml")
    manifest = json.loads((survey / "manifest.json").read_text())
    manifest["project"] = str(folder / "project.xml")
    (out / "manifest.json").write_text(json.dumps(manifest))
    return out


def test_bench_reconstruct_prints_seconds_per_stage_of_a_rendered_survey(survey, tmp_path):
    # 2048 SIFT features an image (not 8192), from the survey's project: the table's
    # content is under test, and designer's and COLMAP's command line's features,
    # matching and mapping take a fraction of the time
    survey = _with_features(survey, tmp_path / "in", 2048)
    run = _designer("bench", "reconstruct", "--survey", str(survey), "--scale", "0.25",
                    cwd=tmp_path)
    assert run.returncode == 0, run.stderr
    lines = run.stdout.splitlines()
    assert f"of {survey}:" in lines[0] and "dense matching at 171 px" in lines[0]
    registered, images = map(int, re.search(r"(\d+)/(\d+) images registered", lines[0]).groups())
    assert images == len(list((survey / "images").glob("*.png"))) and registered == images
    # one row per stage in processing order, then the total, each with a wall time
    rows = [line.split() for line in lines[2:10]]
    assert [r[0] for r in rows] == [*STAGES, "total"]
    for r in rows:
        float(r[1])
    # the dense matcher's rows and the total carry CPU seconds; the sparse ones do not;
    # with COLMAP's command line installed, features, matching and mapping carry its
    # seconds for the same steps
    cli = shutil.which("colmap") is not None
    assert [len(r) for r in rows] == ([3, 3, 3, 2, 3, 3, 2, 3] if cli else
                                      [2, 2, 2, 2, 3, 3, 2, 3])
    if cli:
        assert all(float(r[2]) > 0 for r in rows[:3])
        assert "images registered" in run.stdout.splitlines()[-1]
    written = json.loads((tmp_path / "bench-reconstruct" / "bench-reconstruct.json").read_text())
    summary = json.loads(
        (tmp_path / "bench-reconstruct" / "reconstruction" / "summary.json").read_text())
    assert summary["settings"]["dense"] == "cpu" and summary["dense"]["status"] == "ok"
    assert summary["settings"]["matching"]["max_features"] == 2048  # the project's
    points = summary["dense"]["points"]
    assert points > summary["points"] and written[-1]["dense_points"] == points
    assert f"dense points {points}," in run.stdout
    per_s = float(re.search(r", (\d+) per wall second", run.stdout).group(1))
    assert per_s == round(points / summary["stage_seconds"]["dense_s"])
    # the printed fusion row is the matcher's own fusion time
    assert float(rows[5][1]) == round(summary["dense"]["stage_seconds"]["fusion_s"], 1)


def test_survey_option_is_refused_where_it_does_not_apply(survey, tmp_path):
    run = _designer("bench", "dense", "--survey", str(survey), cwd=tmp_path)
    assert run.returncode == 2 and "--survey" in run.stderr
    run = _designer("bench", "reconstruct", "--survey", str(tmp_path), cwd=tmp_path)
    assert run.returncode == 2 and "manifest.json" in run.stderr
    assert not (tmp_path / "bench-reconstruct").exists()
