"""The status bar says what is true of the project shown: a file refused on opening is
said so, and a good file opened after it takes that message away (issue 53, finding 4)."""

from __future__ import annotations

import pytest

from designer.project import template, write_project
from tests.gui.helpers import problems, wait_idle

pytestmark = pytest.mark.gui


def test_opening_a_good_file_after_a_refused_one_clears_cannot_open(qtbot, window,
                                                                    tmp_path):
    w = window
    refused = tmp_path / "root.xml"
    refused.write_text("<survey/>\n")  # not a project
    good = tmp_path / "good.xml"
    write_project(template("survey").project, good)

    assert not w.file_actions.open(refused)
    assert w.statusBar().currentMessage() == "Cannot open root.xml"
    assert w.file_actions.open(good), problems(w)
    # read at once: "opened …" is shown for 5 s, and a loaded machine can take longer
    # than that to finish the opened project's jobs
    assert w.statusBar().currentMessage() == "opened good.xml"
    wait_idle(qtbot, w)
    status = w.statusBar().currentMessage()
    assert "Cannot open" not in status, status
    assert not w.docks["Problems"].isVisible()
