"""Terrain-aware planning in the Flight panel (problem 10 of the user test): the figures
``designer plan`` computes, in the window, with warnings for images that see past the
terrain (without surroundings), low overlap and GCPs seen by fewer than 3 images."""

from __future__ import annotations

import pytest

from designer.checks.plan_report import plan_project, plan_summary
from designer.gui.qt.panels.gcps import IMAGES_COLUMN
from designer.gui.state import edits
from tests.gui.helpers import problems, wait_idle

pytestmark = pytest.mark.gui


def test_flight_beyond_the_terrain_is_warned_about(qtbot, window, tmp_path):
    w = window
    project = edits.ensure_flight_plan(w.document.project)
    # the whole terrain as the area, flown high: the edge images overhang the terrain
    project = edits.set_flight(project, area=edits.terrain_rectangle(project),
                               altitude_agl_m=80.0)
    project = edits.add_target(edits.add_target(project, 0.0, 0.0), -49.0, 49.5)
    w.editor.edit(project, "a flight far beyond the terrain")
    w.docks["Flight"].raise_()
    wait_idle(qtbot, w)
    flight = w.panels["Flight"]
    # the flat terrain's default surroundings continue it as far as the images see
    assert "past the terrain" not in flight.warnings_label.text()
    w.editor.edit(edits.replace_path(w.document.project, "scene.terrain.surroundings",
                                     "none"), "no surroundings")
    wait_idle(qtbot, w)
    warnings = flight.warnings_label.text()
    assert "images see past the terrain" in warnings
    assert "worst IMG_" in warnings
    # the fix, as the window does it
    assert "choose surroundings “auto” in the Terrain panel" in warnings, warnings
    assert "<surroundings" not in warnings, warnings

    # the same figures as designer plan
    path = tmp_path / "beyond.xml"
    assert w.file_actions.save_to(path), problems(w)
    s = plan_summary(plan_project(w.document.project, tmp_path))
    f = w.sync.plan
    assert f.n_images == s["n_images"]
    assert f.images_over_area == s["stations_over_area"] < f.n_images
    assert f.gsd_min_m == pytest.approx(s["gsd_terrain_m"]["min"])
    assert f.gsd_max_m == pytest.approx(s["gsd_terrain_m"]["max"])
    assert f.gsd_median_m == pytest.approx(s["gsd_centre_m_median"])
    assert f"{100 * s['gsd_terrain_m']['min']:.2f} to" in flight.real_gsd.text()
    assert f"{s['stations_over_area']} of {s['n_images']} look at the area" in \
        flight.real_images.text()
    assert f"front {100 * s['front_overlap_median']:.0f} %" in flight.real_overlap.text()

    # images per GCP: a column of the GCP table; the corner GCP is seen by fewer than 3
    table = w.panels["GCPs"].table
    by_id = {g["id"]: g["images"] for g in s["gcps"]}
    for r in range(table.rowCount()):
        assert table.item(r, IMAGES_COLUMN).text() == str(by_id[table.item(r, 0).text()])
    assert all(n >= 3 for n in by_id.values()) and "GCPs seen" not in warnings

    # a flight over the terrain only, with ample overlap: no warnings
    inner = edits.set_flight(w.document.project, area=((-20.0, -20.0), (20.0, -20.0),
                                                       (20.0, 20.0), (-20.0, 20.0)),
                             altitude_agl_m=20.0)
    w.editor.edit(inner, "a flight over the terrain")
    wait_idle(qtbot, w)
    assert "past the terrain" not in flight.warnings_label.text()
    # … which leaves the corner GCP out of sight
    assert "GCPs seen by fewer than 3 images: GCP02" in flight.warnings_label.text()
    row = [table.item(r, 0).text() for r in range(table.rowCount())].index("GCP02")
    assert int(table.item(row, IMAGES_COLUMN).text()) < 3
    assert table.item(row, IMAGES_COLUMN).background().color().red() > 200

    # low overlap is warned about
    w.editor.edit(edits.set_flight(w.document.project, front_overlap_percent=20.0,
                                   side_overlap_percent=10.0), "low overlap")
    wait_idle(qtbot, w)
    text = flight.warnings_label.text()
    assert "low front overlap" in text and "(planned 20 %)" in text
    assert "low side overlap" in text
