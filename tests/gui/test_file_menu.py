"""The File menu says what went wrong in the window's words: a recent project that was
moved or deleted is named as gone and leaves Open Recent (no line:column of a file that
is not there, no command line to type)."""

from __future__ import annotations

import pytest

from tests.gui.helpers import choose_menu, problems, wait_idle

pytestmark = pytest.mark.gui


def test_a_recent_project_that_is_gone_is_said_so_and_leaves_the_list(qtbot, window,
                                                                      tmp_path):
    w = window
    assert w.file_actions.new("survey")
    wait_idle(qtbot, w)
    kept, gone = tmp_path / "kept.xml", tmp_path / "gone.xml"
    assert w.file_actions.save_to(kept), problems(w)
    assert w.file_actions.save_to(gone), problems(w)
    gone.unlink()
    qtbot.wait(100)  # the window draws its menus again after the saves
    choose_menu(qtbot, w, "File", "Open Recent", str(gone.resolve()))
    wait_idle(qtbot, w)
    lines = problems(w)
    assert w.docks["Problems"].isVisible()
    assert len(lines) == 1, lines
    line = lines[0]
    assert "gone.xml" in line and "no longer exists" in line
    assert "designer new" not in line and ":1:1" not in line and "<project>" not in line
    assert "Open Recent" in line
    # the entry left the menu; the other stays, and the project open is untouched
    assert w.file_actions.recent() == [str(kept.resolve())]
    titles = [a.text() for a in w.file_actions.recent_menu.actions()]
    assert titles == [str(kept.resolve())]
    assert w.document.path == gone
