"""Render provenance in the window, with Blender for real: a tiny survey (96 × 72 px
images) is rendered, the terrain is changed in the window, Render and Results say "out
of date" with the reason, Render re-renders what changed, and all is up to date again."""

from __future__ import annotations

import pytest
from PySide6.QtCore import Qt
from PySide6.QtWidgets import QDoubleSpinBox

from tests.gui.helpers import field, set_field
from tests.gui.tiny_survey_helpers import (
    record_reconstruction,
    render_from_the_panel,
    reopen_reconstructed,
    save_tiny_survey,
    wait_state,
)

pytestmark = [pytest.mark.gui, pytest.mark.blender, pytest.mark.slow]


def test_terrain_edit_marks_render_and_results_out_of_date(qtbot, window, tmp_path):
    pytest.importorskip("bpy")
    w = window
    path, n = save_tiny_survey(qtbot, w, tmp_path)
    render, results = w.panels["Render"], w.panels["Results"]
    assert not render.out_of_date.isVisible() or not render.out_of_date.stale

    render_from_the_panel(qtbot, w, n)
    wait_state(qtbot, w, lambda: render.out_of_date.text().startswith(f"the {n} rendered"))
    assert not render.out_of_date.stale and render.start_button.text() == "Render"

    # a reconstruction of these images, recorded with the digests it was made from
    record_reconstruction(w, path, with_settings=False)
    reopen_reconstructed(qtbot, w, path)
    assert not results.out_of_date.stale

    # the terrain changes in the window: every image is out of date, for the scene and
    # (flown at a height above the ground) for its pose
    set_field(qtbot, field(w, QDoubleSpinBox, "scene.terrain.source.height_m"), "1.5")
    assert w.document.project.scene.terrain.source.height_m == 1.5
    wait_state(qtbot, w, lambda: render.out_of_date.stale)
    text = render.out_of_date.text()
    assert text == (f"{n} images out of date: the terrain, the pose; ground truth out of "
                    "date (the project changed since it was written)"), text
    assert render.start_button.text() == f"Re-render {n} changed images"
    assert results.out_of_date.stale
    assert "the rendered images no longer match the project (" in results.out_of_date.text()
    # undone, the images are the project's again
    w.undo_stack.undo()
    wait_state(qtbot, w, lambda: not render.out_of_date.stale)
    w.undo_stack.redo()
    wait_state(qtbot, w, lambda: render.out_of_date.stale)

    # re-render what changed (saves first): up to date again
    qtbot.mouseClick(render.start_button, Qt.MouseButton.LeftButton)
    qtbot.waitUntil(lambda: render.start_button.isEnabled(), timeout=600000)
    assert not w.document.dirty
    assert render.state.text().startswith(f"done: {n} images"), render.log.toPlainText()
    wait_state(qtbot, w, lambda: render.out_of_date.text().startswith(f"the {n} rendered"))
    assert not render.out_of_date.stale and render.start_button.text() == "Render"
    # the reconstruction was made from the images before: out of date until redone
    assert results.out_of_date.text() == (
        f"out of date: {n} images rendered anew since this reconstruction: reconstruct again")
