"""Round two, readings: render thumbnails in their images' shape and named, the cloud's
colour bar and histogram in one unit, a colour range of 0 refused, GCP labels that do
not cover the error labels, messages that do not move the fields, and the achieved
overlap written in words when it cannot be measured."""

from __future__ import annotations

import sys
import time

import numpy as np
import pytest
from PySide6.QtCore import QPoint, Qt
from PySide6.QtWidgets import QLabel

from designer.gui.qt.command_process import RenderProcess
from designer.gui.state import edits
from tests.gui.helpers import (
    add_hills_and_flight,
    open_panel,
    problems,
    set_field,
    wait_idle,
    write_xyz_ply,
)
from tests.gui.render_helpers import FAKE_RENDER

pytestmark = pytest.mark.gui


# ---------------------------------------------------------------------- thumbnails
def test_thumbnails_keep_the_image_shape_and_show_the_names(qtbot, window, monkeypatch,
                                                           tmp_path):
    """4:3 images rendered while the Render panel is on screen: each thumbnail is drawn
    120 × 90 px (not squeezed into the size of its text) with its name under it, even
    when the thumbnail is read after the item was laid out."""
    from designer.gui.qt.panels import render as render_panel

    w = window
    project = edits.set_flight(edits.ensure_flight_plan(w.document.project),
                               area=((-20.0, -20.0), (20.0, -20.0), (20.0, 20.0),
                                     (-20.0, 20.0)), altitude_agl_m=60.0)
    w.editor.edit(project, "small flight")
    wait_idle(qtbot, w)
    assert w.file_actions.save_to(tmp_path / "small.xml"), problems(w)
    # green 96 × 72 images (4:3)
    script = tmp_path / "fake_render.py"
    script.write_text(FAKE_RENDER.replace("(60, 90, 3)", "(72, 96, 3)")
                      .replace("image[:, : 10 * (i + 1)]", "image[:, :]"))
    monkeypatch.setattr(RenderProcess, "command", staticmethod(
        lambda project, out_dir, resume=False, quality=None, workers=None:
        [sys.executable, str(script), str(out_dir), "3", "0.05"]))
    read = render_panel._thumbnail
    # a slow disk: the list lays the items out before their thumbnails arrive
    monkeypatch.setattr(render_panel, "_thumbnail",
                        lambda path: (time.sleep(0.4), read(path))[1])

    panel = open_panel(w, "Render")
    qtbot.mouseClick(panel.start_button, Qt.MouseButton.LeftButton)
    qtbot.waitUntil(lambda: panel.start_button.isEnabled(), timeout=20000)
    wait_idle(qtbot, w)
    qtbot.wait(200)
    thumbs = panel.thumbs
    assert thumbs.count() == 3
    image = thumbs.viewport().grab().toImage()
    metrics = thumbs.fontMetrics()
    for i in range(3):
        item = thumbs.item(i)
        name = panel.image_names[i].rsplit(".", 1)[0]
        assert item.text().splitlines()[0] == name
        rect = thumbs.visualItemRect(item)
        # room for the picture and, under it, the name and the time
        assert rect.height() >= 90 + 2 * metrics.height(), rect
        assert rect.width() >= max(120, metrics.horizontalAdvance(name)), rect
        # the green picture as drawn: 120 × 90 px, the image's 4:3
        xs, ys = [], []
        for y in range(rect.top(), rect.bottom() + 1, 1):
            for x in range(rect.left(), rect.right() + 1, 1):
                c = image.pixelColor(x, y)
                if c.green() > 150 and c.red() < 60 and c.blue() < 60:
                    xs.append(x)
                    ys.append(y)
        assert xs, f"no picture drawn for {name}"
        width, height = max(xs) - min(xs) + 1, max(ys) - min(ys) + 1
        assert (width, height) == (120, 90), (name, width, height)
        # the name is written below the picture, inside the item
        assert max(ys) + metrics.height() <= rect.bottom() + 1


# ---------------------------------------------------------------------- results
def _cloud(qtbot, w, tmp_path):
    add_hills_and_flight(w)
    wait_idle(qtbot, w)
    hf = w.sync.terrain.heightfield
    rng = np.random.default_rng(2)
    x, y = rng.uniform(-30, 30, 500), rng.uniform(-30, 30, 500)
    write_xyz_ply(tmp_path / "cloud.ply",
                  np.column_stack([x, y, hf.height_at(x, y) + rng.normal(0, 0.01, 500)]))
    results = open_panel(w, "Results")
    results.open_cloud(tmp_path / "cloud.ply")
    wait_idle(qtbot, w)
    assert results.result is not None
    return results


def test_colour_bar_and_histogram_in_millimetres(qtbot, window, tmp_path):
    w = window
    results = _cloud(qtbot, w, tmp_path)
    bars = w.view.plotter.scalar_bars
    assert "signed distance (mm)" in bars and "signed distance (m)" not in bars
    lut = w.view.cloud_lookup_table()
    ax = results.figure.axes[0]
    assert "(mm)" in ax.get_xlabel()
    # the colour bar spans what the histogram spans, in the same unit
    assert lut.scalar_range == pytest.approx(ax.get_xlim())
    assert lut.scalar_range == pytest.approx(results.histogram_range_mm)
    drawn = w.view.layer_data("cloud")
    np.testing.assert_allclose(np.asarray(drawn["signed distance (mm)"]),
                               1000 * results.result.distances_m, rtol=1e-6)


def test_colour_range_of_zero_is_refused(qtbot, window, tmp_path):
    w = window
    results = _cloud(qtbot, w, tmp_path)
    before = w.view.cloud_lookup_table().scalar_range
    xlim = results.figure.axes[0].get_xlim()
    for typed in ("0", "0.04"):
        set_field(qtbot, results.range_spin, typed)
        assert results.range_spin.error, f"{typed} mm accepted"
        assert "not applied" in results.range_spin.error
        message = results.findChild(QLabel, "input-errors")
        assert message.isVisible() and "Colour range" in message.text()
        assert w.view.cloud_lookup_table().scalar_range == pytest.approx(before)
        assert results.figure.axes[0].get_xlim() == pytest.approx(xlim)
    set_field(qtbot, results.range_spin, "0.1")
    assert not results.range_spin.error
    assert w.view.cloud_lookup_table().scalar_range == pytest.approx((-0.1, 0.1))
    assert results.figure.axes[0].get_xlim() == pytest.approx((-0.1, 0.1))


def _labels(w, name: str) -> list[str]:
    """The texts of a label layer of the view, as VTK draws them."""
    actor = w.view.plotter.actors.get(f"{name}-labels")
    if actor is None or not actor.GetVisibility():
        return []
    data = actor.GetMapper().GetInputAlgorithm().GetInputDataObject(0, 0)
    array = data.GetPointData().GetAbstractArray("labels")
    return [array.GetValue(i) for i in range(array.GetNumberOfValues())]


def test_gcp_labels_leave_the_error_labels_alone(qtbot, window, tmp_path):
    """A GCP with an error label is named by it: its plain label is not drawn on top
    (a small error puts both at the same place); back when the errors are hidden."""
    w = window
    project = edits.add_target(edits.add_target(edits.add_target(
        w.document.project, 10.0, 5.0), -20.0, 15.0), 0.0, -25.0)
    w.editor.edit(project, "three GCPs")
    wait_idle(qtbot, w)
    assert sorted(_labels(w, "targets:labels")) == ["GCP01", "GCP02", "GCP03"]
    truth = w.sync.targets.true_xyz
    csv = tmp_path / "gcp_residuals.csv"
    csv.write_text("id,role,X,Y,Z\n"
                   f"GCP01,control,{truth[0, 0] + 0.001},{truth[0, 1]},{truth[0, 2]}\n"
                   f"GCP02,control,{truth[1, 0]},{truth[1, 1]},{truth[1, 2] + 0.03}\n")
    results = open_panel(w, "Results")
    results.open_residuals(csv)
    wait_idle(qtbot, w)
    errors = _labels(w, "residuals:labels")
    assert sorted(errors) == ["GCP01 1 mm", "GCP02 30 mm"]
    # GCP03 has no estimate: still named; the others by their error label only
    assert _labels(w, "targets:labels") == ["GCP03"]
    # no two labels at the same place on screen
    ren = w.view.plotter.renderer

    def on_screen(p):
        ren.SetWorldPoint(*(np.asarray(p) - w.view.offset), 1.0)
        ren.WorldToDisplay()
        return np.array(ren.GetDisplayPoint()[:2])

    lines = w.view.layer_data("residuals")
    tips = np.asarray(lines.points, dtype=float)[2:] + w.view.offset
    anchors = [on_screen(p) for p in tips] + [on_screen(truth[2])]
    for a in range(len(anchors)):
        for b in range(a + 1, len(anchors)):
            assert np.linalg.norm(anchors[a] - anchors[b]) > 20
    # errors hidden: every GCP named again; shown: de-cluttered again
    w.view.set_layer_visible("residuals", False)
    assert sorted(_labels(w, "targets:labels")) == ["GCP01", "GCP02", "GCP03"]
    w.view.set_layer_visible("residuals", True)
    assert _labels(w, "targets:labels") == ["GCP03"]
    results.clear()
    wait_idle(qtbot, w)
    assert sorted(_labels(w, "targets:labels")) == ["GCP01", "GCP02", "GCP03"]


# ---------------------------------------------------------------------- messages
def test_a_message_does_not_move_the_fields(qtbot, window):
    w = window
    w.editor.edit(edits.ensure_flight_plan(w.document.project), "a flight")
    panel = open_panel(w, "Flight")
    wait_idle(qtbot, w)
    box = panel.altitude_spin
    qtbot.waitUntil(box.isVisible)
    before = box.mapTo(w, QPoint(0, 0))
    message = panel.findChild(QLabel, "input-errors")
    assert not message.isVisible()
    box.setFocus()
    box.selectAll()
    qtbot.keyClicks(box.lineEdit(), "abc")
    qtbot.keyClick(box.lineEdit(), Qt.Key.Key_Return)
    qtbot.waitUntil(message.isVisible)
    qtbot.wait(50)
    assert "not a number" in message.text()
    assert box.mapTo(w, QPoint(0, 0)) == before
    # the message is seen: inside the panel, below the field
    assert message.mapTo(w, QPoint(0, 0)).y() > before.y()
    assert panel.rect().contains(message.geometry())


def test_gcp_message_does_not_move_the_layout_fields(qtbot, window):
    w = window
    w.editor.edit(edits.add_target(w.document.project, 10.0, 5.0), "a GCP")
    wait_idle(qtbot, w)
    panel = open_panel(w, "GCPs")
    qtbot.waitUntil(panel.count.isVisible)
    before = panel.count.mapTo(w, QPoint(0, 0))
    for column, text in ((2, "east"), (3, "north")):   # X, Y
        item = panel.table.item(0, column)
        panel.table.setCurrentItem(item)
        item.setText(text)          # as the cell editor commits it
    wait_idle(qtbot, w)
    assert len(panel.error_label.text().splitlines()) == 2
    assert panel.count.mapTo(w, QPoint(0, 0)) == before


# ---------------------------------------------------------------------- flight
def test_achieved_overlap_in_words_when_not_measured(qtbot, window):
    w = window
    panel = open_panel(w, "Flight")
    wait_idle(qtbot, w)
    # no flight yet: nothing to measure
    text = panel.real_overlap.text()
    assert "–" not in text and text.startswith("not computed"), text
    # one flight line over a narrow strip: no side overlap to measure
    project = edits.set_flight(edits.ensure_flight_plan(w.document.project),
                               area=((-40.0, -2.0), (40.0, -2.0), (40.0, 2.0),
                                     (-40.0, 2.0)), altitude_agl_m=80.0,
                               side_overlap_percent=0.0)
    w.editor.edit(project, "one line")
    wait_idle(qtbot, w)
    assert w.sync.plan is not None
    assert not np.isfinite(w.sync.plan.side_overlap_median)
    text = panel.real_overlap.text()
    assert "–" not in text, text
    assert "side overlap not measured" in text and "line" in text, text
    assert text.startswith("front "), text
