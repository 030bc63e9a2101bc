"""A rendered image at full size with the GCP observations drawn on it: a ring and the
id at each GCP's projected centre (pixel coordinates of the rendered image)."""

from __future__ import annotations

from PySide6.QtCore import QPointF, Qt
from PySide6.QtGui import QColor, QFont, QPainter, QPen, QPixmap
from PySide6.QtWidgets import QDialog, QLabel, QScrollArea, QVBoxLayout, QWidget

RING_COLOUR = "#ff2d55"


def annotated(path: str, observations: list[tuple[str, float, float]]) -> QPixmap:
    """The image with a ring and a label per (id, u, v) observation."""
    pixmap = QPixmap(path)
    if pixmap.isNull():
        return pixmap
    painter = QPainter(pixmap)
    painter.setRenderHint(QPainter.RenderHint.Antialiasing)
    radius = max(6.0, 0.02 * max(pixmap.width(), pixmap.height()))
    pen = QPen(QColor(RING_COLOUR))
    pen.setWidthF(max(2.0, radius / 5))
    painter.setPen(pen)
    font = QFont()
    font.setPixelSize(int(max(10, radius)))
    font.setBold(True)
    painter.setFont(font)
    for gid, u, v in observations:
        centre = QPointF(u, v)
        painter.drawEllipse(centre, radius, radius)
        painter.drawText(centre + QPointF(radius * 1.2, -radius * 0.4), gid)
    painter.end()
    return pixmap


class ImageViewer(QDialog):
    """Shows one image; the observations it has are listed in the title."""

    def __init__(self, path: str, observations, parent: QWidget | None = None) -> None:
        super().__init__(parent)
        self.observations = list(observations)
        ids = ", ".join(o[0] for o in self.observations) or "no GCP"
        self.setWindowTitle(f"{path} — {ids}")
        self.label = QLabel()
        self.label.setAlignment(Qt.AlignmentFlag.AlignCenter)
        self.pixmap = annotated(path, self.observations)
        self.label.setPixmap(self.pixmap)
        scroll = QScrollArea()
        scroll.setWidget(self.label)
        scroll.setWidgetResizable(True)
        layout = QVBoxLayout(self)
        layout.addWidget(scroll)
        caption = QLabel(f"GCPs seen (projected true centres): {ids}")
        caption.setWordWrap(True)
        layout.addWidget(caption)
        self.resize(min(1200, self.pixmap.width() + 40), min(900, self.pixmap.height() + 80))
