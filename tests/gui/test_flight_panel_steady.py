"""The Flight panel holds still while the user edits it: warnings that come and go do
not move the area table under the mouse, and the area's errors number the vertices as
the table's rows do (from 1)."""

from __future__ import annotations

import pytest
from PySide6.QtCore import QCoreApplication, QEvent, QPoint

from designer.gui.state import edits
from tests.gui.helpers import LAYOUT_ROUNDS, wait_idle

pytestmark = pytest.mark.gui


def _table_top(flight) -> QPoint:
    return flight.area_table.mapTo(flight.window(), QPoint(0, 0))


def test_warnings_that_come_and_go_leave_the_area_table_in_place(qtbot, window):
    w = window
    # no surroundings: images that look past the terrain's edge see the background
    project = edits.replace_path(edits.ensure_flight_plan(w.document.project),
                                 "scene.terrain.surroundings", "none")
    inner = edits.set_flight(project, area=((-20.0, -20.0), (20.0, -20.0), (20.0, 20.0),
                                            (-20.0, 20.0)), altitude_agl_m=20.0)
    w.editor.edit(inner, "a flight over the terrain")
    w.docks["Flight"].raise_()
    wait_idle(qtbot, w)
    flight = w.panels["Flight"]
    assert "past the terrain" not in flight.warnings_label.text()
    before = _table_top(flight)

    far = edits.set_flight(w.document.project, area=edits.terrain_rectangle(project),
                           altitude_agl_m=80.0)
    w.editor.edit(far, "a flight beyond the terrain")
    wait_idle(qtbot, w)
    assert "images see past the terrain" in flight.warnings_label.text()  # they came
    assert _table_top(flight) == before

    w.undo_action.trigger()  # Edit → Undo: … and went
    wait_idle(qtbot, w)
    assert "past the terrain" not in flight.warnings_label.text()
    assert _table_top(flight) == before


def test_a_crossing_area_names_its_vertices_as_the_table_rows():
    from designer.errors import DesignerError
    from designer.survey.area import as_polygon

    bow_tie = [(0.0, 0.0), (10.0, 10.0), (10.0, 0.0), (0.0, 10.0)]
    with pytest.raises(DesignerError) as error:
        as_polygon(bow_tie)
    text = str(error.value)
    assert "vertex 1 to vertex 2" in text and "vertex 3 to vertex 4" in text
    assert "edge 3-0" not in text


def test_the_fields_stay_put_when_the_figures_of_a_new_flight_arrive(qtbot, window):
    """The figures (GSD, overlaps, estimates) are computed in worker threads after a
    template opens; arriving, they must not push the fields below them down under a
    mouse that is about to click one."""
    w = window
    w.docks["Flight"].raise_()
    assert w.file_actions.new("survey")
    flight = w.panels["Flight"]
    fields = (flight.camera, flight.altitude_spin, flight.noisy, flight.timed)
    # laid out for the new project (the event loop does it before the user can click)
    # while the figures are still being computed
    for _ in range(LAYOUT_ROUNDS):
        QCoreApplication.sendPostedEvents(None, QEvent.Type.LayoutRequest.value)
    assert flight.real_gsd.text() == "–"
    before = [f.mapTo(w, QPoint(0, 0)) for f in fields]
    wait_idle(qtbot, w)
    assert " to " in flight.real_gsd.text() and flight.images_label.text() == "60"
    assert [f.mapTo(w, QPoint(0, 0)) for f in fields] == before
    # the figures are on screen beside the fields, not scrolled away below them
    for label in (flight.images_label, flight.real_gsd):
        assert label.visibleRegion().boundingRect().height() >= label.height() - 1
