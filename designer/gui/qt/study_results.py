"""The results part of the Study panel: a study output folder's runs as a table (each
factor's level, the study's metrics, seconds and status) and its charts with a selector
to browse them, one at a time at a size that reads in the panel: each metric against each
factor's levels, drawn here as the report draws them
(:func:`designer.study.report.draw_level_chart`), then the report's other figures
(``DIR/figures``: accuracy against cost, error maps), which are never shrunk below
:data:`MIN_IMAGE_SCALE` of their size (the area scrolls instead)."""

from __future__ import annotations

import textwrap
from pathlib import Path

from PySide6.QtCore import Qt, QUrl, Signal
from PySide6.QtGui import QColor, QDesktopServices, QPixmap
from PySide6.QtWidgets import (
    QAbstractItemView,
    QComboBox,
    QDialog,
    QHBoxLayout,
    QLabel,
    QPushButton,
    QScrollArea,
    QStackedWidget,
    QTableWidget,
    QTableWidgetItem,
    QVBoxLayout,
    QWidget,
)

from designer.gui.state.study_data import (
    LevelChart,
    StudyFolder,
    cell_text,
    column_words,
    figure_words,
    level_charts,
)

FAILED_COLOUR = "#c0392b"
FAILED_BACKGROUND = "#fdecea"
#: the height of the chart area (px): a chart and its labels at the panel's width
CHART_HEIGHT_PX = 360
#: the report's figures are shown at least this share of their size (scrolled when wider)
MIN_IMAGE_SCALE = 0.6


class _Figure(QLabel):
    double_clicked = Signal()

    def mouseDoubleClickEvent(self, event) -> None:
        self.double_clicked.emit()


class StudyResults(QWidget):
    """Shows one :class:`~designer.gui.state.study_data.StudyFolder`."""

    def __init__(self, parent: QWidget | None = None) -> None:
        super().__init__(parent)
        layout = QVBoxLayout(self)
        layout.setContentsMargins(0, 0, 0, 0)
        self.summary = QLabel("no study folder open")
        self.summary.setWordWrap(True)
        layout.addWidget(self.summary)
        self.table = QTableWidget(0, 0)
        self.table.setEditTriggers(QAbstractItemView.EditTrigger.NoEditTriggers)
        self.table.setSelectionBehavior(QAbstractItemView.SelectionBehavior.SelectRows)
        self.table.setMinimumHeight(160)
        self.table.verticalHeader().hide()
        layout.addWidget(self.table)
        row = QHBoxLayout()
        self.figure_choice = QComboBox()
        self.figure_choice.setObjectName("study-chart-choice")
        self.figure_choice.setToolTip("the study's charts: each metric against each factor, "
                                      "then the report's figures")
        self.figure_choice.currentIndexChanged.connect(self._show_figure)
        self.report_button = QPushButton("Open report")
        self.report_button.setToolTip("report.html in the web browser")
        self.report_button.clicked.connect(self._open_report)
        self.report_button.setEnabled(False)
        row.addWidget(QLabel("plot"))
        row.addWidget(self.figure_choice, 1)
        row.addWidget(self.report_button)
        layout.addLayout(row)
        self.figure = _Figure()
        self.figure.setObjectName("study-figure")
        self.figure.setAlignment(Qt.AlignmentFlag.AlignCenter)
        self.figure.setToolTip("double-click: the plot at full size")
        self.figure.double_clicked.connect(self.open_figure)
        self.image_area = QScrollArea()
        self.image_area.setWidget(self.figure)
        self.image_area.setWidgetResizable(True)
        self.stack = QStackedWidget()
        self.stack.setFixedHeight(CHART_HEIGHT_PX)
        self.stack.addWidget(self.image_area)
        layout.addWidget(self.stack)
        self.canvas = None  # the chart's matplotlib canvas, made when first needed
        self.charts: list[LevelChart] = []
        self.folder: StudyFolder | None = None
        self._pixmap = QPixmap()

    def show_folder(self, folder: StudyFolder) -> None:
        self.folder = folder
        self.summary.setText(folder.describe())
        self.summary.setStyleSheet(f"color: {FAILED_COLOUR}" if folder.failed_rows else "")
        columns = folder.columns
        self.table.clear()
        self.table.setColumnCount(len(columns))
        for c, key in enumerate(columns):  # in words; results.csv's column in the tooltip
            # on two or three short lines: the words keep the columns about as narrow
            # as their numbers
            header = QTableWidgetItem("\n".join(textwrap.wrap(column_words(key), 16)))
            header.setToolTip(f"{column_words(key)}\n(in results.csv: {key})")
            self.table.setHorizontalHeaderItem(c, header)
        self.table.setRowCount(len(folder.rows))
        for r, row in enumerate(folder.rows):
            failed = str(row.get("status", "")) != "ok"
            for c, key in enumerate(columns):
                item = QTableWidgetItem(cell_text(row.get(key)))
                if failed:  # the whole row stands out; the reason on every cell
                    item.setBackground(QColor(FAILED_BACKGROUND))
                    item.setToolTip(f"{row.get('run', '')} failed: "
                                    f"{folder.failure_reason(row)}")
                    if key == "status":
                        item.setForeground(Qt.GlobalColor.red)
                self.table.setItem(r, c, item)
        self.table.resizeColumnsToContents()
        self.charts = level_charts(folder) if folder.summary is not None else []
        blocked = self.figure_choice.blockSignals(True)
        self.figure_choice.clear()
        for k, chart in enumerate(self.charts):
            self.figure_choice.addItem(chart.name, k)
            self.figure_choice.setItemData(
                k, f"{chart.name}\n(in the study's files: {chart.identifiers})",
                Qt.ItemDataRole.ToolTipRole)
        drawn = {f"factor-{c.factor}" for c in self.charts}
        for path in folder.figures:  # the report's own figures of what is drawn: not again
            if path.stem not in drawn:
                self.figure_choice.addItem(figure_words(path.stem), str(path))
                self.figure_choice.setItemData(self.figure_choice.count() - 1,
                                               str(path), Qt.ItemDataRole.ToolTipRole)
        self.figure_choice.blockSignals(blocked)
        self.report_button.setEnabled((folder.path / "report.html").is_file())
        self._show_figure()

    def clear(self) -> None:
        """Show no study folder."""
        self.folder = None
        self.summary.setText("no study folder open")
        self.summary.setStyleSheet("")
        self.table.clear()
        self.table.setRowCount(0)
        self.table.setColumnCount(0)
        self.charts = []
        blocked = self.figure_choice.blockSignals(True)
        self.figure_choice.clear()
        self.figure_choice.blockSignals(blocked)
        self.report_button.setEnabled(False)
        self._show_figure()

    def select_figure(self, name: str) -> None:
        index = self.figure_choice.findText(name)
        if index >= 0:
            self.figure_choice.setCurrentIndex(index)

    @property
    def figure_path(self) -> Path | None:
        """The report figure shown (None: a chart drawn here, or nothing)."""
        data = self.figure_choice.currentData()
        return Path(data) if isinstance(data, str) and data else None

    @property
    def chart(self) -> LevelChart | None:
        """The chart shown (None: a report figure, or nothing)."""
        data = self.figure_choice.currentData()
        return self.charts[data] if isinstance(data, int) else None

    def _show_figure(self, *_) -> None:
        # the whole name where the selector cuts a long one
        self.figure_choice.setToolTip(self.figure_choice.currentData(
            Qt.ItemDataRole.ToolTipRole) or "the study's charts: each metric against each "
            "factor, then the report's figures")
        chart = self.chart
        if chart is not None:
            self._draw(chart)
            return
        self.stack.setCurrentWidget(self.image_area)
        path = self.figure_path
        self._pixmap = QPixmap(str(path)) if path is not None else QPixmap()
        if self._pixmap.isNull():
            self.figure.setPixmap(QPixmap())
            self.figure.setText("no plot yet" if path is None else f"cannot read {path}")
            return
        self.figure.setToolTip(f"{path}\ndouble-click: the plot at full size")
        self._fit()

    def _draw(self, chart: LevelChart) -> None:
        if self.canvas is None:
            from matplotlib.backends.backend_qtagg import FigureCanvasQTAgg
            from matplotlib.figure import Figure

            self.canvas = FigureCanvasQTAgg(Figure())
            self.canvas.setObjectName("study-chart")
            self.canvas.setToolTip("double-click: the chart in a window of its own")
            self.canvas.mouseDoubleClickEvent = lambda _e: self.open_figure()
            self.stack.addWidget(self.canvas)
        self.stack.setCurrentWidget(self.canvas)
        _plot(self.canvas.figure, chart)
        self.canvas.draw_idle()

    def _fit(self) -> None:
        if self._pixmap.isNull():
            return
        width = max(200, self.image_area.viewport().width() - 4)
        width = max(width, round(MIN_IMAGE_SCALE * self._pixmap.width()))
        self.figure.setPixmap(self._pixmap.scaledToWidth(
            min(width, self._pixmap.width()), Qt.TransformationMode.SmoothTransformation))

    def resizeEvent(self, event) -> None:
        super().resizeEvent(event)
        self._fit()

    def open_figure(self) -> QDialog | None:
        """The current plot at full size in a window of its own."""
        chart = self.chart
        if chart is not None:
            return self._open_chart(chart)
        if self._pixmap.isNull():
            return None
        dialog = QDialog(self)
        dialog.setWindowTitle(str(self.figure_path))
        label = QLabel()
        label.setPixmap(self._pixmap)
        scroll = QScrollArea()
        scroll.setWidget(label)
        QVBoxLayout(dialog).addWidget(scroll)
        dialog.resize(min(1400, self._pixmap.width() + 40), min(900, self._pixmap.height() + 40))
        dialog.show()
        self.viewer = dialog
        return dialog

    def _open_chart(self, chart: LevelChart) -> QDialog:
        from matplotlib.backends.backend_qtagg import FigureCanvasQTAgg
        from matplotlib.figure import Figure

        dialog = QDialog(self)
        dialog.setWindowTitle(chart.name)
        canvas = FigureCanvasQTAgg(Figure())
        _plot(canvas.figure, chart)
        QVBoxLayout(dialog).addWidget(canvas)
        dialog.resize(900, 600)
        dialog.show()
        self.viewer = dialog
        return dialog

    def _open_report(self) -> None:
        if self.folder is not None:
            QDesktopServices.openUrl(QUrl.fromLocalFile(str(self.folder.path / "report.html")))


def _plot(figure, chart: LevelChart) -> None:
    """``chart`` alone on ``figure``, its labels inside the figure."""
    from designer.study.report import draw_level_chart

    figure.clear()
    ax = figure.add_subplot()
    draw_level_chart(ax, chart.factor, chart.levels, chart.stats, chart.points,
                     chart.title, chart.is_cost)
    ax.set_xlabel(column_words(f"factor:{chart.factor}"))  # in words, as the selector
    ax.set_title(ax.get_title(), fontsize=10)
    figure.set_layout_engine("constrained")
