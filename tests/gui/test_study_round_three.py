"""The Study panel names the right file, follows the open project and reads at the
window's size: an open project with unsaved changes that are not valid is reported at
its own file and line; after another project is opened the panel is about that one, and
a Run that is greyed says why; the base a factor varies around is said to be the
project's; each results chart has room to be read."""

from __future__ import annotations

import re

import pytest

from designer.gui.qt.widgets import format_number as num
from designer.project import project_to_bytes
from tests.gui.helpers import type_cell, wait_idle
from tests.gui.study_helpers import _add, _checked, _tiny_base

pytestmark = pytest.mark.gui


def test_an_invalid_open_project_is_reported_at_its_own_file_and_line(qtbot, window,
                                                                      tmp_path):
    w = window
    panel, base = _tiny_base(qtbot, w, tmp_path)
    # a GCP typed off the terrain: the project in the window is not valid, not saved
    w.docks["GCPs"].raise_()
    table = w.panels["GCPs"].table
    type_cell(qtbot, w, table, 0, 2, num(w.document.project.scene.terrain.extent.max_X + 500))
    wait_idle(qtbot, w)
    assert w.document.dirty
    w.docks["Study"].raise_()
    _add(qtbot, panel, "marking-sigma-px", "0.2 2")
    _checked(qtbot, w, panel)
    errors = panel.errors.text()
    assert panel.errors.isVisible() and not panel.run_box.run_button.isEnabled()
    assert "untitled-study.xml" not in errors, errors
    assert "unsaved changes" in errors.splitlines()[0], errors
    m = re.search(rf"^{re.escape(str(base))}:(\d+):(\d+): <true>: GCP .* lies outside the "
                  "terrain extent", errors, re.M)
    assert m, errors
    # the line of the project as it would be saved, where that GCP's <true> is
    saved = project_to_bytes(w.document.project).decode().splitlines()
    line = saved[int(m.group(1)) - 1]
    assert "<true" in line, line


def test_levels_that_are_not_numbers_are_refused_in_words(qtbot, window, tmp_path):
    w = window
    panel, _ = _tiny_base(qtbot, w, tmp_path)
    _add(qtbot, panel, "render-samples", "abc")
    _checked(qtbot, w, panel)
    errors = panel.errors.text()
    assert "factor render-samples: value 'abc' is not usable: not a whole number; write " \
           "one such as 3" in errors, errors
    assert "invalid literal" not in errors and "base 10" not in errors
