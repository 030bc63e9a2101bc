"""Results: a reconstructed point cloud coloured by signed distance to the true terrain
(diverging map, colour bar in the view), histogram and statistics, GCP error table.
Reading the cloud and computing distances run off the UI thread."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from PySide6.QtWidgets import (
    QFileDialog,
    QGroupBox,
    QHBoxLayout,
    QLabel,
    QPushButton,
    QTableWidget,
    QTableWidgetItem,
    QVBoxLayout,
)

from designer.gui import results_data
from designer.gui.panels.base import Panel

CMAP = "RdBu_r"


class ResultsPanel(Panel):
    title = "Results"
    parts = frozenset()

    def build(self, layout) -> None:
        row = QHBoxLayout()
        open_cloud = QPushButton("Open point cloud…")
        open_cloud.clicked.connect(self._choose_cloud)
        open_gcps = QPushButton("Open GCP residuals…")
        open_gcps.clicked.connect(self._choose_residuals)
        clear = QPushButton("Clear")
        clear.clicked.connect(self.clear)
        row.addWidget(open_cloud)
        row.addWidget(open_gcps)
        row.addWidget(clear)
        layout.addLayout(row)
        self.state = QLabel("open the cloud of a reconstruction (designer sfm writes "
                            "cloud.ply and gcp_residuals.csv)")
        self.state.setWordWrap(True)
        layout.addWidget(self.state)

        hist = QGroupBox("signed distance to the true terrain (+ above)")
        v = QVBoxLayout(hist)
        from matplotlib.backends.backend_qtagg import FigureCanvasQTAgg
        from matplotlib.figure import Figure

        self.figure = Figure(figsize=(4, 2.4), dpi=90, layout="constrained")
        self.canvas = FigureCanvasQTAgg(self.figure)
        self.canvas.setMinimumHeight(200)
        v.addWidget(self.canvas)
        self.stats = QTableWidget(0, 2)
        self.stats.setHorizontalHeaderLabels(["statistic", "value"])
        self.stats.horizontalHeader().setStretchLastSection(True)
        self.stats.setMinimumHeight(180)
        v.addWidget(self.stats)
        layout.addWidget(hist)

        gcps = QGroupBox("GCP errors (estimated − true)")
        v = QVBoxLayout(gcps)
        self.gcp_table = QTableWidget(0, 6)
        self.gcp_table.setHorizontalHeaderLabels(["id", "role", "dX mm", "dY mm", "dZ mm",
                                                  "3-D mm"])
        self.gcp_table.setMinimumHeight(180)
        v.addWidget(self.gcp_table)
        self.rmse = QLabel("")
        self.rmse.setWordWrap(True)
        v.addWidget(self.rmse)
        layout.addWidget(gcps)
        self.result: results_data.CloudResult | None = None

    # ------------------------------------------------------------------ actions
    def _choose_cloud(self) -> None:
        path, _ = QFileDialog.getOpenFileName(
            self, "Open point cloud", str(self.editor.document.base_dir),
            "point clouds (*.ply *.las *.laz *.xyz *.txt *.csv)")
        if path:
            self.open_cloud(Path(path))

    def _choose_residuals(self) -> None:
        path, _ = QFileDialog.getOpenFileName(self, "Open GCP residuals",
                                              str(self.editor.document.base_dir),
                                              "CSV (*.csv)")
        if path:
            self.open_residuals(Path(path))

    def open_cloud(self, path: Path) -> None:
        """Read the cloud and compare it with the true surface in a worker thread."""
        doc, terrain = self.editor.document, self.sync.terrain
        self.state.setText(f"reading {path.name} and computing distances…")
        self.sync.tasks.submit(
            "cloud", results_data.evaluate_cloud, Path(path), doc.path, doc.dirty,
            terrain.heightfield if terrain else None, terrain.mesh if terrain else None,
            on_done=self.show_result,
            on_error=lambda e: self.state.setText(f"{path.name}: {e}"))
        residuals = Path(path).with_name("gcp_residuals.csv")
        if residuals.is_file():
            self.open_residuals(residuals)

    def open_residuals(self, path: Path) -> None:
        """GCP errors of estimates in a CSV against the project's targets (a thread)."""
        terrain = self.sync.terrain
        self.sync.tasks.submit(
            "gcp-errors", results_data.evaluate_gcps, Path(path), self.project,
            terrain.heightfield if terrain else None, on_done=self.show_gcp_errors,
            on_error=lambda e: self.rmse.setText(f"{Path(path).name}: {e}"))

    def clear(self) -> None:
        self.result = None
        self.sync.view.remove_layer("cloud")
        self.sync.view.request_render()
        self.figure.clear()
        self.canvas.draw_idle()
        self.stats.setRowCount(0)

    # ------------------------------------------------------------------ display
    def show_result(self, result: results_data.CloudResult) -> None:
        self.result = result
        self.sync.view.show_cloud(result.points_world, result.distances_m, result.limit_m)
        self.state.setText(f"{result.name}: {len(result.points_world):,} points against "
                           f"{result.reference or 'the truth'}; colours "
                           f"±{1000 * result.limit_m:.1f} mm (98th percentile of |Δ|)")
        self._histogram(result)
        rows = result.rows()
        self.stats.setRowCount(len(rows))
        for r, (k, v) in enumerate(rows):
            self.stats.setItem(r, 0, QTableWidgetItem(k))
            self.stats.setItem(r, 1, QTableWidgetItem(v))

    def _histogram(self, result: results_data.CloudResult) -> None:
        import matplotlib

        hist = result.stats["histogram"]
        edges = 1000 * np.asarray(hist["edges"])
        counts = np.asarray(hist["counts"])
        lim = 1000 * result.limit_m
        self.figure.clear()
        ax = self.figure.add_subplot()
        centres = (edges[:-1] + edges[1:]) / 2
        cmap = matplotlib.colormaps[CMAP]
        ax.bar(centres, counts, width=np.diff(edges),
               color=[cmap(0.5 + 0.5 * np.clip(c / lim, -1, 1)) for c in centres])
        ax.axvline(0, color="k", lw=0.8)
        ax.set_xlabel("signed distance (mm)")
        ax.set_ylabel("points")
        self.canvas.draw_idle()

    def show_gcp_errors(self, result: dict) -> None:
        """Per-GCP errors (mm) and RMSE per role from ``designer.evaluate.gcp_errors``."""
        rows = result["points"]
        self.gcp_table.setRowCount(len(rows))
        for r, g in enumerate(rows):
            values = [g["gcp_id"], g["role"]] + [f"{1000 * g[k]:+.1f}" for k in
                                                 ("dX", "dY", "dZ")] + [f"{1000 * g['dXYZ']:.1f}"]
            for c, text in enumerate(values):
                self.gcp_table.setItem(r, c, QTableWidgetItem(text))
        parts = []
        for role in ("control", "check"):
            s = result["summary"][role]
            if s["n"]:
                parts.append(f"{role} ({s['n']}): RMSE XY {1000 * s['rmse_XY']:.1f} mm, "
                             f"Z {1000 * s['rmse_Z']:.1f} mm, XYZ {1000 * s['rmse_XYZ']:.1f} mm")
        if result["missing"]:
            parts.append("no estimate for " + ", ".join(result["missing"]))
        self.rmse.setText("\n".join(parts))
