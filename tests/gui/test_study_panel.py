"""Study panel: a study built with clicks and typing on the open project (live counts,
errors located in the study file, Run refused), saved and opened again; a tiny study run
from the panel, cancelled, resumed to the end, its results table and plots shown."""

from __future__ import annotations

import json
import os
import re
import time

import pytest
from PySide6.QtCore import Qt
from PySide6.QtGui import QPixmap
from PySide6.QtWidgets import QLabel

from designer.gui.qt.panels.study import NO_FACTOR
from designer.study.xml import read_study
from tests.gui.helpers import answer_file_dialog, set_field, wait_idle
from tests.gui.study_helpers import _add, _checked, _tiny_base

pytestmark = pytest.mark.gui








def _runs_line(text: str) -> tuple[int, int, int]:
    m = re.search(r"(\d+) variants × (\d+) replicates? = (\d+) runs", text)
    assert m, text
    return tuple(int(g) for g in m.groups())


def test_a_study_is_built_checked_saved_and_opened_again(qtbot, window, tmp_path):
    w = window
    panel, _ = _tiny_base(qtbot, w, tmp_path)
    text = _checked(qtbot, w, panel)
    assert panel.errors.text() == NO_FACTOR  # said in the panel's words
    assert not panel.run_box.run_button.isEnabled()

    # a processing-only factor: base 0.5 px plus two levels, all on one render
    _add(qtbot, panel, "marking-sigma-px", "0.2 2")
    text = _checked(qtbot, w, panel)
    assert _runs_line(text) == (3, 1, 3)
    assert "1 render (" in text and "3 reconstructions" in text
    assert "estimated time" in text and not panel.errors.isVisible()

    # a render factor given as a range: two more variants, each its own render
    _add(qtbot, panel, "sun-elevation-deg", "30:40:10")
    text = _checked(qtbot, w, panel)
    assert _runs_line(text) == (5, 1, 5)
    assert "3 renders" in text
    assert panel.rows[-1].count.text() == "2 levels"

    set_field(qtbot, panel.replicates, "2")
    qtbot.mouseClick(panel.vary["marking-error"], Qt.MouseButton.LeftButton)
    assert _runs_line(_checked(qtbot, w, panel)) == (5, 2, 10)
    panel.design.setCurrentIndex(panel.design.findData("full-factorial"))
    assert _runs_line(_checked(qtbot, w, panel)) == (4, 2, 8)  # 2 × 2 combinations
    panel.design.setCurrentIndex(panel.design.findData("one-at-a-time"))

    # a value the factor does not accept: a located error, Run refused
    bad = _add(qtbot, panel, "calibration", "fixed sometimes")
    _checked(qtbot, w, panel)
    error = panel.errors.text()
    assert re.match(r".*untitled-study\.xml:\d+:\d+: “camera parameters the adjustment "
                    r"estimates”: value 'sometimes' is not usable: use one of: fixed", error), \
        error
    assert panel.errors.isVisible() and not panel.run_box.run_button.isEnabled()
    # a range that goes backwards is refused before the study is written
    qtbot.mouseClick(bad.remove_button, Qt.MouseButton.LeftButton)
    sun = panel.rows[-1]
    sun.levels.selectAll()
    qtbot.keyClicks(sun.levels, "40:30:10")
    _checked(qtbot, w, panel)
    assert "factor “sun elevation (°)”: stop 30 is below start 40" in panel.errors.text()
    sun.levels.selectAll()
    qtbot.keyClicks(sun.levels, "30:40:10")
    assert _runs_line(_checked(qtbot, w, panel)) == (5, 2, 10)
    assert not panel.errors.isVisible()

    # the cost the report plots accuracy against: flight minutes unless chosen
    assert panel.cost_axis.currentData() == "flight-minutes"
    assert "<cost>" not in panel.study_text()
    panel.cost_axis.setCurrentIndex(panel.cost_axis.findData("control-gcps"))
    assert "<cost>control-gcps</cost>" in panel.study_text()
    assert _runs_line(_checked(qtbot, w, panel)) == (5, 2, 10)

    # saved through the dialog: a study file the reader reads back as the panel shows it
    path = tmp_path / "studies" / "sun.xml"
    path.parent.mkdir()
    panel.name.selectAll()
    qtbot.keyClicks(panel.name, "sun-and-marks")
    answer_file_dialog(path)
    qtbot.mouseClick(panel.save_button, Qt.MouseButton.LeftButton)
    assert path.is_file()
    study = read_study(path)
    assert study.name == "sun-and-marks"
    assert study.base.file == "../tiny-template-base.xml"
    assert [(f.name, f.values) for f in study.factors] == [
        ("marking-sigma-px", ("0.2", "2")), ("sun-elevation-deg", ("30", "40"))]
    # the range is written as the range it was typed as
    assert '<range start="30" stop="40" step="10"/>' in path.read_text()
    assert (study.design, study.replicates.count, study.replicates.vary) == (
        "one-at-a-time", 2, ("marking-error",))
    assert set(study.metrics) == {"check_rmse_xy_m", "check_rmse_z_m", "cloud_nmad_m",
                                  "registered"}
    assert study.cost == "control-gcps"
    assert panel.run_box.folder.text() == str(path.parent / "sun-study")

    # another study replaces it in the panel; opening the saved file brings it back
    for row in list(panel.rows):
        qtbot.mouseClick(row.remove_button, Qt.MouseButton.LeftButton)
    set_field(qtbot, panel.replicates, "1")
    panel.cost_axis.setCurrentIndex(panel.cost_axis.findData("images"))
    assert not panel.rows
    answer_file_dialog(path)
    qtbot.mouseClick(panel.open_button, Qt.MouseButton.LeftButton)
    assert [(r.name, r.levels.text()) for r in panel.rows] == [
        ("marking-sigma-px", "0.2 2"), ("sun-elevation-deg", "30:40:10")]
    assert panel.name.text() == "sun-and-marks" and panel.replicates.value() == 2
    assert panel.vary["marking-error"].isChecked() and not panel.vary["pose-noise"].isChecked()
    assert panel.cost_axis.currentData() == "control-gcps"
    assert _runs_line(_checked(qtbot, w, panel)) == (5, 2, 10)
    assert panel.run_box.run_button.isEnabled()


def test_an_opened_study_with_an_error_points_into_its_file(qtbot, window, tmp_path):
    w = window
    panel, _ = _tiny_base(qtbot, w, tmp_path)
    path = tmp_path / "bad.xml"
    path.write_text(
        '<?xml version="1.0"?>\n'
        '<study xmlns="urn:designer:project:1" schema-version="1.0" name="bad">\n'
        '  <base-project file="tiny-template-base.xml"/>\n\n\n'
        '  <factor name="altitude-m"><values>20 -5</values></factor>\n'
        "</study>\n")
    assert panel.open_study(path)
    _checked(qtbot, w, panel)
    assert panel.errors.text().startswith(f"{path}:6:")
    assert "“flight height above ground (m)”: the level '-5' makes a project that is not " \
           "valid: Flight › " in panel.errors.text(), panel.errors.text()
    assert not panel.run_box.run_button.isEnabled()
    # a file the reader refuses is listed, not half-loaded
    path.write_text(path.read_text().replace("factor>", "factr>").replace("<factor ", "<factr "))
    assert not panel.open_study(path)
    assert f"{path}:6:3: unknown element “factr”" in panel.errors.text()


def test_a_study_whose_base_is_missing_asks_for_it(qtbot, window, tmp_path):
    w = window
    panel, base = _tiny_base(qtbot, w, tmp_path)
    w.file_actions.new(None)  # the window's project is another one now
    wait_idle(qtbot, w)
    w.docks["Study"].raise_()
    path = tmp_path / "elsewhere" / "study.xml"
    path.parent.mkdir()
    path.write_text((tmp_path / "tiny-template.xml").read_text())  # base: not beside it
    answer_file_dialog(base)
    assert panel.open_study(path)
    assert panel.base_file == base.resolve()
    assert str(base.resolve()) in panel.base_label.text()
    assert _runs_line(_checked(qtbot, w, panel)) == (4, 1, 4)
    assert panel.use_window.isVisible()
    # the window's blank project as the base instead: it has no flight to vary
    qtbot.mouseClick(panel.use_window, Qt.MouseButton.LeftButton)
    _checked(qtbot, w, panel)
    assert panel.base_file is None and panel.errors.isVisible()
    assert not panel.run_box.run_button.isEnabled()


def _group_alive(pid: int) -> bool:
    try:
        os.killpg(pid, 0)
    except ProcessLookupError:
        return False
    return True


@pytest.mark.blender
def test_a_tiny_study_runs_cancels_resumes_and_shows_its_results(qtbot, window, tmp_path):
    w = window
    panel, _ = _tiny_base(qtbot, w, tmp_path)
    _add(qtbot, panel, "marking-sigma-px", "2")  # and the base's 0.5 px: one render
    assert _runs_line(_checked(qtbot, w, panel)) == (2, 1, 2)
    predicted = panel.cost
    assert panel.save_study(tmp_path / "marks.xml")
    assert _runs_line(_checked(qtbot, w, panel)) == (2, 1, 2)
    box = panel.run_box
    out = tmp_path / "marks-study"
    assert box.folder.text() == str(out)
    assert box.run_button.text() == "Run" and box.run_button.isEnabled()

    # run; cancel once the first run is finished
    qtbot.mouseClick(box.run_button, Qt.MouseButton.LeftButton)
    assert box.process.running and box.cancel_button.isEnabled()
    pid = box.process.process.processId()
    qtbot.waitUntil(lambda: box.progress.value() >= 1 or not box.process.running,
                    timeout=300_000)
    assert box.process.running, box.log.toPlainText()
    assert "runs finished" in box.state.text()
    finished = {p.parent.name: p.read_bytes() for p in out.glob("runs/*/result.json")}
    qtbot.mouseClick(box.cancel_button, Qt.MouseButton.LeftButton)
    qtbot.waitUntil(lambda: not box.process.running, timeout=30_000)
    assert box.state.text().startswith("cancelled"), box.state.text()
    assert "Resume continues" in box.state.text()
    deadline = time.monotonic() + 10
    while _group_alive(pid) and time.monotonic() < deadline:  # no worker left behind
        qtbot.wait(100)
    assert not _group_alive(pid)
    assert finished and not (out / "results.csv").exists()
    assert box.run_button.text() == "Resume" and box.run_button.isEnabled()
    # the unfinished folder opened: the finished runs, and that it is not finished
    assert panel.open_folder(out)
    assert panel.results.table.rowCount() == len(finished)
    assert "not finished (Resume continues)" in panel.results.summary.text()

    # resume to the end: the runs finished before are kept as they were
    qtbot.mouseClick(box.run_button, Qt.MouseButton.LeftButton)
    qtbot.waitUntil(lambda: not box.process.running, timeout=300_000)
    assert box.state.text().startswith("done"), box.state.text() + box.log.toPlainText()
    assert "--resume" in box.process.process.arguments()
    for run, content in finished.items():
        assert (out / "runs" / run / "result.json").read_bytes() == content
    summary = json.loads((out / "summary.json").read_text())
    assert (summary["runs"], summary["renders"], summary["reconstructions"]) == (
        predicted.runs, predicted.renders, predicted.reconstructions)
    assert not box.run_button.isEnabled()  # the folder holds a finished study

    # the results: a row per run with the factor's level, metrics and status; the plots
    results = panel.results
    table = results.table
    headers = [table.horizontalHeaderItem(c).text().replace("\n", " ")
               for c in range(table.columnCount())]
    assert table.rowCount() == 2
    assert {"run", "GCP marking error σ (px)", "check-point RMSE Z (m)", "flight time (min)",
            "status"} <= set(headers)
    levels = {table.item(r, headers.index("GCP marking error σ (px)")).text()
              for r in range(2)}
    assert levels == {"0.5", "2"}
    assert {table.item(r, headers.index("status")).text() for r in range(2)} == {"ok"}
    assert float(table.item(0, headers.index("check-point RMSE Z (m)")).text()) > 0
    names = [results.figure_choice.itemText(k) for k in range(results.figure_choice.count())]
    # a chart per metric of the factor (drawn in the panel), then the report's figures
    pareto = "accuracy against cost (the report's figure)"
    assert "check-point RMSE Z (m) against GCP marking error σ (px)" in names, names
    assert pareto in names, names
    # the report's row of them: not again
    assert "every metric against GCP marking error σ (px)" not in names
    results.select_figure(pareto)
    assert results.figure_path.name == "pareto.png"
    assert not results.figure.pixmap().isNull() and results.figure.pixmap().width() > 100
    qtbot.mouseDClick(results.figure, Qt.MouseButton.LeftButton)
    full = results.viewer
    assert full.isVisible() and full.findChild(QLabel).pixmap().size() == QPixmap(
        str(out / "figures" / "pareto.png")).size()
    full.close()

    # the folder opened afresh shows the same
    panel.results.table.setRowCount(0)
    assert panel.open_folder(out)
    assert panel.results.table.rowCount() == 2
    assert "2 of 2 runs finished" in panel.results.summary.text()


def test_run_on_an_unsaved_study_saves_it_and_runs_on_the_first_click(qtbot, window,
                                                                       tmp_path):
    w = window
    panel, _ = _tiny_base(qtbot, w, tmp_path)
    _add(qtbot, panel, "marking-sigma-px", "2")
    assert _runs_line(_checked(qtbot, w, panel)) == (2, 1, 2)
    box = panel.run_box
    out = tmp_path / "first-click"
    box.folder.setFocus()
    qtbot.keyClicks(box.folder, str(out))
    assert panel.study_path is None and box.run_button.isEnabled()

    # Run asks where to save the study, saves it and starts the run: one click
    path = tmp_path / "first.xml"
    answer_file_dialog(path)
    qtbot.mouseClick(box.run_button, Qt.MouseButton.LeftButton)
    assert path.is_file() and panel.study_path == path
    assert box.process.running, box.state.text()
    assert box.state.text().startswith(f"starting the study into {out}")
    assert box.progress.maximum() == 2
    assert box.folder.text() == str(out)  # the folder chosen is kept
    assert not box.run_button.isEnabled() and box.cancel_button.isEnabled()
    qtbot.mouseClick(box.cancel_button, Qt.MouseButton.LeftButton)
    qtbot.waitUntil(lambda: not box.process.running, timeout=30_000)


def _base_without_gcps(qtbot, w, folder):
    """The tiny base without GCP targets (its processing still georeferences on GCPs)."""
    from dataclasses import replace

    from designer.project import write_project
    from designer.study.templates import template_base

    p = template_base("tiny")
    p = replace(p, scene=replace(p.scene, targets=None), processing=replace(
        p.processing, gcps=replace(p.processing.gcps, control=None)))
    base = folder / "no-gcps.xml"
    write_project(p, base)
    assert w.open_project(base)
    wait_idle(qtbot, w)
    w.docks["Study"].raise_()
    return w.panels["Study"]


def test_a_study_whose_runs_would_fail_is_warned_before_run(qtbot, window, tmp_path):
    w = window
    panel = _base_without_gcps(qtbot, w, tmp_path)
    _add(qtbot, panel, "marking-sigma-px", "2")
    assert _runs_line(_checked(qtbot, w, panel)) == (2, 1, 2)
    warning = panel.warnings.text()
    assert panel.warnings.isVisible() and not panel.errors.isVisible()
    assert "every run (2 of 2) would fail" in warning, warning
    assert "GCP mode similarity needs at least 3 control GCPs" in warning, warning
    assert "0 GCP targets" in warning
    qtbot.keyClicks(panel.run_box.folder, str(tmp_path / "out"))
    assert panel.run_box.run_button.isEnabled()  # a warning: the study may still run

    # a study that varies the GCP mode: only the runs that need GCPs are named
    _add(qtbot, panel, "gcp-mode", "none")
    _checked(qtbot, w, panel)
    warning = panel.warnings.text()
    assert "2 of 3 runs" in warning and "would fail" in warning, warning
    # none of them needs GCPs any more: the warning goes away
    for row in list(panel.rows):
        qtbot.mouseClick(row.remove_button, Qt.MouseButton.LeftButton)
    _add(qtbot, panel, "marking-sigma-px", "2")
    _checked(qtbot, w, panel)
    assert panel.warnings.isVisible()
    from designer.gui.state import edits

    w.editor.edit(edits.replace_path(w.document.project, "processing.gcps.mode", "none"),
                  "GCP mode none")
    _checked(qtbot, w, panel)
    assert not panel.warnings.isVisible(), panel.warnings.text()


@pytest.mark.blender
def test_a_study_whose_runs_failed_is_shown_as_failed(qtbot, window, tmp_path):
    w = window
    panel = _base_without_gcps(qtbot, w, tmp_path)
    _add(qtbot, panel, "marking-sigma-px", "2")
    assert _runs_line(_checked(qtbot, w, panel)) == (2, 1, 2)
    assert panel.save_study(tmp_path / "no-gcps-study.xml")
    _checked(qtbot, w, panel)
    box = panel.run_box
    qtbot.mouseClick(box.run_button, Qt.MouseButton.LeftButton)
    qtbot.waitUntil(lambda: not box.process.running, timeout=300_000)
    state = box.state.text()
    assert not state.startswith("done"), state
    assert re.match(r"finished in .*: 0 of 2 runs succeeded, 2 failed: only 0 control GCPs "
                    r"are seen", state), state + box.log.toPlainText()
    assert "/runs/" not in state  # the reason, not the run's folder
    assert "#c0392b" in box.state.styleSheet()
    assert box.progress.property("failed") is True
    assert "#c0392b" in box.progress.styleSheet()
    # the table: failed rows stand out, the reason in every cell's tooltip
    results = panel.results
    assert "2 failed" in results.summary.text() and "#c0392b" in results.summary.styleSheet()
    table = results.table
    for r in range(table.rowCount()):
        item = table.item(r, 0)
        assert item.background().color().name() == "#fdecea"
        assert "only 0 control GCPs" in item.toolTip()


def test_a_texture_chosen_for_the_project_resolves_from_a_study_elsewhere(qtbot, window,
                                                                          tmp_path):
    """The project's missing texture chosen again (Texture: Choose…) with the project not
    saved yet: a study in another folder finds the texture where the project does."""
    from dataclasses import replace

    import numpy as np
    from PIL import Image
    from PySide6.QtWidgets import QPushButton

    from designer.project import model as m
    from designer.project import write_project
    from designer.study.templates import template_base

    w = window
    project_dir, study_dir = tmp_path / "survey", tmp_path / "studies"
    (project_dir / "textures").mkdir(parents=True)
    study_dir.mkdir()
    p = template_base("tiny")
    p = replace(p, scene=replace(p.scene, texture=replace(
        p.scene.texture, source=m.ImageTexture("ground.png"))))  # not there
    base = project_dir / "field.xml"
    write_project(p, base)
    texture = project_dir / "textures" / "ground.png"
    Image.fromarray(np.full((64, 64, 3), 120, np.uint8)).save(texture)
    assert w.open_project(base)
    wait_idle(qtbot, w)
    assert any("ground.png" in line for line in
               [w.problems.item(i).text() for i in range(w.problems.count())])

    # Texture: Choose… the image where it is now
    w.docks["Texture"].raise_()
    choose = w.panels["Texture"].image.findChild(QPushButton)
    answer_file_dialog(texture)
    qtbot.mouseClick(choose, Qt.MouseButton.LeftButton)
    wait_idle(qtbot, w)
    assert w.document.project.scene.texture.source.file == "textures/ground.png"
    assert w.document.dirty

    # a study beside the project's folder, on that project
    study = study_dir / "marks.xml"
    study.write_text(
        '<?xml version="1.0"?>\n'
        '<study xmlns="urn:designer:project:1" schema-version="1.0" name="marks">\n'
        '  <base-project file="../survey/field.xml"/>\n'
        '  <factor name="marking-sigma-px"><values>2</values></factor>\n'
        "</study>\n")
    panel = w.panels["Study"]
    w.docks["Study"].raise_()
    assert panel.open_study(study)
    text = _checked(qtbot, w, panel)
    assert not panel.errors.isVisible(), panel.errors.text()
    assert _runs_line(text) == (2, 1, 2)
    # the study's copy of the unsaved project names the texture from the study's folder
    assert 'file="../survey/textures/ground.png"' in panel.study_text(study)


def test_opening_another_project_clears_the_study_results(qtbot, window, tmp_path):
    w = window
    panel, base = _tiny_base(qtbot, w, tmp_path)
    out = tmp_path / "old-study"  # a study folder of this project, one run finished
    (out / "runs" / "v000-r00").mkdir(parents=True)
    (out / "study.json").write_text(json.dumps({"name": "old", "runs": ["v000-r00",
                                                                         "v001-r00"]}))
    (out / "runs" / "v000-r00" / "result.json").write_text(json.dumps(
        {"run": "v000-r00", "status": "ok", "check_rmse_z_m": 0.02}))
    assert panel.open_folder(out)
    assert panel.results.table.rowCount() == 1
    assert "study 'old'" in panel.results.summary.text()

    other = tmp_path / "other.xml"
    other.write_bytes(base.read_bytes())
    assert w.open_project(other)
    wait_idle(qtbot, w)
    assert panel.results.table.rowCount() == 0
    assert panel.results.summary.text() == "no study folder open"
    assert panel.results.folder is None and panel.results.figure_choice.count() == 0
    # the folder held a study of the project before: resuming it on this one would mix
    # the two projects' runs in one study
    assert panel.run_box.folder.text() == ""
