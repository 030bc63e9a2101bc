"""The Study panel names factors, re-drawn draws, metrics and costs in a surveyor's words,
with the study file's identifier in the tooltip (issue 53, finding 10: it listed
"altitude-m (render)", "gcp-selection", "check_rmse_xy_m")."""

from __future__ import annotations

import re

import pytest
from PySide6.QtCore import Qt
from PySide6.QtWidgets import QScrollArea

from designer.study.cost import COSTS
from designer.study.factors import DRAWS, FACTORS
from designer.study.results import METRIC_COLUMNS
from tests.gui.helpers import open_panel, wait_idle
from tests.gui.study_helpers import _add

#: an identifier: lower-case words joined by '-' or '_' (k1, JPEG are words)
IDENTIFIER = re.compile(r"\b[a-z0-9]+(?:[-_][a-z0-9]+)+\b")


def _worded(text: str, identifier: str) -> None:
    assert text and text != identifier, (text, identifier)
    assert identifier not in text or not IDENTIFIER.fullmatch(identifier), (text, identifier)
    assert "_" not in text, text


@pytest.mark.gui
def test_the_study_panel_words_every_identifier_and_tips_it(qtbot, window):
    w = window
    panel = open_panel(w, "Study")
    wait_idle(qtbot, w)
    choice = panel.factor_choice
    assert choice.count() == len(FACTORS)
    for k in range(choice.count()):
        name = choice.itemData(k)
        _worded(choice.itemText(k), name)
        assert name in choice.itemData(k, Qt.ItemDataRole.ToolTipRole)
    for name, box in panel.vary.items():
        assert name in DRAWS
        _worded(box.text(), name)
        assert name in box.toolTip()
    assert panel.metrics.count() == len(METRIC_COLUMNS)
    for k in range(panel.metrics.count()):
        item = panel.metrics.item(k)
        name = item.data(Qt.ItemDataRole.UserRole)
        assert name == METRIC_COLUMNS[k]
        _worded(item.text(), name)
        assert name in item.toolTip()
    assert panel.cost_axis.count() == len(COSTS)
    for k in range(panel.cost_axis.count()):
        name = panel.cost_axis.itemData(k)
        _worded(panel.cost_axis.itemText(k), name)
        assert name in panel.cost_axis.itemData(k, Qt.ItemDataRole.ToolTipRole)

    # the words fit: the panel's fields are no wider than its dock shows (it does not
    # scroll sideways, so wider fields would be cut at the right)
    scroll = panel.findChild(QScrollArea)
    assert scroll.widget().minimumSizeHint().width() <= scroll.viewport().width()

    row = _add(qtbot, panel, "altitude-m", "40 60")
    _worded(row.label.text(), "altitude-m")
    assert "flight height" in row.label.text()
    assert "altitude-m" in row.label.toolTip()
    # what is saved is still the study file's identifiers
    panel.metrics.item(METRIC_COLUMNS.index("check_rmse_xy_m")).setCheckState(
        Qt.CheckState.Checked)
    assert "check_rmse_xy_m" in panel.study().metrics
    assert panel.study().factors[0].name == "altitude-m"


def _named(text: str) -> list[str]:
    """The study file's and results.csv's identifiers in ``text`` (and any '_')."""
    names = [n for n in (*FACTORS, *DRAWS, *METRIC_COLUMNS) if re.search(r"[-_]", n)]
    return [n for n in names if re.search(rf"(?<![\w-]){re.escape(n)}(?![\w-])", text)] + (
        ["_"] if "_" in text else [])


@pytest.mark.gui
def test_the_study_results_table_and_chart_selector_speak_words(qtbot, window, tmp_path):
    """A finished study's table heads its columns and the selector names its charts in
    words (they listed results.csv's ``check_rmse_z_m``, ``flight_min``, ``total_s``
    and ``marking-sigma-px: …``, ``pareto``); results.csv's name stays in the tooltip."""
    from tests.gui.helpers import answer_file_dialog
    from tests.gui.study_helpers import _tiny_base, finished_study

    w = window
    panel, _ = _tiny_base(qtbot, w, tmp_path)
    out = tmp_path / "tiny-study"
    finished_study(tmp_path / "tiny-template.xml", out)
    answer_file_dialog(out)
    qtbot.mouseClick(panel.open_folder_button, Qt.MouseButton.LeftButton)
    results = panel.results
    qtbot.waitUntil(lambda: results.figure_choice.count() > 0, timeout=10000)
    table = results.table
    assert table.rowCount() > 0 and table.columnCount() > 4
    headers = [table.horizontalHeaderItem(c) for c in range(table.columnCount())]
    for header in headers:
        assert not _named(header.text()), header.text()
        assert "results.csv" in header.toolTip(), header.toolTip()
    texts = [h.text().replace("\n", " ") for h in headers]
    assert "check-point RMSE Z (m)" in texts and "time per run (s)" in texts, texts
    tips = " ".join(h.toolTip() for h in headers)
    assert "check_rmse_z_m" in tips and "total_s" in tips, tips
    choice = results.figure_choice
    names = [choice.itemText(k) for k in range(choice.count())]
    for name in names:
        assert not _named(name) and "_" not in name, names
    assert any(n.startswith("check-point RMSE Z (m) against ") for n in names), names
    assert "accuracy against cost (the report's figure)" in names, names
    chart_tips = [choice.itemData(k, Qt.ItemDataRole.ToolTipRole) for k in range(choice.count())]
    assert any("check_rmse_z_m" in (t or "") for t in chart_tips), chart_tips
    # the chart drawn names its factor in words under its axis; the selector's tooltip
    # says its whole name where the selector is too narrow for it
    choice.setCurrentIndex(0)
    wait_idle(qtbot, w)
    assert choice.toolTip().startswith(names[0]), choice.toolTip()
    (ax,) = results.canvas.figure.axes
    assert not _named(ax.get_xlabel()), ax.get_xlabel()
