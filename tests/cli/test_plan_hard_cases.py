"""``designer plan`` warns of nearly collinear control and of a network too thin for
structure from motion in ``designer check``'s words, over a procedural terrain and over a
terrain mesh (which it cannot analyse)."""

from __future__ import annotations

import subprocess
import sys
from dataclasses import replace

from tests.hard_cases import scenes
from tests.synthetic import write_project_file

#: the elements of the warnings that need no height field
ELEMENTS = ("<targets>: ", "<trajectory>: ")


def _collinear_and_thin():
    """Five control GCPs nearly on one line, seen by two photos."""
    project = scenes.surveyed_at_true(scenes.collinear_control(0.5))
    two = project.trajectory.exterior_orientations[:2]
    return replace(project, trajectory=replace(project.trajectory,
                                               exterior_orientations=two))


def _designer(*args) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "designer", *map(str, args)],
                          capture_output=True, text=True, timeout=300)


def _check_warnings(path) -> list[str]:
    check = _designer("check", path)
    assert check.returncode == 0, check.stderr
    lines = [e for e in check.stderr.splitlines() if any(x in e for x in ELEMENTS)]
    assert len(lines) == 2, check.stderr
    assert "nearly collinear" in lines[0] and "2 images" in lines[1], lines
    return lines


def test_plan_over_a_terrain_mesh_warns_as_check_does(tmp_path):
    path = scenes.on_a_terrain_mesh(_collinear_and_thin(), tmp_path)
    expected = _check_warnings(path)
    plan = _designer("plan", path)
    err = plan.stderr.splitlines()
    assert "Traceback" not in plan.stderr
    assert [e for e in err if e.startswith("warning: ")] == expected, plan.stderr
    # the analysis itself still needs a height field, and says so last
    assert plan.returncode == 2 and "a mesh terrain cannot be analysed" in err[-1], err


def test_plan_over_a_procedural_terrain_warns_as_check_does(tmp_path):
    path = write_project_file(_collinear_and_thin(), tmp_path)
    expected = [e.split(">: ", 1)[1] for e in _check_warnings(path)]
    plan = _designer("plan", path)
    assert plan.returncode == 0, plan.stderr
    warned = [e.split("warning: ", 1)[1] for e in plan.stdout.splitlines()
              if e.startswith("  warning: ")]
    for line in expected:
        assert warned.count(line) == 1, plan.stdout
