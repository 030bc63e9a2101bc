"""The dense part of the Results panel: the DEM of difference (``dod.png``) of the last
reconstruction, its dome amplitude, and which cloud the view shows (dense or sparse)."""

from __future__ import annotations

from pathlib import Path

from PySide6.QtCore import Qt, Signal
from PySide6.QtGui import QPixmap
from PySide6.QtWidgets import QGroupBox, QHBoxLayout, QLabel, QPushButton, QVBoxLayout

from designer.gui.state.reconstruct_job import DenseProducts, dense_products


class DenseView(QGroupBox):
    """Shown when the reconstruction has dense products; asks for a cloud to be shown."""

    #: the cloud file to show coloured by its error (dense.ply, or None: the sparse one)
    show_cloud = Signal(object)

    def __init__(self, parent=None) -> None:
        super().__init__("dense cloud and DEM of difference", parent)
        v = QVBoxLayout(self)
        self.summary = QLabel("")
        self.summary.setObjectName("dense-summary")
        self.summary.setWordWrap(True)
        v.addWidget(self.summary)
        self.image = QLabel()
        self.image.setObjectName("dod-image")
        self.image.setAlignment(Qt.AlignmentFlag.AlignCenter)
        v.addWidget(self.image)
        row = QHBoxLayout()
        self.dense_button = QPushButton("Show the dense cloud")
        self.dense_button.clicked.connect(lambda: self.show_cloud.emit(self.products.cloud_ply))
        self.sparse_button = QPushButton("Show the sparse cloud")
        self.sparse_button.clicked.connect(lambda: self.show_cloud.emit(None))
        row.addWidget(self.dense_button)
        row.addWidget(self.sparse_button)
        v.addLayout(row)
        self.products: DenseProducts | None = None
        self.hide()

    def load(self, out_dir: Path | None) -> DenseProducts | None:
        """Show the dense products of the reconstruction in ``out_dir`` (hidden if none)."""
        self.products = dense_products(out_dir) if out_dir is not None else None
        self.setVisible(self.products is not None)
        if self.products is None:
            return None
        self.summary.setText(self.products.text())
        pixmap = QPixmap(str(self.products.dod_png))
        if pixmap.isNull():
            self.image.setText(f"{self.products.dod_png}: not readable")
        else:
            self.image.setPixmap(pixmap.scaledToWidth(
                340, Qt.TransformationMode.SmoothTransformation))
        return self.products
