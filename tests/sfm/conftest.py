"""Rendered surveys shared by the SfM tests: rendered once per test run, whichever
pytest-xdist worker asks first (the others wait for it and read the same folder)."""

from __future__ import annotations

import contextlib
import dataclasses
import fcntl
import os
from collections.abc import Callable, Iterator
from pathlib import Path

import pytest

from designer.project import model as m
from designer.render.pipeline import render_project
from tests.synthetic import small_flight_survey, write_project_file


@contextlib.contextmanager
def _locked(path: Path) -> Iterator[None]:
    with open(path, "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        yield


def _run_folder(tmp_path_factory) -> Path:
    """The run's base temporary folder, the same for every xdist worker of the run."""
    base = tmp_path_factory.getbasetemp()
    if os.environ.get("PYTEST_XDIST_WORKER"):
        base = base.parent  # the workers' folders sit side by side in the run's folder
    return base


def _rendered_once(tmp_path_factory, name: str, project: Callable[[], m.Project]) -> Path:
    """``folder/out`` of ``project()`` rendered into a folder every worker of the run
    shares (the run's base temporary folder): the first worker to ask renders it under a
    lock, the others wait and take it (a marker written after the render says it
    finished; a folder without it is rendered again, resumed)."""
    base = _run_folder(tmp_path_factory)
    folder = base / f"shared-{name}"
    with _locked(base / f"shared-{name}.lock"):
        if not (folder / "rendered").is_file():
            folder.mkdir(exist_ok=True)
            render_project(write_project_file(project(), folder), folder / "out", workers=2,
                           resume=True)
            (folder / "rendered").touch()
    return folder / "out"


@pytest.fixture(scope="session")
def survey(tmp_path_factory):
    """A dozen 640 × 480 nadir images at 30 m (GSD 6 cm) of hilly terrain with 7 GCPs."""
    out = _rendered_once(tmp_path_factory, "sfm", small_flight_survey)
    assert len(list((out / "images").glob("*.png"))) <= 12
    return out


@pytest.fixture(scope="session")
def survey_cache(tmp_path_factory):
    """A feature cache (designer.sfm.feature_cache) every worker of the run shares, for
    the reconstructions of ``survey`` with its default settings (test_reconstruct.py,
    test_dense.py, test_reconstruct_dense.py): the features and matches of the known
    poses, and the features, matches and SfM model of a free run, are computed once per
    run by whichever test asks first (the cache locks a key while it is computed) and
    taken by the others. test_feature_cache.py shows a taken model gives the result of
    a run of its own; the tests that check extraction, matching or the cache themselves
    keep their own."""
    return _run_folder(tmp_path_factory) / "shared-sfm-feature-cache"


@pytest.fixture(scope="session")
def convergent_survey(tmp_path_factory):
    """The same area flown crosshatch with the camera tilted 20°, through a lens with
    barrel distortion (k1 = −0.08, k2 = 0.01): a convergent network for self-calibration."""
    def build() -> m.Project:
        project = small_flight_survey(distortion=m.BrownConradyDistortion(k1=-0.08, k2=0.01))
        plan = dataclasses.replace(project.trajectory.flight_plan, crosshatch=True,
                                   tilt_deg=20.0)
        project = dataclasses.replace(project, trajectory=m.Trajectory(flight_plan=plan))
        return dataclasses.replace(project, render=m.Render(preset="draft", workers=2))

    return _rendered_once(tmp_path_factory, "sfm-convergent", build)


@pytest.fixture(scope="session")
def two_camera_survey(tmp_path_factory):
    """The small flight flown by a two-camera rig: a 5 mm 640 × 480 nadir camera and a
    6 mm 560 × 420 camera tilted 20° forward, principal point off centre (24 images)."""
    from tests.synthetic import two_camera_survey as build

    return _rendered_once(tmp_path_factory, "sfm-rig", build)
