"""The Results panel on a rendered survey that has no reconstruction yet: it says what is
missing and how to make it, in place of the cloud of the project shown before."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest
from PySide6.QtCore import Qt
from PySide6.QtTest import QTest

from tests.gui.helpers import activate, open_panel, wait_idle, write_xyz_ply
from tests.gui.tiny_survey_helpers import save_tiny_survey, wait_state

pytestmark = [pytest.mark.gui, pytest.mark.blender, pytest.mark.slow]


def test_a_rendered_survey_without_a_reconstruction_says_so(qtbot, window, tmp_path):
    pytest.importorskip("bpy")
    w = window
    path, n = save_tiny_survey(qtbot, w, tmp_path)
    out = (path.parent / w.document.project.outputs.directory).resolve()
    results = open_panel(w, "Results")
    # saved, not rendered: what to do first
    assert w.open_project(path)
    wait_idle(qtbot, w)
    text = results.state.text()
    assert text.startswith("no reconstruction: the survey is not rendered yet in "
                           f"{out}"), text
    assert "Render panel" in text, text

    subprocess.run([sys.executable, "-m", "designer", "render", str(path), "-o", str(out)],
                   check=True, capture_output=True, cwd=tmp_path)
    # rendered meanwhile (by the command), then saved: the panel reads the folder anew
    activate(qtbot, w)
    QTest.keyClick(w.windowHandle(), Qt.Key.Key_S, Qt.KeyboardModifier.ControlModifier)
    wait_state(qtbot, w, lambda: results.state.text().startswith(
        f"no reconstruction in {out}: "), timeout_ms=20000)

    # another project's cloud shown in the panel …
    assert w.file_actions.new(None)
    wait_idle(qtbot, w)
    write_xyz_ply(tmp_path / "other.ply", np.array([[0.0, 0.0, 0.0], [1.0, 1.0, 0.5],
                                                    [2.0, 0.0, 0.2]]))
    results.open_cloud(tmp_path / "other.ply")
    wait_idle(qtbot, w)
    assert results.state.text().startswith("other.ply: 3 points")

    # … then the rendered survey opened: it has no reconstruction, and the panel says so
    assert w.open_project(path)
    wait_idle(qtbot, w)
    assert results.result is None and w.view.layer_data("cloud") is None
    text = results.state.text()
    assert text == (f"no reconstruction in {out}: press Reconstruct above to make one from "
                    f"its {n} rendered images"), text
    assert results.survey_label.text().startswith(f"{out}: {n} rendered images")
    assert results.gcp_table.rowCount() == 0 and results.rmse.text() == ""
    assert results.out_of_date.text() == ""

    # Clear after a cloud: the same words again, not the cloud's
    results.open_cloud(tmp_path / "other.ply")
    wait_idle(qtbot, w)
    clear = next(b for b in results.findChildren(type(results.reconstruct_button))
                 if b.text() == "Clear")
    qtbot.mouseClick(clear, Qt.MouseButton.LeftButton)
    assert results.state.text() == text
