"""The study factor ``rolling-shutter-readout-s``: 0 is a global shutter."""

from __future__ import annotations

import dataclasses

import pytest

from designer.project import model as m
from designer.project import template
from designer.project.validate import semantic_problems
from designer.study.factors import FACTORS
from tests.world.rolling_helpers import rolling_project


def test_readout_sets_removes_and_adds_the_rolling_shutter():
    f = FACTORS["rolling-shutter-readout-s"]
    assert f.stage == "render"
    p = rolling_project(readout_s=0.03, direction="bottom-to-top")
    assert f.get(p) == 0.03
    slower = f.set(p, f.parse("0.05"))
    assert slower.cameras[0].rolling_shutter == m.RollingShutter(0.05, "bottom-to-top")
    off = f.set(p, f.parse("0"))
    assert off.cameras[0].rolling_shutter is None and f.get(off) == 0.0
    on = f.set(off, 0.02)
    assert on.cameras[0].rolling_shutter == m.RollingShutter(0.02, "top-to-bottom")
    assert semantic_problems(on) == []
    # a level past the range is refused by the project's own validation
    assert any("readout-s = 0.9" in p.message for p in semantic_problems(f.set(p, 0.9)))


def test_a_readout_needs_the_base_project_to_have_a_time_line():
    f = FACTORS["rolling-shutter-readout-s"]
    example = template("survey").project
    assert example.trajectory.time_line is None and f.get(example) == 0.0
    with pytest.raises(ValueError, match="no time line"):
        f.set(example, 0.03)
    timed = dataclasses.replace(example, trajectory=dataclasses.replace(
        example.trajectory, time_line=m.TimeLine("2026-06-21T09:30:00Z", 8.0)))
    assert f.get(f.set(timed, 0.03)) == 0.03
