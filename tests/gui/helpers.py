"""Helpers of the GUI tests: waiting for the window, finding fields, clicking the view."""

from __future__ import annotations

import time

import numpy as np


def wait_idle(qtbot, window, timeout_s: float = 60.0) -> None:
    """Wait until the window's background jobs are done and the view has drawn."""
    deadline = time.monotonic() + timeout_s
    while True:
        qtbot.waitUntil(lambda: not window.tasks.busy, timeout=int(timeout_s * 1000))
        qtbot.wait(50)
        if not window.tasks.busy:
            break
        assert time.monotonic() < deadline, "the window kept computing"
    window.view.render_now()


def field(window, cls, name: str):
    """The bound field whose object name is the model path ``name``."""
    widget = window.findChild(cls, name)
    assert widget is not None, f"no field {name}"
    return widget


def ground_pixels(window, n: int, margin: float = 0.3) -> list[tuple[int, int, np.ndarray]]:
    """n widget pixels over the terrain (a grid in the middle of the view) and the
    ground point under each."""
    plotter = window.view.plotter
    w, h = plotter.width(), plotter.height()
    out = []
    cols = int(np.ceil(np.sqrt(n)))
    rows = int(np.ceil(n / cols))
    for k in range(n):
        i, j = divmod(k, cols)
        x = int(w * (margin + (1 - 2 * margin) * (j + 0.5) / cols))
        y = int(h * (0.45 + 0.3 * (i + 0.5) / rows))
        ground = window.view.interaction.ground_at(x, y)
        assert ground is not None, f"no ground under pixel {(x, y)}"
        out.append((x, y, ground))
    return out


def problems(window) -> list[str]:
    """The lines of the Problems panel."""
    return [window.problems.item(i).text() for i in range(window.problems.count())]


def answer_file_dialog(path) -> None:
    """Choose ``path`` in the next file dialog the window opens (Qt's own dialog, as on a
    desktop without a native one): select the file and press Open."""
    from PySide6.QtCore import QTimer
    from PySide6.QtWidgets import QApplication, QFileDialog, QLineEdit

    def answer() -> None:
        dialog = QApplication.activeModalWidget()
        if not isinstance(dialog, QFileDialog):
            QTimer.singleShot(50, answer)
            return
        # typed into the file name field, as a person would (selectFile() waits for the
        # dialog's folder listing, which is read in a thread)
        dialog.findChild(QLineEdit, "fileNameEdit").setText(str(path))
        dialog.accept()

    QTimer.singleShot(50, answer)
