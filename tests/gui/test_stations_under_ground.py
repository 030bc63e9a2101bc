"""A flight inside the hills is a problem of the window, as of ``designer check``: the
Problems list names how many camera stations are under the ground, the lowest clearance
and the fix in the Flight panel's words, and the Flight panel shows no figures measured
from under the ground; raising the flight clears it (issue #53, finding 1)."""

from __future__ import annotations

import pytest
from PySide6.QtWidgets import QLabel

from tests.gui.helpers import answer_file_dialog, choose_menu, open_panel, problems, wait_idle
from tests.survey.scenes import survey_flown

pytestmark = pytest.mark.gui


def test_a_flight_inside_the_hills_is_listed_until_it_is_raised(qtbot, window, tmp_path):
    from designer.gui.state import edits

    w = window
    path = survey_flown(tmp_path, 5.0)
    answer_file_dialog(path)
    choose_menu(qtbot, w, "File", "Open…")
    wait_idle(qtbot, w)
    assert w.document.path == path
    qtbot.waitUntil(lambda: any("camera stations" in line for line in problems(w)),
                    timeout=20000)
    (line,) = problems(w)
    assert line.startswith("Flight › "), line
    assert (" of 3600 camera stations are below the terrain or within 1 cm of it; the "
            "lowest, ") in line, line
    assert " m below it: their images would be taken from inside the scene; raise the height " \
           "above ground in the Flight panel by more than " in line, line
    assert "altitude-agl-m" not in line and "<" not in line, line
    assert w.docks["Problems"].isVisible()
    label = open_panel(w, "Flight").findChild(QLabel, "plan-warnings")
    wait_idle(qtbot, w)
    # no GSD, texel or overlap figures measured from under the ground
    assert "texel" not in label.text() and "overlap" not in label.text(), label.text()

    w.editor.edit(edits.set_flight(w.document.project, altitude_agl_m=20.0), "fly higher")
    wait_idle(qtbot, w)
    qtbot.waitUntil(lambda: not problems(w), timeout=20000)
    assert not w.docks["Problems"].isVisible()
