"""Opening a survey (issue 53, at survey size): the window is usable before the figures
over the terrain arrive. They are computed once per opening, in a worker thread, and the
Flight panel says they are being computed meanwhile; the flight is planned and the
terrain grown once for the stations, the images and the figures. Structural checks,
not timings: ``designer bench gui --images N`` measures the seconds."""

from __future__ import annotations

import threading

import pytest

from tests.gui.helpers import open_panel, wait_idle

pytestmark = pytest.mark.gui


def test_opening_a_survey_computes_its_figures_once_off_the_ui_thread(
        qtbot, window, tmp_path, monkeypatch):
    from designer.bench.gui_survey import survey_project
    from designer.gui.qt.panels.flight import COMPUTING, REAL_TITLE
    from designer.gui.state import plan_figures
    from designer.project import write_project
    from designer.survey import project_poses, surroundings

    def counted(module, name, calls):
        real = getattr(module, name)

        def call(*args, **kwargs):
            calls.append(threading.current_thread() is threading.main_thread())
            return real(*args, **kwargs)

        monkeypatch.setattr(module, name, call)

    figures, planned, grown = [], [], []
    counted(plan_figures, "compute_plan_figures", figures)
    counted(project_poses, "platform_stations", planned)
    counted(surroundings, "grown_terrain", grown)
    path = tmp_path / "block.xml"
    write_project(survey_project(60), path)
    w = window
    flight = open_panel(w, "Flight")
    said = []  # what the Flight panel said while the figures were computed

    def computing() -> None:
        if w.sync.plan_computing:
            said.append((flight.real_box.title(), flight.real_overlap.text(),
                         flight.real_overlap.isEnabled(), w.sync.stations is not None,
                         bool(flight.time_label.text())))

    w.sync.plan_computing_changed.connect(computing)
    assert w.file_actions.open(path)
    wait_idle(qtbot, w)

    assert figures == [False]  # once, in a worker thread
    assert planned == [False] and grown == [False]  # the stations job's, for all
    # the stations and the render estimate were up while the figures were computed
    assert said == [(f"{REAL_TITLE} — {COMPUTING}", COMPUTING, False, True, True)]
    assert not w.sync.plan_computing and w.sync.plan is not None
    assert flight.real_box.title() == REAL_TITLE
    assert flight.real_overlap.isEnabled() and flight.real_overlap.text().startswith("front")

    # a moved GCP is counted again as it is made, with the images the figures have: no
    # figures job, no flight planned again
    from designer.gui.state import edits

    t = w.document.project.targets[0]
    w.editor.edit(edits.move_target(w.document.project, t.id, t.true.X + 3.0, t.true.Y),
                  "Move GCP")
    wait_idle(qtbot, w)
    assert figures == [False] and planned == [False] and grown == [False]
    assert w.sync.plan.gcp_ids[0] == t.id


def test_figures_of_before_an_edit_are_greyed_while_the_new_ones_are_computed(
        qtbot, window, tmp_path):
    from designer.bench.gui_survey import survey_project
    from designer.gui.qt.panels.flight import COMPUTING, REAL_TITLE
    from designer.gui.state import edits
    from designer.project import write_project

    path = tmp_path / "block.xml"
    write_project(survey_project(60), path)
    w = window
    flight = open_panel(w, "Flight")
    assert w.file_actions.open(path)
    wait_idle(qtbot, w)
    before = w.sync.plan
    said = []

    def computing() -> None:
        if w.sync.plan_computing:
            said.append((flight.real_box.title(), flight.real_gsd.isEnabled(),
                         w.sync.plan is before))

    w.sync.plan_computing_changed.connect(computing)
    plan = w.document.project.trajectory.flight_plan
    w.editor.edit(edits.set_flight(w.document.project,
                                   altitude_agl_m=plan.altitude_agl_m + 5.0), "Flight height")
    wait_idle(qtbot, w)
    assert said == [(f"{REAL_TITLE} — {COMPUTING}", False, True)]
    assert w.sync.plan is not before and flight.real_gsd.isEnabled()
