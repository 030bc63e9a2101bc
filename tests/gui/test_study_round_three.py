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
    # in the Problems list's words: led by the panel that fixes it, not by <true>
    m = re.search(rf"^{re.escape(str(base))}:(\d+):(\d+): GCPs › GCP .* lies outside the "
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
    assert "“render samples per pixel”: value 'abc' is not usable: not a whole number; " \
           "write one such as 3" in errors, errors
    assert "invalid literal" not in errors and "base 10" not in errors


def _finished_study(folder, name: str, runs: list[str]) -> None:
    """What ``designer study run -o folder`` leaves when every run is done."""
    import json

    (folder / "runs").mkdir(parents=True)
    (folder / "study.json").write_text(json.dumps({"name": name, "runs": runs}))
    for run in runs:
        (folder / "runs" / run).mkdir()
        (folder / "runs" / run / "result.json").write_text(json.dumps(
            {"run": run, "status": "ok"}))
    (folder / "results.csv").write_text("run,status\n" + "".join(f"{r},ok\n" for r in runs))
    (folder / "summary.json").write_text(json.dumps({"study": name, "runs": len(runs)}))


def _run_reasons(panel) -> list[str]:
    """What the run box says, in the lines of text one can see (not the fields' names)."""
    from PySide6.QtWidgets import QLabel

    return [label.text() for label in panel.run_box.findChildren(QLabel)
            if label.isVisible() and label.text().strip() and label.wordWrap()]


def test_the_study_panel_follows_another_project_and_a_greyed_run_says_why(qtbot, window,
                                                                          tmp_path):
    from PySide6.QtCore import Qt

    from tests.gui.helpers import answer_file_dialog

    w = window
    panel, base = _tiny_base(qtbot, w, tmp_path)
    box = panel.run_box
    # no output folder yet: Run is greyed, and says so
    _add(qtbot, panel, "marking-sigma-px", "2")
    _checked(qtbot, w, panel)
    assert not box.run_button.isEnabled()
    assert any("output folder" in t for t in _run_reasons(panel)), _run_reasons(panel)

    # saved beside the project; its output folder holds the finished study already
    study = tmp_path / "marks.xml"
    _finished_study(tmp_path / "marks-study", "marks", ["v000-r00", "v001-r00"])
    answer_file_dialog(study)
    qtbot.mouseClick(panel.save_button, Qt.MouseButton.LeftButton)
    _checked(qtbot, w, panel)
    assert panel.file_label.text() == f"saved: {study}"
    assert box.folder.text() == str(tmp_path / "marks-study")
    assert not box.run_button.isEnabled()
    reasons = " ".join(_run_reasons(panel))
    assert "finished study 'marks'" in reasons and "another folder" in reasons, reasons

    # another project opened: the study is on it now, its file and folder are not
    other = tmp_path / "elsewhere" / "other.xml"
    other.parent.mkdir()
    other.write_bytes(base.read_bytes())
    assert w.open_project(other)
    wait_idle(qtbot, w)
    w.docks["Study"].raise_()
    _checked(qtbot, w, panel)
    assert panel.file_label.text().startswith("not saved (the study is on the project "
                                              "just opened"), panel.file_label.text()
    assert str(other) in panel.base_label.text(), panel.base_label.text()
    assert panel.study_path is None and box.folder.text() == ""
    assert not box.run_button.isEnabled()
    assert any("output folder" in t for t in _run_reasons(panel)), _run_reasons(panel)
    # a study saved now is on the project opened
    again = tmp_path / "elsewhere" / "marks.xml"
    answer_file_dialog(again)
    qtbot.mouseClick(panel.save_button, Qt.MouseButton.LeftButton)
    assert 'file="other.xml"' in again.read_text()
    _checked(qtbot, w, panel)
    assert box.folder.text() == str(tmp_path / "elsewhere" / "marks-study")
    assert box.run_button.isEnabled() and not _run_reasons(panel), _run_reasons(panel)


def _chart_areas(results, charts_per_report_figure: int) -> list[tuple[float, float]]:
    """The drawn area (px) of each chart shown: the axes of a chart drawn in the panel,
    or the share of the picture of a report figure (a factor's figure holds its charts
    side by side)."""
    canvas = getattr(results, "canvas", None)
    if canvas is not None and canvas.isVisible():
        canvas.figure.canvas.draw()
        return [tuple(ax.get_window_extent().size) for ax in canvas.figure.axes]
    picture = results.figure.pixmap()
    across = charts_per_report_figure if results.figure_choice.currentText().startswith(
        "every metric against") else 1
    return [(picture.width() / across, picture.height())] * across


def test_each_study_chart_reads_at_the_window_size(qtbot, window, tmp_path):
    from PySide6.QtCore import Qt

    from tests.gui.helpers import answer_file_dialog
    from tests.gui.study_helpers import finished_study

    w = window
    panel, _ = _tiny_base(qtbot, w, tmp_path)
    out = tmp_path / "tiny-study"
    metrics = ("check_rmse_z_m", "check_rmse_xy_m", "cloud_nmad_m", "registered")
    finished_study(tmp_path / "tiny-template.xml", out, metrics)
    answer_file_dialog(out)
    qtbot.mouseClick(panel.open_folder_button, Qt.MouseButton.LeftButton)
    results = panel.results
    qtbot.waitUntil(lambda: results.figure_choice.count() > 0, timeout=10000)
    choice = results.figure_choice
    names = [choice.itemText(k) for k in range(choice.count())]
    assert "accuracy against cost (the report's figure)" in names, names
    choice.setFocus()
    qtbot.keyClick(choice, Qt.Key.Key_Home)
    seen = []
    for k in range(choice.count()):
        if k:
            qtbot.keyClick(choice, Qt.Key.Key_Down)
        qtbot.wait(50)
        assert choice.currentIndex() == k
        # the chart fits the panel's width: nothing of it is cut off at the side
        shown = results.stack.currentWidget() if hasattr(results, "stack") else results.figure
        assert shown.width() <= panel.width(), (shown.width(), panel.width())
        for width, height in _chart_areas(results, len(metrics) + 1):
            seen.append((choice.currentText(), round(width), round(height)))
    small = [s for s in seen if s[1] < 300 or s[2] < 200]
    assert not small, small
    # every metric of every factor, and the cost, has a chart of its own
    assert len(seen) >= 2 * (len(metrics) + 1)


def test_the_base_a_factor_varies_around_is_said_to_be_the_projects(qtbot, window,
                                                                    tmp_path):
    w = window
    panel, _ = _tiny_base(qtbot, w, tmp_path)
    row = _add(qtbot, panel, "jpeg-quality", "80 90")
    text = _checked(qtbot, w, panel)
    assert not panel.errors.isVisible(), panel.errors.text()
    assert "3 variants × 1 replicate = 3 runs" in re.sub("<[^>]+>", "", text), text
    # where the third run comes from: the base project as it is, which sets no JPEG quality
    assert "one at a time: the base project as it is (JPEG quality not set in it) and " \
           "2 variants" in text, text
    label = row.findChild(type(panel.plan_label)).text()
    assert "in the base project: not set" in label, label
    # a factor the project sets: its value, from the project
    row = _add(qtbot, panel, "marking-sigma-px", "2")
    text = _checked(qtbot, w, panel)
    assert "(JPEG quality not set in it, GCP marking error σ (px) 0.5)" in text, text
    assert "in the base project: 0.5" in row.findChild(type(panel.plan_label)).text()
    panel.design.setCurrentIndex(panel.design.findData("full-factorial"))
    text = _checked(qtbot, w, panel)
    assert "full factorial: every combination of the levels" in text, text
