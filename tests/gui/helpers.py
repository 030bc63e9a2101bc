"""Helpers of the GUI tests: waiting for the window, finding fields, clicking the view."""

from __future__ import annotations

import textwrap
import time

import numpy as np
from PySide6.QtCore import Qt
from PySide6.QtTest import QTest

#: rounds of posted layout requests delivered after the jobs: a label that grows asks its
#: panel's layout, which asks the scroll area around it to fit the panel anew (one round
#: each), and so on up the nested layouts
LAYOUT_ROUNDS = 8


def wait_idle(qtbot, window, timeout_s: float = 60.0) -> None:
    """Wait until the window's background jobs are done, the view has drawn and the
    panels are laid out for what the jobs wrote into them."""
    from PySide6.QtCore import QCoreApplication, QEvent

    deadline = time.monotonic() + timeout_s
    while True:
        qtbot.waitUntil(lambda: not window.tasks.busy, timeout=int(timeout_s * 1000))
        qtbot.wait(50)
        if not window.tasks.busy:
            break
        assert time.monotonic() < deadline, "the window kept computing"
    window.view.render_now()
    # figures arriving just before can leave a scroll area fitting its panel a round
    # later (meanwhile its fields sit where the old, shorter figures left them)
    for _ in range(LAYOUT_ROUNDS):
        QCoreApplication.sendPostedEvents(None, QEvent.Type.LayoutRequest.value)


def refused_message(qtbot, window, before, panel) -> str:
    """After an edit the window must refuse: nothing reached the project (it still equals
    ``before``); what ``panel`` says about it."""
    wait_idle(qtbot, window)
    assert window.document.project == before, "applied"
    return panel.input_label.text()


def field(window, cls, name: str):
    """The bound field in ``window`` (the window, or one of its panels) whose object name
    is ``name`` (the model path, or the field's label)."""
    widget = window.findChild(cls, name)
    assert widget is not None, f"no field {name}"
    return widget


def open_panel(window, title: str):
    """The window's panel ``title``, its dock raised to the top of its tab group."""
    window.docks[title].raise_()
    return window.panels[title]


def ground_pixels(window, n: int, margin: float = 0.3) -> list[tuple[int, int, np.ndarray]]:
    """n widget pixels over the terrain (a grid over the middle of the terrain's extent,
    ``margin`` of it left on each side, as the view draws it, whatever the view's size and
    framing) and the ground point under each."""
    view = window.view
    plotter = view.plotter
    ren = plotter.renderer
    h, dpr = plotter.height(), plotter.devicePixelRatioF()
    e = window.document.project.scene.terrain.extent
    z = window.sync.terrain.z_mean_m if window.sync.terrain is not None else 0.0
    corners = []
    for fx in (margin, 1 - margin):
        for fy in (margin, 1 - margin):
            xyz = np.array([e.min_X + fx * (e.max_X - e.min_X),
                            e.min_Y + fy * (e.max_Y - e.min_Y), z])
            ren.SetWorldPoint(*(xyz - view.offset), 1.0)
            ren.WorldToDisplay()
            xd, yd, _ = ren.GetDisplayPoint()
            corners.append((xd / dpr, h - 1 - yd / dpr))
    xs, ys = zip(*corners, strict=True)
    out = []
    cols = int(np.ceil(np.sqrt(n)))
    rows = int(np.ceil(n / cols))
    for k in range(n):
        i, j = divmod(k, cols)
        x = int(min(xs) + (max(xs) - min(xs)) * (j + 0.5) / cols)
        y = int(min(ys) + (max(ys) - min(ys)) * (i + 0.5) / rows)
        ground = window.view.interaction.ground_at(x, y)
        assert ground is not None, f"no ground under pixel {(x, y)}"
        out.append((x, y, ground))
    return out


def problems(window) -> list[str]:
    """The lines of the Problems panel."""
    return [window.problems.item(i).text() for i in range(window.problems.count())]


def answer_file_dialog(path, timeout_s: float = 20.0) -> None:
    """Choose ``path`` in the next file dialog the window opens (Qt's own dialog, as on a
    desktop without a native one): select the file and press Open.

    Gives up after ``timeout_s``: any other modal window then open is closed (so the
    test is not left blocked in it) and the test fails with the reason."""
    from PySide6.QtCore import QTimer
    from PySide6.QtWidgets import QApplication, QDialog, QFileDialog, QLineEdit

    deadline = time.monotonic() + timeout_s

    def answer() -> None:
        dialog = QApplication.activeModalWidget()
        if not isinstance(dialog, QFileDialog):
            if time.monotonic() < deadline:
                QTimer.singleShot(50, answer)
                return
            seen = type(dialog).__name__ if dialog is not None else "no modal window"
            if isinstance(dialog, QDialog):
                dialog.reject()
            raise AssertionError(f"no file dialog opened within {timeout_s:g} s to choose "
                                 f"{path} (found: {seen})")
        # typed into the file name field, as a person would (selectFile() waits for the
        # dialog's folder listing, which is read in a thread)
        dialog.findChild(QLineEdit, "fileNameEdit").setText(str(path))
        dialog.accept()

    QTimer.singleShot(50, answer)


def open_with_ctrl_o(qtbot, window, path) -> None:
    """File → Open as a user does it: Ctrl+O in the active window, ``path`` answered in
    the file dialog; then wait until the window has computed what the file holds."""
    from PySide6.QtCore import Qt
    from PySide6.QtTest import QTest

    answer_file_dialog(path)
    window.activateWindow()
    qtbot.waitUntil(window.isActiveWindow)
    QTest.keyClick(window.windowHandle(), Qt.Key.Key_O, Qt.KeyboardModifier.ControlModifier)
    wait_idle(qtbot, window)


def set_field(qtbot, box, value) -> None:
    """Type a value into a spin box as a person would (select all, type, Enter)."""
    from PySide6.QtCore import Qt

    box.setFocus()
    box.selectAll()
    qtbot.keyClicks(box.lineEdit(), str(value))
    qtbot.keyClick(box.lineEdit(), Qt.Key.Key_Return)


def design_example(qtbot, w, n_gcps: int = 5) -> list[np.ndarray]:
    """A survey designed from scratch with the panels and the mouse: a new project,
    procedural hills typed in, ``n_gcps`` GCPs clicked on the terrain, the a6000 preset
    and a 40 m grid flight at 75/65 %; returns the ground points clicked."""
    import pytest
    from PySide6.QtCore import QPoint, Qt
    from PySide6.QtWidgets import QDoubleSpinBox, QSpinBox

    from designer.gui.state import camera_presets

    doc = w.document
    assert w.file_actions.new(None)
    wait_idle(qtbot, w)
    assert doc.project.scene.terrain.kind == "flat"

    # Terrain: procedural hills, relief and seed typed in.
    terrain = w.panels["Terrain"]
    terrain.kind.setCurrentIndex(terrain.kind.findData("procedural"))
    wait_idle(qtbot, w)
    assert doc.project.scene.terrain.kind == "procedural"
    set_field(qtbot, field(w, QDoubleSpinBox, "scene.terrain.source.max_height_m"), "8")
    set_field(qtbot, field(w, QSpinBox, "scene.terrain.source.seed"), "11")
    wait_idle(qtbot, w)
    src = doc.project.scene.terrain.source
    assert (src.max_height_m, src.seed) == (8.0, 11)
    hf = w.sync.terrain.heightfield
    # hills fixed to the world stay inside lowest..highest without reaching them exactly
    # (about 90 % of the relief over a terrain a few hill sizes across)
    lowest = src.min_height_m
    assert lowest <= hf.heights_m.min() and hf.heights_m.max() <= 8.0
    assert hf.heights_m.max() > lowest + 0.6 * (8.0 - lowest)

    # GCPs: five clicks on the terrain in the 3D view.
    gcps = w.panels["GCPs"]
    w.docks["GCPs"].raise_()
    qtbot.mouseClick(gcps.place, Qt.MouseButton.LeftButton)
    assert w.view.interaction.mode == "place"
    placed = []
    for x, y, ground in ground_pixels(w, n_gcps):
        qtbot.mouseClick(w.view.plotter, Qt.MouseButton.LeftButton, pos=QPoint(x, y))
        placed.append(ground)
    wait_idle(qtbot, w)
    targets = doc.project.targets
    assert [t.id for t in targets] == [f"GCP{k:02d}" for k in range(1, n_gcps + 1)]
    for t, ground in zip(targets, placed, strict=True):
        assert (t.true.X, t.true.Y) == pytest.approx(tuple(ground[:2]), abs=0.6e-4)  # 0.1 mm
        assert t.true.Z is None  # draped on the terrain
    assert gcps.table.rowCount() == n_gcps
    qtbot.mouseClick(gcps.place, Qt.MouseButton.LeftButton)
    assert w.view.interaction.mode == "navigate"

    # Camera: a preset of a real camera.
    camera = w.panels["Camera"]
    camera.preset.setCurrentIndex(camera.preset.findData("a6000"))
    cam = doc.project.cameras[0]
    a6000 = camera_presets.preset("a6000")
    assert (cam.focal_length_mm, cam.sensor_width_mm, cam.image_width_px) == (16.0, 23.5, 6000)
    assert cam.sensor_height_mm == pytest.approx(23.5 * 4000 / 6000)
    assert cam.sensor_height_mm == a6000.sensor_height_mm

    # Flight: a grid over the terrain at 40 m, 75/65 % overlap.
    flight = w.panels["Flight"]
    w.docks["Flight"].raise_()
    qtbot.mouseClick(flight.create, Qt.MouseButton.LeftButton)
    set_field(qtbot, field(w, QDoubleSpinBox, "trajectory.flight_plan.altitude_agl_m"), "40")
    set_field(qtbot, field(w, QDoubleSpinBox, "trajectory.flight_plan.front_overlap_percent"), "75")
    set_field(qtbot, field(w, QDoubleSpinBox, "trajectory.flight_plan.side_overlap_percent"), "65")
    wait_idle(qtbot, w)
    plan = doc.project.trajectory.flight_plan
    assert (plan.altitude_agl_m, plan.front_overlap_percent, plan.side_overlap_percent) == (
        40.0, 75.0, 65.0)
    assert plan.camera == cam.id
    return placed


def add_hills_and_flight(w) -> None:
    """Procedural hills (±3 m) and the default flight, as one edit."""
    from designer.gui.state import edits
    from designer.project import model as m

    project = w.document.project
    terrain = m.Terrain(project.scene.terrain.extent, m.ProceduralTerrain(
        seed=3, grid_spacing_m=1.0, roughness=0.2, min_height_m=-3.0, max_height_m=3.0))
    project = edits.ensure_flight_plan(edits.replace_path(project, "scene.terrain", terrain))
    w.editor.edit(project, "hills and a flight")


def write_xyz_ply(path, xyz) -> None:
    """A PLY file of the points ``xyz`` (N, 3), float64."""
    from plyfile import PlyData, PlyElement

    data = np.empty(len(xyz), dtype=[("x", "f8"), ("y", "f8"), ("z", "f8")])
    data["x"], data["y"], data["z"] = xyz.T
    PlyData([PlyElement.describe(data, "vertex")]).write(str(path))


def answer_file_dialogs(answers, timeout_s: float = 20.0) -> None:
    """Answer the next file dialogs in turn, as a person would: each answer is a path
    (typed into the file name field, then Open/Save), ``(path, file type)`` (the file
    type chosen first) or None (Cancel). Gives up like :func:`answer_file_dialog`."""
    from PySide6.QtCore import QTimer
    from PySide6.QtWidgets import QApplication, QDialog, QFileDialog, QLineEdit

    answers = list(answers)
    deadline = [time.monotonic() + timeout_s]

    def answer() -> None:
        dialog = QApplication.activeModalWidget()
        if not isinstance(dialog, QFileDialog) or not dialog.isVisible():
            if time.monotonic() < deadline[0]:
                QTimer.singleShot(50, answer)
                return
            seen = type(dialog).__name__ if dialog is not None else "no modal window"
            if isinstance(dialog, QDialog):
                dialog.reject()
            raise AssertionError(f"no file dialog opened within {timeout_s:g} s for "
                                 f"{answers[0]} (found: {seen})")
        given = answers.pop(0)
        if given is None:
            dialog.reject()
        else:
            path, file_type = given if isinstance(given, tuple) else (given, None)
            if file_type is not None:
                assert file_type in dialog.nameFilters(), dialog.nameFilters()
                dialog.selectNameFilter(file_type)
            dialog.findChild(QLineEdit, "fileNameEdit").setText(str(path))
            dialog.accept()
        if answers:
            deadline[0] = time.monotonic() + timeout_s
            QTimer.singleShot(100, answer)

    QTimer.singleShot(50, answer)


def choose_menu(qtbot, window, *titles: str) -> None:
    """Click through the menu bar: ``choose_menu(qtbot, w, "File", "Import flight",
    "From a folder of images…")`` (titles without their & accelerators)."""
    from PySide6.QtCore import Qt

    def find(actions, title):
        for action in actions:
            if action.text().replace("&", "") == title:
                return action
        raise AssertionError(f"no menu entry '{title}' in "
                             f"{[a.text() for a in actions if a.text()]}")

    bar = window.menuBar()
    action = find(bar.actions(), titles[0])
    qtbot.mouseClick(bar, Qt.MouseButton.LeftButton, pos=bar.actionGeometry(action).center())
    menu = action.menu()
    qtbot.waitUntil(menu.isVisible, timeout=5000)
    for title in titles[1:]:
        action = find(menu.actions(), title)
        submenu = action.menu()  # asked before the click, which may delete the entry
        qtbot.mouseClick(menu, Qt.MouseButton.LeftButton,
                         pos=menu.actionGeometry(action).center())
        if submenu is not None:
            menu = submenu
            qtbot.waitUntil(menu.isVisible, timeout=5000)


def type_cell(qtbot, w, table, row, col, text) -> None:
    """Double-click the cell, type over it, Enter (as a person edits a table)."""
    from PySide6.QtCore import Qt
    from PySide6.QtTest import QTest

    rect = table.visualItemRect(table.item(row, col))
    pos = table.viewport().mapTo(w, rect.center())
    QTest.mouseDClick(w.windowHandle(), Qt.MouseButton.LeftButton,
                      Qt.KeyboardModifier.NoModifier, pos)
    qtbot.wait(100)
    QTest.keyClick(w.windowHandle(), Qt.Key.Key_A, Qt.KeyboardModifier.ControlModifier)
    for ch in text:
        QTest.keyClick(w.windowHandle(), ch)
    QTest.keyClick(w.windowHandle(), Qt.Key.Key_Return)
    qtbot.wait(50)


def cloud_with_outlier(w, tmp_path, sigma_m=0.01, n=3000):
    """Points on a grid over the hills, normal errors of sigma_m and one point 1.4 km
    below the ground."""
    hf = w.sync.terrain.heightfield
    rng = np.random.default_rng(7)
    x = rng.uniform(-40, 40, n).round()
    y = rng.uniform(-40, 40, n).round()
    dz = rng.normal(0.0, sigma_m, n)
    dz[123] = -1400.0
    xyz = np.column_stack([x, y, hf.height_at(x, y) + dz])
    path = tmp_path / "cloud.ply"
    write_xyz_ply(path, xyz)
    return path, xyz


def activate(qtbot, w) -> None:
    """Keyboard focus needs the active window (Xvfb has no window manager to give it)."""
    w.activateWindow()
    w.raise_()
    qtbot.waitUntil(w.isActiveWindow)


def type_text(qtbot, w, box, text: str) -> None:
    """Click into the field, select all, type, Enter."""
    QTest.mouseClick(w.windowHandle(), Qt.MouseButton.LeftButton, Qt.KeyboardModifier.NoModifier,
                     box.mapTo(w, box.rect().center()))
    qtbot.waitUntil(box.hasFocus)
    box.selectAll()
    for ch in text:
        QTest.keyClick(w.windowHandle(), ch)
    QTest.keyClick(w.windowHandle(), Qt.Key.Key_Return)
    qtbot.wait(20)


#: renders the listed frames as blank pictures of the listed sizes, named as the images
FAKE_SIZED_RENDER = textwrap.dedent("""
    import json, sys
    from pathlib import Path
    import numpy as np, cv2
    out, frames = Path(sys.argv[1]), json.loads(Path(sys.argv[2]).read_text())
    (out / "images").mkdir(parents=True, exist_ok=True)
    print(json.dumps({"event": "worker_started", "worker": 0, "pid": 1,
                      "frames": [f["index"] for f in frames]}), flush=True)
    for f in frames:
        path = out / "images" / f["name"]
        cv2.imwrite(str(path), np.full((f["height"], f["width"], 3), 90, np.uint8))
        print(json.dumps({"event": "frame_done", "index": f["index"], "path": str(path),
                          "seconds": 0.01}), flush=True)
    print(json.dumps({"event": "worker_done"}), flush=True)
""")


def render_blank_frames(qtbot, window, monkeypatch, tmp_path, frames: list[dict]):
    """Press Render in the Render panel with the render command replaced by
    FAKE_SIZED_RENDER for ``frames`` ({"index", "name", "width", "height"} each); wait
    for it to finish and return the panel."""
    import json
    import sys

    from designer.gui.qt.command_process import RenderProcess

    (tmp_path / "frames.json").write_text(json.dumps(frames))
    script = tmp_path / "fake_render.py"
    script.write_text(FAKE_SIZED_RENDER)
    monkeypatch.setattr(RenderProcess, "command", staticmethod(
        lambda project, out_dir, resume=False, quality=None, workers=None:
        [sys.executable, str(script), str(out_dir), str(tmp_path / "frames.json")]))
    panel = open_panel(window, "Render")
    qtbot.mouseClick(panel.start_button, Qt.MouseButton.LeftButton)
    qtbot.waitUntil(lambda: panel.start_button.isEnabled(), timeout=60000)
    return panel


def choose_entry(qtbot, window, box, text: str) -> None:
    """Open the combo box ``box`` with the mouse and click the entry ``text`` in its list
    (scrolled to first, as a wheel would, when the list is longer than its popup)."""
    from PySide6.QtWidgets import QApplication

    QTest.mouseClick(window.windowHandle(), Qt.MouseButton.LeftButton,
                     Qt.KeyboardModifier.NoModifier, box.mapTo(window, box.rect().center()))
    view = box.view()
    qtbot.waitUntil(view.isVisible)
    # the list ignores a release within a double-click interval of its opening (the
    # release of the click that opened it)
    qtbot.wait(QApplication.doubleClickInterval() + 50)
    texts = [box.itemText(i) for i in range(box.count())]
    index = box.model().index(texts.index(text), 0)
    view.scrollTo(index)
    qtbot.mouseClick(view.viewport(), Qt.MouseButton.LeftButton,
                     pos=view.visualRect(index).center())
    qtbot.waitUntil(lambda: not view.isVisible())
