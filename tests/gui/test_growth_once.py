"""An edit of the flight grows the terrain's surroundings once: the stations job (frusta,
render estimate) and the plan figures over the rendered terrain share one growth."""

from __future__ import annotations

import pytest
from PySide6.QtCore import Qt

from designer.gui.state import edits
from designer.survey import surroundings
from tests.gui.helpers import open_panel, wait_idle
from tests.synthetic import count_calls

pytestmark = pytest.mark.gui


def test_a_flight_edit_grows_the_terrain_once(qtbot, window, monkeypatch):
    w = window
    w.editor.edit(edits.ensure_flight_plan(w.document.project), "a flight")
    panel = open_panel(w, "Flight")
    wait_idle(qtbot, w)
    assert w.sync.plan is not None
    planned = count_calls(monkeypatch, surroundings, "terrain_growth")
    grown = count_calls(monkeypatch, surroundings, "grow_terrain")
    box = panel.altitude_spin
    qtbot.waitUntil(box.isVisible)
    box.setFocus()
    box.selectAll()
    qtbot.keyClicks(box.lineEdit(), "70")
    qtbot.keyClick(box.lineEdit(), Qt.Key.Key_Return)
    wait_idle(qtbot, w)
    assert w.document.project.trajectory.flight_plan.altitude_agl_m == 70.0
    # the figures are the new flight's, over the terrain grown for it
    assert w.sync.plan is not None and w.sync.plan.n_images == w.sync.stations.n_images
    assert (len(planned), len(grown)) == (1, 1)
