"""The dome of a reconstruction's clouds over the survey area (docs/processing.md,
"Doming: measured").

A self-calibrated block over flat ground can bend into a dome or bowl; the dense
stage measures it on the dense cloud's DEM of difference. The same fit on the sparse
(tie-point) cloud shows which stage moved the surface — SfM and the adjustment, or the
dense matcher — and measures the dome without dense matching. Both are fitted over the
area the flight plan covers (:func:`survey_area_world`): a cloud reaches as far beyond
it as the images look, farther for tilted images, and a peak-to-edge amplitude grows
with the square of the area fitted.
"""

from __future__ import annotations

import math

import numpy as np

#: a sparse DSM cell holds about this many tie points on average
SPARSE_POINTS_PER_CELL = 4.0


def survey_area_world(project) -> np.ndarray | None:
    """The area the project's flight plan covers ((K, 2) world polygon), the ground its
    dome is measured over; None without a flight plan (explicit exterior orientations
    only: the whole DoD)."""
    plan = project.trajectory.flight_plan
    return None if plan is None else np.asarray(plan.area, float)


def sparse_cell_m(points_xy: np.ndarray, gsd_m: float) -> float:
    """The DSM cell of a sparse cloud: 4 GSD, or larger so that a cell holds about
    :data:`SPARSE_POINTS_PER_CELL` points of the cloud's spread."""
    spread = np.ptp(points_xy, axis=0) if len(points_xy) else np.zeros(2)
    area = float(max(spread[0], gsd_m) * max(spread[1], gsd_m))
    return max(4.0 * gsd_m, math.sqrt(SPARSE_POINTS_PER_CELL * area / max(len(points_xy), 1)))


def sparse_dome(points_world: np.ndarray, project_path, gsd_m: float) -> dict | None:
    """The dome (dict: kind, amplitude m and GSD, area, cells, cell size) of the sparse
    cloud ``points_world`` (N, 3) against the project's true surface, over its survey
    area; None for fewer than 100 points."""
    from designer.evaluate.compare import reference_mesh
    from designer.evaluate.raster_products import cloud_dome
    from designer.project import load_project

    points = np.asarray(points_world, float)
    if len(points) < 100:
        return None
    project = load_project(project_path)
    return cloud_dome(points, reference_mesh(project_path), sparse_cell_m(points[:, :2], gsd_m),
                      gsd_m, survey_area_world(project))
