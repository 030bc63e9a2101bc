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
