"""``designer gui --screenshot`` and ``designer bench gui`` end to end."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from designer.project.new import write_template

pytestmark = pytest.mark.gui
ROOT = Path(__file__).resolve().parents[2]


def _designer(*args: str, cwd: Path) -> subprocess.CompletedProcess:
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    return subprocess.run([sys.executable, "-m", "designer", *args], cwd=cwd, env=env,
                          capture_output=True, text=True, timeout=600)


def test_screenshot_opens_renders_saves_and_exits(tmp_path):
    import cv2

    write_template(tmp_path / "survey.xml", "survey")
    result = _designer("gui", "survey.xml", "--screenshot", "shot.png", "--panel", "GCPs",
                       cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    image = cv2.imread(str(tmp_path / "shot.png"))
    assert image is not None and image.shape[:2] == (1000, 1600)
    # the 3D view in the middle is not blank: textured terrain and overlays
    view = image[100:900, 500:1100]
    assert view.std() > 20


def test_screenshot_of_a_broken_project_fails_with_its_problems(tmp_path):
    (tmp_path / "bad.xml").write_text("<project/>")
    result = _designer("gui", "bad.xml", "--screenshot", "shot.png", cwd=tmp_path)
    assert result.returncode == 2
    assert "bad.xml" in result.stderr and not (tmp_path / "shot.png").exists()


def test_gui_benchmark_runs_small(tmp_path):
    result = _designer("bench", "gui", "--scale", "0.01", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    assert "edit -> updated frame (median)" in result.stdout


def test_gui_benchmark_at_survey_size_runs_small(tmp_path):
    """``designer bench gui --images N`` (issue 53, at survey size), on a small block: the
    window's render estimate and void figures are designer plan's."""
    result = _designer("bench", "gui", "--images", "60", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    out = result.stdout
    assert "edit -> frame with the new stations (median)" in out
    assert "no freeze over 5 s (0 here)" in out
    assert out.count("(equal)") == 2 and "DIFFERENT" not in out, out


def test_only_the_gui_benchmark_takes_images(tmp_path):
    result = _designer("bench", "core", "--images", "60", cwd=tmp_path)
    assert result.returncode != 0
    assert "--images: only 'designer bench gui' takes it" in result.stderr
