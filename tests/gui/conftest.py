"""GUI tests run on a real X server: Xvfb is started here when DISPLAY is unset.

Qt's offscreen platform cannot host VTK's OpenGL widget, so tests marked ``gui`` get a
virtual display (``Xvfb :N -screen 0 1600x1000x24``) for the whole session and the
``xcb`` platform. Tests without the marker (the Qt-free modules) need neither.
"""

from __future__ import annotations

import gc
import os

import pytest

from designer.gui.xvfb import start_xvfb, stop_xvfb
from tests.gui.helpers import wait_idle


@pytest.fixture(scope="session")
def x_display():
    os.environ["QT_QPA_PLATFORM"] = "xcb"
    proc = None
    if not os.environ.get("DISPLAY"):
        proc, display = start_xvfb()
        os.environ["DISPLAY"] = display
    yield os.environ["DISPLAY"]
    if proc is not None:
        # Qt holds its X connection until the application object is gone.
        from PySide6.QtWidgets import QApplication

        if QApplication.instance() is not None:
            QApplication.instance().shutdown()
        stop_xvfb(proc)


@pytest.fixture(scope="session")
def qapp_args(x_display):
    """pytest-qt's QApplication is made on the display (overrides its fixture)."""
    return ["designer-gui-tests"]


#: tracked objects left alive after a test's collection above which they are frozen
FREEZE_OBJECTS = 50_000


@pytest.fixture(autouse=True)
def _collect_on_the_main_thread():
    """No automatic garbage collection during a GUI test; after it (and after pytest-qt
    closed its widgets) one collection on the main thread. An automatic collection runs
    in whichever thread happens to allocate: in a background task's thread it would free
    a closed window's VTK plotter, whose OpenGL objects' deletion waits for VTK's
    collector while the main thread, drawing, holds that collector and waits for the GIL
    the task thread holds — both would wait for ever (seen under load: a worker stuck in
    ``BasePlotter.__del__`` from ``designer-gui_1`` while the main thread sat in
    ``_cb_make_current``).

    After a collection that leaves more than FREEZE_OBJECTS tracked objects alive (after
    the first GUI test: the modules, Qt's and VTK's wrappers, some 300 000; later, a
    test that imported more modules) they are frozen (``gc.freeze``): later collections
    look only at what the tests since made, a few thousand objects, milliseconds instead
    of half a second each."""
    gc.disable()
    try:
        yield
    finally:
        gc.collect()
        if len(gc.get_objects()) > FREEZE_OBJECTS:
            gc.freeze()
        gc.enable()


@pytest.fixture
def settings(tmp_path):
    from PySide6.QtCore import QSettings

    return QSettings(str(tmp_path / "designer-gui.ini"), QSettings.Format.IniFormat)


@pytest.fixture
def window(qtbot, settings, tmp_path, monkeypatch):
    """The designer window, shown, on a blank project; closed without prompts."""
    from PySide6.QtWidgets import QMessageBox

    from designer.gui.qt.main_window import MainWindow

    monkeypatch.chdir(tmp_path)
    monkeypatch.setattr(QMessageBox, "question",
                        staticmethod(lambda *a, **k: QMessageBox.StandardButton.Discard))
    w = MainWindow(settings=settings)
    qtbot.addWidget(w)
    w.show()
    qtbot.waitExposed(w)
    wait_idle(qtbot, w)
    yield w
    w.close()


@pytest.fixture
def saved_project(qtbot, window, tmp_path):
    """The window with a small flight saved as small.xml (the Render panel tests)."""
    from designer.gui.state import edits
    from tests.gui.helpers import problems, wait_idle

    w = window
    project = edits.ensure_flight_plan(w.document.project)
    project = edits.set_flight(project, area=((-20.0, -20.0), (20.0, -20.0), (20.0, 20.0),
                                              (-20.0, 20.0)), altitude_agl_m=60.0)
    w.editor.edit(project, "small flight")
    wait_idle(qtbot, w)
    assert w.file_actions.save_to(tmp_path / "small.xml"), problems(w)
    return w
