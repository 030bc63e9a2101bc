"""Helpers of the flight-file tests: photos as a drone writes them."""

from __future__ import annotations

from designer.project import load_project
from tests.flight.helpers import EXAMPLE, true_poses, write_dji_image


def _flown_images(folder, n: int):
    """DJI-style geotagged images of the example survey's first ``n`` true poses."""
    project = load_project(EXAMPLE)
    poses = true_poses(project, EXAMPLE.parent)[:n]
    folder.mkdir()
    for k, pose in enumerate(poses):
        write_dji_image(folder / f"DJI_{k + 1:04d}.JPG", pose, project.crs)
    return poses
