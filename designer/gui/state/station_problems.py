"""Camera stations under the ground, over what the window has computed (Qt-free).

``designer check`` and ``designer plan`` refuse stations below the terrain, inside a
building or a plant (designer.checks.station_clearance); the window lists them among
its problems as the flight is edited. The stations, the terrain's height field, the
buildings' meshes and the plants are those the view draws, so asking after every edit
costs a bilinear height per station and a few box tests: milliseconds.
"""

from __future__ import annotations

import numpy as np

from designer.checks.station_clearance import (
    LowStations,
    low_stations,
    low_stations_issue,
    station_clearance,
)
from designer.project import model as m


def window_low_stations(project: m.Project, terrain, stations, buildings=None,
                        vegetation=None) -> LowStations | None:
    """The platform stations of ``stations`` (a designer.gui.state.derived.StationsResult)
    below, or within the camera's near distance of, the ``terrain``'s height field (a
    TerrainResult), the ``buildings`` (BuildingsResult) or the plants of ``vegetation``
    (VegetationResult); None when there are none or nothing to judge them by."""
    hf = terrain.heightfield if terrain is not None else None
    if hf is None or stations is None or not len(stations.stations):
        return None
    meshes = [] if buildings is None else [(buildings.vertices_world, buildings.faces)]
    plants = None if vegetation is None else vegetation.plants
    C = np.asarray(stations.C_world, dtype=float)
    clearance, what = station_clearance(C, hf, meshes, plants)
    return low_stations([s.image_name for s in stations.stations], clearance, what,
                        project.trajectory.flight_plan)


def station_problem_lines(project: m.Project, low: LowStations | None) -> list[str]:
    """``low`` as lines of the window's Problems list (``Flight › …``, in its words)."""
    from designer.gui.state.wording import issue_line

    return [issue_line(issue) for issue in low_stations_issue(project, low)]
