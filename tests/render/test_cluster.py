"""Rendering through a real (local) Dask cluster gives the same images as local workers."""

from __future__ import annotations

import cv2
import distributed
import numpy as np
import pytest

from designer.errors import DesignerError
from designer.render.pipeline import render_project
from tests.synthetic import small_survey, write_project_file

pytestmark = [pytest.mark.blender, pytest.mark.slow]


def test_dask_cluster_renders_the_same_images_as_local_workers(tmp_path):
    project = write_project_file(small_survey(n_photos=3, samples=8, size_px=(320, 240)), tmp_path)
    local = render_project(project, tmp_path / "local", workers=1)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster:
        remote = render_project(project, tmp_path / "dask", scheduler=cluster.scheduler_address)
    assert sorted(remote.report.rendered) == [0, 1, 2]
    for pose in local.prepared.poses:
        a = cv2.imread(str(tmp_path / "local" / "images" / pose.image_name))
        b = cv2.imread(str(tmp_path / "dask" / "images" / pose.image_name))
        # Same seed, same scene, same samples: Cycles is deterministic on one machine.
        assert np.array_equal(a, b)


def test_an_unreachable_scheduler_is_a_clear_error(tmp_path, small_project_file):
    project = small_project_file(n_photos=1, samples=1, size_px=(64, 48))
    with pytest.raises(DesignerError, match="cannot reach the Dask scheduler"):
        render_project(project, tmp_path / "out", scheduler="tcp://127.0.0.1:1")
