"""Results: reconstruct the rendered survey (COLMAP, then the comparison with the truth,
in other processes), or open any point cloud; the cloud is coloured by its signed
distance to the true terrain (diverging map, colour bar in the view), with a histogram,
statistics and the GCP error table. Reading clouds and distances run off the UI thread."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from PySide6.QtWidgets import (
    QFileDialog,
    QGroupBox,
    QHBoxLayout,
    QLabel,
    QProgressBar,
    QPushButton,
    QTableWidget,
    QTableWidgetItem,
    QVBoxLayout,
)

from designer.gui.qt.boxes import log_view
from designer.gui.qt.panels.base import Panel
from designer.gui.qt.panels.dense_view import DenseView
from designer.gui.qt.panels.out_of_date import OutOfDate
from designer.gui.qt.reconstruct_process import ReconstructRun
from designer.gui.qt.widgets import combo, dspin, form, readout
from designer.gui.state import output_state, results_data
from designer.gui.state.reconstruct_job import (
    MODES,
    STAGES,
    ReconstructJob,
    processing_text,
    survey_status,
)
from designer.gui.state.wording import count, point_text

CMAP = "RdBu_r"


#: the picked-point line while no point of the cloud shown is picked
PICK_HINT = "click a point of the cloud in the view to read its distance"

class ResultsPanel(Panel):
    title = "Results"
    parts = frozenset({"outputs", "processing"})

    def build(self, layout) -> None:
        self._build_reconstruct(layout)
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
        self.state = QLabel("")
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
        self.clipped_label = QLabel("")
        self.clipped_label.setWordWrap(True)
        v.addWidget(self.clipped_label)
        f = form()
        # at least 0.1 mm (the field's last decimal): a range of 0 is refused with a
        # message, not taken and then ignored
        self.range_spin = dspin(1000 * results_data.COLOUR_RANGE_STEP_M, 1e7, 1, 1.0, "mm",
                                label="Colour range ±")
        self.range_spin.setToolTip("the colours (and the histogram) span ± this distance, "
                                   "at least 0.1 mm; points beyond take the end colours")
        self._range_idle()
        self.range_spin.valueChanged.connect(lambda v: self.set_range(v / 1000))
        f.addRow("colour range ±", self.range_spin)
        self.picked = readout()
        self.picked.setText(PICK_HINT)
        f.addRow("picked point", self.picked)
        v.addLayout(f)
        self.stats = QTableWidget(0, 2)
        self.stats.setHorizontalHeaderLabels(["statistic", "value"])
        self.stats.horizontalHeader().setStretchLastSection(True)
        self.stats.setMinimumHeight(180)
        v.addWidget(self.stats)
        self.outlier_label = QLabel("")
        self.outlier_label.setWordWrap(True)
        v.addWidget(self.outlier_label)
        self.outlier_table = QTableWidget(0, 4)
        self.outlier_table.setHorizontalHeaderLabels(["Δ", "E", "N", "H"])
        self.outlier_table.setMinimumHeight(120)
        self.outlier_table.setMaximumHeight(200)
        v.addWidget(self.outlier_table)
        layout.addWidget(hist)
        self.sync.view.clicked.connect(self.pick_point)

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
        self._compared: Path | None = None
        #: the reconstruction folder the comparison shown was made from
        self._compared_dir: Path | None = None
        self.limit_m = 1.0
        self._pending_residuals = None
        self.editor.document.events.connect("reset", self._reopened)
        self.sync.terrain_changed.connect(self._terrain_ready)
        self._missing = ""
        self._show_missing()

    def _build_reconstruct(self, layout) -> None:
        box = QGroupBox("reconstruct the rendered survey")
        f = form(box)
        self.survey_label = readout()
        f.addRow("survey", self.survey_label)
        self.mode = combo([(text, mode) for text, mode in MODES])
        f.addRow("poses", self.mode)
        self.settings_label = readout()
        self.settings_label.setToolTip("the project's <processing>, set in the Processing "
                                       "panel")
        f.addRow("processing", self.settings_label)
        row = QHBoxLayout()
        self.reconstruct_button = QPushButton("Reconstruct")
        self.reconstruct_button.setToolTip(
            "designer reconstruct, then designer compare with the true surface, in other "
            "processes; the cloud then appears coloured by its error")
        self.reconstruct_button.clicked.connect(self.reconstruct)
        self.cancel_button = QPushButton("Cancel")
        self.cancel_button.setEnabled(False)
        self.cancel_button.clicked.connect(self.cancel_reconstruction)
        row.addWidget(self.reconstruct_button)
        row.addWidget(self.cancel_button)
        f.addRow(row)
        self.progress = QProgressBar()
        self.progress.setRange(0, len(STAGES))
        self.progress.setValue(0)
        self.progress.setFormat("%v / %m stages")
        f.addRow(self.progress)
        self.stage_label = QLabel("")
        self.stage_label.setWordWrap(True)
        f.addRow(self.stage_label)
        self.log = log_view(500, 90)
        f.addRow(self.log)
        self.out_of_date = OutOfDate("results-out-of-date")
        f.addRow(self.out_of_date)
        layout.addWidget(box)
        self.dense = DenseView()
        self.dense.show_cloud.connect(self.show_reconstructed_cloud)
        layout.addWidget(self.dense)
        self.run = ReconstructRun(self)
        self.run.stage.connect(self._stage)
        self.run.output.connect(self.log.appendPlainText)
        self.run.finished.connect(self._reconstructed)
        self.job: ReconstructJob | None = None
        self.editor.document.events.connect("file", lambda **_: self.survey_readout())

    # ------------------------------------------------------------------ reconstruct
    def refresh(self) -> None:
        super().refresh()
        self.survey_readout()
        self.settings_label.setText(processing_text(self.project.processing))

    def showEvent(self, event) -> None:  # a render may have finished meanwhile
        super().showEvent(event)
        self.survey_readout()

    def survey_dir(self) -> Path | None:
        """The render output folder of the saved project (None while never saved)."""
        path = self.editor.document.path
        if path is None:
            return None
        return (path.parent / self.project.outputs.directory).resolve()

    def missing_text(self) -> str:
        """What the panel shows while it shows no cloud: that there is no reconstruction
        and what makes one (save, render, Reconstruct)."""
        folder = self.survey_dir()
        if folder is None:
            return ("no reconstruction: save the project, render it (Render panel) and "
                    "press Reconstruct above; or open the cloud of a reconstruction")
        n, _text = survey_status(folder)
        if not n:
            return (f"no reconstruction: the survey is not rendered yet in {folder}; "
                    "render it in the Render panel, then press Reconstruct above")
        return (f"no reconstruction in {folder}: press Reconstruct above to make one from "
                f"its {count(n, 'rendered image')}")

    def _show_missing(self) -> None:
        self._missing = self.missing_text()
        self.state.setText(self._missing)

    def survey_readout(self) -> None:
        if self.state.text() == self._missing:  # no cloud shown: saved or rendered since?
            self._show_missing()
        folder = self.survey_dir()
        if folder is None:
            self.survey_label.setText("– (save the project and render it first)")
            return
        n, text = survey_status(folder)
        self.survey_label.setText(text if n else f"{folder}: not rendered yet")

    def reconstruct(self) -> None:
        """Run designer reconstruct and designer compare on the rendered survey."""
        doc = self.editor.document
        if doc.dirty or doc.path is None:
            window = self.window()
            if not hasattr(window, "file_actions") or not window.file_actions.save():
                self.stage_label.setText("save the project (without problems) first: the "
                                         "comparison reads the saved file")
                return
        folder = self.survey_dir()
        n, text = survey_status(folder)
        self.survey_readout()
        if not n:
            self.stage_label.setText(f"{text}. Render the survey first (Render panel).")
            return
        self.job = ReconstructJob(doc.path, folder, self.mode.currentData())
        self._digests = output_state.manifest_digests(folder)  # the images it is made from
        self.log.clear()
        self.progress.setValue(0)
        self.stage_label.setText(f"reconstructing {count(n, 'image')} into {self.job.out_dir} …")
        self.reconstruct_button.setEnabled(False)
        self.cancel_button.setEnabled(True)
        self.run.start(self.job)

    def cancel_reconstruction(self) -> None:
        self.run.cancel()
        self.stage_label.setText("stopping…")

    def _stage(self, index: int, title: str) -> None:
        self.progress.setValue(index)
        self.stage_label.setText(f"stage {index + 1} of {len(STAGES)}: {title} …")

    def _reconstructed(self, code: int, message: str) -> None:
        self.reconstruct_button.setEnabled(True)
        self.cancel_button.setEnabled(False)
        if code != 0:
            self.stage_label.setText("cancelled" if code == 130 else message)
            return
        self.progress.setValue(len(STAGES))
        job = self.job
        output_state.record_reconstruction_inputs(job.survey_dir, job.out_dir, self._digests)
        self.stage_label.setText(f"done: {job.out_dir}; report {job.compare_dir / 'report.html'}")
        self._compared, self._compared_dir = job.distances_ply, job.out_dir
        dense = self.dense.load(job.out_dir)
        self.show_reconstructed_cloud(dense.cloud_ply if dense is not None else None)
        if job.gcp_residuals_csv.is_file():
            self.open_residuals(job.gcp_residuals_csv)

    def _reopened(self, project) -> None:
        """Another project: drop the shown results, show its last reconstruction."""
        self.clear()
        self.gcp_table.setRowCount(0)
        self.rmse.setText("")
        folder = self.survey_dir()
        found = results_data.last_reconstruction(folder) if folder is not None else None
        self._compared = found.distances_ply if found is not None else None
        self._compared_dir = found.out_dir if found is not None else None
        dense = self.dense.load(self._compared_dir)
        if found is None:
            return  # the poses chosen stay as they are
        # the poses selector shows the poses of the reconstruction shown
        index = self.mode.findData(found.mode)
        if index >= 0:
            self.mode.setCurrentIndex(index)
        self.show_reconstructed_cloud(dense.cloud_ply if dense is not None else None)
        residuals = found.out_dir / "gcp_residuals.csv"
        # the GCPs' truth needs the terrain, which is being computed right now
        self._pending_residuals = residuals if residuals.is_file() else None

    def show_render_state(self, state) -> None:
        """Out of date when the images changed after the reconstruction shown, or when
        the rendered images no longer match the project."""
        self.survey_readout()  # the folder was just read: rendered meanwhile?
        stale = None
        if self._compared_dir is not None and self.survey_dir() is not None:
            stale = output_state.reconstruction_state(self.survey_dir(),
                                                      self._compared_dir,
                                                      self.project.processing)
        if not stale and state is not None and not state.ok and self._compared is not None:
            stale = output_state.images_stale_text(state)
        self.out_of_date.show_state(stale, "reconstructed from the images rendered now"
                                    if self._compared is not None and state is not None
                                    else "")

    def show_reconstructed_cloud(self, dense_ply: Path | None) -> None:
        """The dense cloud coloured by its distance to the true surface (computed here, in
        a worker thread), or with None the sparse one as designer compare measured it."""
        if dense_ply is not None:
            self.open_cloud(dense_ply, residuals=False)
            return
        found = self._compared
        if found is None:
            return
        self.state.setText(f"reading {found} …")
        name = self.editor.document.path.name if self.editor.document.path else "the project"
        self.sync.tasks.submit(
            "cloud", results_data.load_compared_cloud, found,
            f"terrain and targets of {name} (designer compare)",
            on_done=self.show_result, on_error=lambda e: self.state.setText(f"{found}: {e}"))

    def _terrain_ready(self) -> None:
        pending, self._pending_residuals = self._pending_residuals, None
        if pending is not None and self.sync.terrain is not None:
            self.open_residuals(pending)

    def shutdown(self) -> None:
        if self.run.running:
            self.run.kill()

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

    def open_cloud(self, path: Path, residuals: bool = True) -> None:
        """Read the cloud and compare it with the true surface in a worker thread."""
        doc, terrain = self.editor.document, self.sync.terrain
        self.state.setText(f"reading {path.name} and computing distances…")
        self.sync.tasks.submit(
            "cloud", results_data.evaluate_cloud, Path(path), doc.path, doc.dirty,
            terrain.heightfield if terrain else None, terrain.mesh if terrain else None,
            on_done=self.show_result,
            on_error=lambda e: self.state.setText(f"{path.name}: {e}"))
        csv = Path(path).with_name("gcp_residuals.csv")
        if residuals and csv.is_file():
            self.open_residuals(csv)

    def open_residuals(self, path: Path) -> None:
        """GCP errors of estimates in a CSV against the project's targets (a thread)."""
        terrain = self.sync.terrain
        self.sync.tasks.submit(
            "gcp-errors", results_data.evaluate_gcps, Path(path), self.project,
            terrain.heightfield if terrain else None, on_done=self.show_gcp_errors,
            on_error=lambda e: self.rmse.setText(f"{Path(path).name}: {e}"))

    def _range_idle(self) -> None:
        """No distances shown: the colour range, greyed, says it comes from them (not the
        field's minimum, which no result has set)."""
        self.range_spin.blockSignals(True)
        self.range_spin.setEnabled(False)
        self.range_spin.setMinimum(0.0)
        self.range_spin.setSpecialValueText("set by the distances")
        self.range_spin.setValue(0.0)
        self.range_spin.blockSignals(False)

    def clear(self) -> None:
        self.sync.view.remove_layer("residuals")
        self.result = None
        self._show_missing()
        self.picked.setText(PICK_HINT)
        self._range_idle()
        self.outlier_table.setRowCount(0)
        self.outlier_label.setText("")
        self.clipped_label.setText("")
        self.sync.view.remove_layer("cloud")
        self.sync.view.request_render()
        self.figure.clear()
        self.canvas.draw_idle()
        self.stats.setRowCount(0)

    # ------------------------------------------------------------------ display
    def show_result(self, result: results_data.CloudResult) -> None:
        """Show a cloud: coloured in the view, robust statistics, outliers, histogram."""
        self.result = result
        self.picked.setText(PICK_HINT)  # a point picked in the cloud shown before is gone
        self.limit_m = result.limit_m
        self.sync.view.show_cloud(result.points_world, result.distances_m, result.limit_m)
        n_out = result.n_outliers
        self.state.setText(f"{result.name}: {len(result.points_world):,} points against "
                           f"{result.reference or 'the truth'}; {_outliers(n_out)}")
        rows = result.rows()
        self.stats.setRowCount(len(rows))
        for r, (k, v) in enumerate(rows):
            self.stats.setItem(r, 0, QTableWidgetItem(k))
            self.stats.setItem(r, 1, QTableWidgetItem(v))
        listed = result.outliers()
        self.outlier_label.setText(
            "no outliers" if not n_out else
            _outliers(n_out) + (f", the {len(listed)} largest:" if n_out > len(listed)
                                       else ":"))
        self.outlier_table.setRowCount(len(listed))
        for r, k in enumerate(listed):
            x, y, z = result.points_world[k]
            for c, text in enumerate((_distance_text(result.distances_m[k]), f"{x:.3f}",
                                      f"{y:.3f}", f"{z:.3f}")):
                self.outlier_table.setItem(r, c, QTableWidgetItem(text))
        self.range_spin.setEnabled(True)
        self.range_spin.blockSignals(True)
        self.range_spin.setSpecialValueText("")
        self.range_spin.setMinimum(1000 * results_data.COLOUR_RANGE_STEP_M)
        self.range_spin.setValue(1000 * result.limit_m)
        self.range_spin.blockSignals(False)
        self._histogram(result)

    def set_range(self, limit_m: float) -> None:
        """Colour the cloud and draw the histogram over ±limit_m."""
        if self.result is None or not limit_m > 0:
            return
        self.limit_m = limit_m
        self.sync.view.set_cloud_range(limit_m)
        self._histogram(self.result)

    def pick_point(self, x_px: float, y_px: float) -> None:
        """A click in the view: the distance of the cloud point under it."""
        if self.result is None:
            return
        k = self.sync.view.cloud_point_at(x_px, y_px)
        if k is None:
            return
        text = (f"Δ = {_distance_text(self.result.distances_m[k])} at "
                f"{point_text(self.result.points_world[k])}")
        self.picked.setText(text)
        window = self.window()
        if hasattr(window, "statusBar"):
            window.statusBar().showMessage(f"point {k}: {text}", 15000)

    def _histogram(self, result: results_data.CloudResult) -> None:
        below, above = results_data.draw_histogram(self.figure, result.distances_m,
                                                   self.limit_m, CMAP)
        lim = 1000 * self.limit_m
        self.histogram_range_mm = (-lim, lim)
        self.clipped_label.setText(
            f"histogram and colours over ±{lim:.1f} mm; outside: {below:,} below, "
            f"{above:,} above" if below or above else
            f"histogram and colours over ±{lim:.1f} mm; every point inside")
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
        scale = self._draw_residuals(rows)
        if scale is not None:
            parts.append(f"in the view: yellow lines from each true GCP to its estimate, "
                         f"errors drawn × {scale:g}")
        self.rmse.setText("\n".join(parts))

    def _draw_residuals(self, rows: list[dict]) -> float | None:
        """GCP errors as lines in the 3D view (see results_data.residual_lines)."""
        if not rows:
            self.sync.view.show_residuals(np.zeros((0, 3)), np.zeros((0, 3)), [], "")
            return None
        true, end, labels, scale = results_data.residual_lines(
            rows, self.project.scene.terrain.extent)
        self.sync.view.show_residuals(true, end, labels, f"× {scale:g}",
                                      [g["gcp_id"] for g in rows])
        return scale

def _distance_text(d: float) -> str:
    """A signed distance in mm below 10 m, else in m (fixed point)."""
    return f"{1000 * d:+.1f} mm" if abs(d) < 10 else f"{d:+.3f} m"


def _outliers(n: int) -> str:
    """``1 outlier``, ``1,234 outliers``."""
    return f"{n:,} outlier{'' if n == 1 else 's'}"
