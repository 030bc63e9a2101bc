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
from collections.abc import Callable
from pathlib import Path

import numpy as np

from designer.errors import DesignerError

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


def tie_point_dome(rec, project_path: Path | None, gsd_m: float,
                   log: Callable[[str], None]) -> dict | None:
    """The dome of the tie points of the world-frame model ``rec`` over the survey area
    (:func:`sparse_dome`), or None without the project or with too few points; a dome
    that cannot be measured is logged, not an error."""
    if project_path is None or not Path(project_path).is_file():
        return None
    points = np.array([pt.xyz for pt in rec.points3D.values()]).reshape(-1, 3)
    try:
        dome = sparse_dome(points, project_path, gsd_m)
    except DesignerError as error:
        log(f"tie-point dome not measured: {error}")
        return None
    if dome is not None:
        log(f"tie points: {dome['kind']} {dome['amplitude_m']:+.4f} m "
            f"({dome['amplitude_gsd']:+.2f} GSD) over {dome['area']}")
    return dome
