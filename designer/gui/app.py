"""Start the designer window (``designer gui``), or render it once into a PNG."""

from __future__ import annotations

import sys
import time
from pathlib import Path

from designer.errors import DesignerError

#: longest wait (s) for the scene to be computed before a screenshot
SCREENSHOT_TIMEOUT_S = 180.0


def application():
    """The QApplication (created once)."""
    from PySide6.QtWidgets import QApplication

    app = QApplication.instance()
    if app is None:
        app = QApplication(sys.argv[:1])
        app.setApplicationName("designer")
        app.setOrganizationName("designer")
    return app


def wait_idle(window, timeout_s: float = SCREENSHOT_TIMEOUT_S) -> None:
    """Process events until every background job of the window has finished."""
    app = application()
    deadline = time.monotonic() + timeout_s
    idle_since = None
    while time.monotonic() < deadline:
        app.processEvents()
        if window.tasks.busy:
            idle_since = None
        elif idle_since is None:
            idle_since = time.monotonic()
        elif time.monotonic() - idle_since > 0.3:
            return
        time.sleep(0.01)
    raise DesignerError(f"the window was still computing after {timeout_s:.0f} s")


def run(project: Path | None = None, screenshot: Path | None = None,
        panel: str | None = None) -> int:
    """Open the window on ``project``; with ``screenshot``, save one frame and exit."""
    from designer.gui.xvfb import ensure_display, stop_xvfb

    xvfb = ensure_display() if screenshot is not None else None
    try:
        app = application()
        from designer.gui.qt.main_thread_gc import MainThreadCollector
        from designer.gui.qt.main_window import MainWindow

        MainThreadCollector(app)  # garbage collected on this thread only

        window = MainWindow()
        if project is not None and not window.open_project(Path(project)):
            problems = [window.problems.item(i).text() for i in range(window.problems.count())]
            if screenshot is None:
                window.show()
                return app.exec()
            raise DesignerError("cannot open the project:\n" + "\n".join(problems))
        window.show()
        if screenshot is None:
            return app.exec()
        if panel is not None:
            if panel not in window.docks:
                raise DesignerError(f"--panel {panel}: choose one of {', '.join(window.docks)}")
            window.docks[panel].show()
            window.docks[panel].raise_()
        wait_idle(window)
        window.save_screenshot(Path(screenshot))
        window.close_without_prompt()
        window.deleteLater()
        app.processEvents()
        return 0
    finally:
        if xvfb is not None:
            # Qt keeps its X connection until the application object is gone; stopping
            # the server first would make Qt abort the process.
            from PySide6.QtWidgets import QApplication

            if QApplication.instance() is not None:
                QApplication.instance().shutdown()
            stop_xvfb(xvfb)
