"""The window judges camera stations against what it draws (the terrain, buildings and
plants it computed) as ``designer check`` judges them against what it builds: the same
stations, the same lowest clearance (Qt-free, issue #53 finding 1)."""

from __future__ import annotations

import contextlib
import io
import re

from designer.cli.main import main


def test_the_window_and_check_find_the_same_stations_in_buildings_and_trees(tmp_path):
    from designer.checks.station_clearance import clearance_issues
    from designer.gui.state import derived
    from designer.gui.state.station_problems import (
        station_problem_lines,
        window_low_stations,
    )
    from designer.project import load_project

    path = tmp_path / "p.xml"
    with contextlib.redirect_stdout(io.StringIO()):
        assert main(["new", str(path), "--template", "survey-structures"]) == 0
    text = re.sub(r"<altitude-agl-m>[^<]*<", "<altitude-agl-m>6<", path.read_text())
    path.write_text(text.replace("<terrain-following>false", "<terrain-following>true"))
    project = load_project(path)
    (issue,) = clearance_issues(project, tmp_path)
    low = issue.value
    assert low.under == "buildings" and low.kinds == ("buildings", "vegetation"), low
    assert low.lowest_m < -3  # 6 m above the ground under 8–12 m roofs

    terrain = derived.compute_terrain(project, tmp_path)
    stations = derived.compute_stations(project, terrain)
    buildings = derived.compute_buildings(project, tmp_path, terrain)
    vegetation = derived.compute_vegetation(project, tmp_path, terrain)
    assert window_low_stations(project, terrain, stations, buildings, vegetation) == low
    # without the buildings and plants drawn yet, the terrain alone is clear
    assert window_low_stations(project, terrain, stations) is None
    (line,) = station_problem_lines(project, low)
    assert line.startswith(f"Flight › {low.n_low} of {low.n_stations} camera stations are "
                           "inside buildings or plants, or within 1 cm of them; the "
                           "lowest, "), line
    assert "below a building's roof" in line and "terrain following" not in line, line
