"""Round two, with Blender for real: the Render and Results panels' out-of-date lines
read as sentences, follow every change that matters (processing too), and are right
the moment a render finishes. Tiny surveys (96 × 72 px images, draft)."""

from __future__ import annotations

import dataclasses

import pytest
from PySide6.QtCore import Qt
from PySide6.QtWidgets import QDoubleSpinBox

from designer.gui.state import edits
from tests.gui.helpers import field, set_field
from tests.gui.tiny_survey_helpers import (
    record_reconstruction,
    render_from_the_panel,
    reopen_reconstructed,
    save_tiny_survey,
    wait_state,
)

pytestmark = [pytest.mark.gui, pytest.mark.blender, pytest.mark.slow]


def _tiny_survey(qtbot, w, tmp_path, gcps: bool = True):
    """A tiny survey (two GCPs) saved, rendered and "reconstructed" (the record designer
    reconstruct leaves: the digests of the images and summary.json with the processing
    settings); reopened. Returns the project path and the number of images."""
    pytest.importorskip("bpy")
    path, n = save_tiny_survey(qtbot, w, tmp_path, gcps)
    render_from_the_panel(qtbot, w, n)
    record_reconstruction(w, path)
    reopen_reconstructed(qtbot, w, path)
    return path, n


def test_results_say_in_a_sentence_why_the_images_are_out_of_date(qtbot, window, tmp_path):
    w = window
    _path, n = _tiny_survey(qtbot, w, tmp_path)
    results = w.panels["Results"]

    set_field(qtbot, field(w, QDoubleSpinBox, "scene.terrain.source.height_m"), "1.5")
    wait_state(qtbot, w, lambda: results.out_of_date.stale)
    text = results.out_of_date.text()
    assert text.startswith(f"out of date: the rendered images no longer match the project "
                           f"({n} images out of date: the terrain"), text
    assert text.endswith("; render, then reconstruct again"), text
    assert "are (" not in text
    w.undo_stack.undo()
    wait_state(qtbot, w, lambda: not results.out_of_date.stale)

    # a project the render cannot be compared with (two GCPs of one id, as a hand-edited
    # file may have): said as such, not as a broken sentence
    targets = w.document.project.targets
    w.editor.edit(edits.set_targets(w.document.project, (
        targets[0], dataclasses.replace(targets[1], id=targets[0].id))), "same ids")
    wait_state(qtbot, w, lambda: results.out_of_date.stale)
    text = results.out_of_date.text()
    assert text.startswith("out of date: the rendered images cannot be compared with the "
                           "project ("), text
    assert "are (" not in text and "cannot compare" not in text


def test_a_processing_change_marks_the_reconstruction_out_of_date(qtbot, window, tmp_path):
    from PySide6.QtWidgets import QComboBox

    w = window
    _tiny_survey(qtbot, w, tmp_path)
    results = w.panels["Results"]
    processing = w.panels["Processing"]
    w.docks["Processing"].raise_()
    # the project's own settings, the defaults the reconstruction used: still up to date
    qtbot.mouseClick(processing.enabled, Qt.MouseButton.LeftButton)
    assert w.document.project.processing is not None
    wait_state(qtbot, w, lambda: True)
    assert not results.out_of_date.stale, results.out_of_date.text()

    mode = field(processing, QComboBox, "processing.gcps.mode")
    mode.setCurrentIndex(mode.findData("bundle"))
    assert w.document.project.processing.gcps.mode == "bundle"
    wait_state(qtbot, w, lambda: results.out_of_date.stale)
    assert results.out_of_date.text() == (
        "out of date: the processing settings changed since this reconstruction (GCPs): "
        "reconstruct again")
    # back to the settings it was made with: up to date again
    mode.setCurrentIndex(mode.findData("similarity"))
    wait_state(qtbot, w, lambda: not results.out_of_date.stale)
    assert results.out_of_date.text().startswith("reconstructed from")


def test_a_finished_resume_is_not_shown_out_of_date(qtbot, window, tmp_path):
    from designer.core.layout import images_dir

    w = window
    _path, n = _tiny_survey(qtbot, w, tmp_path, gcps=False)
    render = w.panels["Render"]
    w.docks["Render"].raise_()
    wait_state(qtbot, w, lambda: render.out_of_date.text().startswith(f"the {n} rendered"))
    first = sorted(images_dir(render.out_dir).glob("IMG_*"))[0]
    first.unlink()  # one image lost: the folder is out of date
    w.stale_watch.check_now()
    wait_state(qtbot, w, lambda: render.out_of_date.stale)
    assert render.out_of_date.text() == "out of date: 1 image not rendered"
    assert render.start_button.text() == "Re-render 1 changed image"

    seen = []  # what the panel says the moment the render is done (at 100 %)
    render.process.finished.connect(lambda *_: seen.append(
        (render.progress.value(), render.out_of_date.isVisible(), render.out_of_date.stale,
         render.out_of_date.text())))
    qtbot.mouseClick(render.start_button, Qt.MouseButton.LeftButton)
    assert not render.out_of_date.stale  # the render is changing the folder right now
    qtbot.waitUntil(lambda: render.start_button.isEnabled(), timeout=600000)
    assert first.is_file()
    (value, _visible, stale, text), = seen
    assert value == n and not stale and "not rendered" not in text, text
    wait_state(qtbot, w, lambda: render.out_of_date.text().startswith(f"the {n} rendered"))
    assert not render.out_of_date.stale and render.start_button.text() == "Render"
