"""Rendered surveys shared by the SfM tests: rendered once per test session."""

from __future__ import annotations

import dataclasses

import pytest

from designer.project import model as m
from designer.render.pipeline import render_project
from tests.synthetic import small_flight_survey, write_project_file


@pytest.fixture(scope="session")
def survey(tmp_path_factory):
    """A dozen 640 × 480 nadir images at 30 m (GSD 6 cm) of hilly terrain with 7 GCPs."""
    folder = tmp_path_factory.mktemp("sfm")
    project = write_project_file(small_flight_survey(), folder)
    summary = render_project(project, folder / "out", workers=2)
    assert len(summary.prepared.poses) <= 12
    return folder / "out"


@pytest.fixture(scope="session")
def convergent_survey(tmp_path_factory):
    """The same area flown crosshatch with the camera tilted 20°, through a lens with
    barrel distortion (k1 = −0.08, k2 = 0.01): a convergent network for self-calibration."""
    folder = tmp_path_factory.mktemp("sfm-convergent")
    project = small_flight_survey(distortion=m.BrownConradyDistortion(k1=-0.08, k2=0.01))
    plan = dataclasses.replace(project.trajectory.flight_plan, crosshatch=True, tilt_deg=20.0)
    project = dataclasses.replace(project, trajectory=m.Trajectory(flight_plan=plan))
    project = dataclasses.replace(project, render=m.Render(preset="draft", workers=2))
    render_project(write_project_file(project, folder), folder / "out", workers=2)
    return folder / "out"


@pytest.fixture(scope="session")
def two_camera_survey(tmp_path_factory):
    """The small flight flown by a two-camera rig: a 5 mm 640 × 480 nadir camera and a
    6 mm 560 × 420 camera tilted 20° forward, principal point off centre (24 images)."""
    from tests.synthetic import two_camera_survey as build

    folder = tmp_path_factory.mktemp("sfm-rig")
    render_project(write_project_file(build(), folder), folder / "out", workers=2)
    return folder / "out"
