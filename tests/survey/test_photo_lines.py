"""Imported photos (a pose list, no flight plan) are read as the flight lines they were
flown in, so their front and side overlaps are measured as for the planned flight."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest

from designer.checks.plan_report import plan_project, project_with_explicit_poses
from designer.project.load import load_project
from designer.survey.project_poses import photo_lines

ROOT = Path(__file__).resolve().parents[2]
EXAMPLE = ROOT / "resources" / "examples" / "survey" / "survey.xml"


def runs(index) -> np.ndarray:
    """Where a new run of equal values starts (the partition, whatever the numbering)."""
    return np.flatnonzero(np.diff(np.asarray(index)) != 0) + 1


@pytest.mark.parametrize("crosshatch", [False, True])
def test_a_planned_flight_exported_as_photos_keeps_its_lines_and_overlaps(crosshatch):
    project = load_project(EXAMPLE)
    plan = dataclasses.replace(project.trajectory.flight_plan, crosshatch=crosshatch,
                               grid_angle_deg=25.0)
    project = dataclasses.replace(project, trajectory=dataclasses.replace(
        project.trajectory, flight_plan=plan))
    planned = plan_project(project, EXAMPLE.parent)
    photos = plan_project(project_with_explicit_poses(planned), EXAMPLE.parent)
    assert photos.project.trajectory.flight_plan is None
    a, b = planned.stations, photos.stations
    assert [s.image_name for s in a] == [s.image_name for s in b]
    assert np.array_equal(runs([s.line_index for s in a]), runs([s.line_index for s in b]))
    assert np.array_equal(runs([s.grid_index for s in a]), runs([s.grid_index for s in b]))
    assert len({s.grid_index for s in b}) == (2 if crosshatch else 1)
    pa, pb = planned.analysis.stations, photos.analysis.stations
    for name in ("front_overlap", "side_overlap_prev", "side_overlap_next"):
        x, y = getattr(pa, name), getattr(pb, name)
        assert np.array_equal(np.isnan(x), np.isnan(y)), name
        assert np.nanmax(np.abs(x - y)) < 0.005, name
    # the plan's figure over its area, measured on the photos
    inside = planned.analysis.station_inside_area
    assert np.nanmedian(pb.front_overlap[inside]) == pytest.approx(
        planned.analysis.summary()["front_overlap_median"], abs=0.005)


def test_a_turn_or_a_jump_starts_a_new_line():
    y = np.arange(6) * 10.0
    # line 1 north, line 2 south beside it (heading turned), line 3 north again after a
    # jump across the area, flown with the same heading as line 1
    xy = np.concatenate([np.column_stack([np.zeros(6), y]),
                         np.column_stack([np.full(6, 30.0), y[::-1]]),
                         np.column_stack([np.full(6, 200.0), y])])
    heading = np.r_[np.zeros(6), np.full(6, 180.0), np.zeros(6)]
    line, grid = photo_lines(xy, heading)
    assert line.tolist() == [0] * 6 + [1] * 6 + [2] * 6
    assert grid.tolist() == [0] * 18
    # a camera held north on every line (no turn of the heading): the track turns
    line, _ = photo_lines(xy[:12], np.zeros(12))
    assert line.tolist() == [0] * 6 + [1] * 6
    # a gap of two missing photos in a line is a jump of 3 spacings: a new line
    gap = np.delete(xy[:6], [2, 3], axis=0)
    assert photo_lines(gap, np.zeros(4))[0].tolist() == [0, 0, 1, 1]
