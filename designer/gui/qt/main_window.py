"""The designer window: the 3D view in the middle, dockable panels around it, menus,
undo/redo, the Problems list and a status bar with the ground coordinates under the
cursor (world coordinates: E, N, H with the project origin applied)."""

from __future__ import annotations

import itertools
from pathlib import Path

import numpy as np
from PySide6.QtCore import QSettings, Qt
from PySide6.QtGui import QAction, QKeySequence, QUndoStack
from PySide6.QtWidgets import (
    QDockWidget,
    QLabel,
    QListWidget,
    QMainWindow,
    QMessageBox,
    QWidget,
)

from designer.gui.qt.file_actions import FileActions
from designer.gui.qt.panels.buildings import BuildingsPanel
from designer.gui.qt.panels.camera import CameraPanel
from designer.gui.qt.panels.effects import EffectsPanel
from designer.gui.qt.panels.flight import FlightPanel
from designer.gui.qt.panels.gcps import GcpPanel
from designer.gui.qt.panels.lighting import LightingPanel
from designer.gui.qt.panels.moving import MovingObjectsPanel
from designer.gui.qt.panels.terrain import TerrainPanel
from designer.gui.qt.panels.texture import TexturePanel
from designer.gui.qt.panels.vegetation import VegetationPanel
from designer.gui.qt.scene_sync import SceneSync
from designer.gui.qt.scene_view import SceneView
from designer.gui.qt.site_flight_actions import SiteFlightActions
from designer.gui.qt.tasks import TaskRunner
from designer.gui.qt.undo import Editor
from designer.gui.state import files, wording
from designer.gui.state.document import ProjectDocument

LAYERS = [("terrain", "Terrain"), ("objects", "Scene objects"), ("buildings", "Buildings"),
          ("vegetation", "Plants"), ("movers", "Moving objects"), ("targets", "GCP targets"),
          ("frusta", "Camera frusta"), ("footprints", "Ground footprints"),
          ("flight", "Flight lines"),
          ("area", "Survey area"), ("cloud", "Point cloud"), ("residuals", "GCP errors")]


def _extra_panels():
    """Panels that are optional at import time (render needs no Qt extras; results uses
    matplotlib's Qt canvas)."""
    out = []
    from designer.gui.qt.panels.render import RenderPanel

    out.append(("right", RenderPanel))
    from designer.gui.qt.panels.processing import ProcessingPanel

    out.append(("right", ProcessingPanel))
    from designer.gui.qt.panels.results import ResultsPanel

    out.append(("right", ResultsPanel))
    from designer.gui.qt.panels.study import StudyPanel

    out.append(("right", StudyPanel))
    return out


#: the docks' widths at the start (px): the left one fits the GCP table's id, role, images
#: and true X, Y, Z (a typed height whole) beside the right dock; the 3D view takes the rest
#: (at 1600 px, about 650)
LEFT_DOCK_PX = 480
RIGHT_DOCK_PX = 460


class MainWindow(QMainWindow):
    def __init__(self, settings: QSettings | None = None) -> None:
        super().__init__()
        self.setWindowTitle("designer")
        self.resize(1600, 1000)
        self.settings = settings or QSettings("designer", "designer-gui")
        self.document = ProjectDocument(files.blank_project())
        self.undo_stack = QUndoStack(self)
        self.editor = Editor(self.document, self.undo_stack)
        self.tasks = TaskRunner(self)
        self.view = SceneView(self)
        self._build_centre()
        self.sync = SceneSync(self.document, self.view, self.tasks)
        self.file_actions = FileActions(self, self.settings)
        self.site_flight_actions = SiteFlightActions(self)

        self.panels: dict[str, QWidget] = {}
        self.docks: dict[str, QDockWidget] = {}
        left = [TerrainPanel, TexturePanel, LightingPanel, GcpPanel, MovingObjectsPanel,
                BuildingsPanel, VegetationPanel]
        right = [CameraPanel, FlightPanel, EffectsPanel]
        for side, cls in [("left", c) for c in left] + [("right", c) for c in right] + \
                _extra_panels():
            self._add_panel(cls, side)
        if "Render" in self.panels and "Results" in self.panels:
            # a finished render is something to reconstruct
            self.panels["Render"].process.finished.connect(
                lambda *_: self.panels["Results"].survey_readout())
        self._tabify(["Terrain", "Texture", "Lighting", "GCPs", "Moving objects", "Buildings",
                      "Vegetation"])
        self._tabify(["Camera", "Flight", "Effects", "Render", "Processing", "Results",
                      "Study"])
        self.docks["Terrain"].raise_()
        self.docks["Flight"].raise_()
        # tabs along the window's sides: every title whole, however many docks share an
        # area (below a 380 px dock, seven titles scrolled, one of them cut)
        from PySide6.QtWidgets import QTabWidget

        self.setTabPosition(Qt.DockWidgetArea.LeftDockWidgetArea, QTabWidget.TabPosition.West)
        self.setTabPosition(Qt.DockWidgetArea.RightDockWidgetArea, QTabWidget.TabPosition.East)
        self.resizeDocks([self.docks["Terrain"], self.docks["Flight"]],
                         [LEFT_DOCK_PX, RIGHT_DOCK_PX], Qt.Orientation.Horizontal)
        self._readable_tabs()
        for dock in self.docks.values():
            dock.dockLocationChanged.connect(self._readable_tabs_later)
        self._watch_outputs()
        self._build_problems()
        self._build_menus()
        self._build_status()

        self.document.events.connect("file", self._file_state)
        self.sync.message.connect(lambda text: self.statusBar().showMessage(text, 8000))
        # an error stays in the status bar while it holds: no timeout
        self.sync.error_message.connect(lambda text: self.statusBar().showMessage(text))
        self.sync.message_withdrawn.connect(self._withdraw_message)
        self.document.reset(self.document.project, None)
        from PySide6.QtWidgets import QApplication

        from designer.gui.qt.input_guard import InputGuard

        self.input_guard = InputGuard(self)
        QApplication.instance().installEventFilter(self.input_guard)

    # ------------------------------------------------------------------ layout
    def _build_centre(self) -> None:
        """The 3D view, and above it the bar that shows an exception no slot caught."""
        from PySide6.QtWidgets import QVBoxLayout

        from designer.gui.qt.uncaught import ErrorBar

        centre = QWidget(self)
        column = QVBoxLayout(centre)
        column.setContentsMargins(0, 0, 0, 0)
        column.setSpacing(0)
        self.error_bar = ErrorBar(centre)
        column.addWidget(self.error_bar)
        column.addWidget(self.view, 1)
        self.setCentralWidget(centre)
        self.error_bar.install()

    def _add_panel(self, cls, side: str) -> None:
        panel = cls(self.editor, self.sync, self)
        dock = QDockWidget(panel.title, self)
        dock.setObjectName(f"dock-{panel.title}")
        dock.setWidget(panel)
        dock.setMinimumWidth(380)
        area = (Qt.DockWidgetArea.LeftDockWidgetArea if side == "left"
                else Qt.DockWidgetArea.RightDockWidgetArea)
        self.addDockWidget(area, dock)
        self.panels[panel.title] = panel
        self.docks[panel.title] = dock

    def _watch_outputs(self) -> None:
        """Render and Results say when what they show no longer matches the project."""
        from designer.gui.qt.stale_watch import StaleWatch

        self.stale_watch = StaleWatch(self.document, self.tasks, self)
        render, results = self.panels.get("Render"), self.panels.get("Results")
        if render is None or results is None:
            return
        self.stale_watch.is_busy = lambda: render.process.running
        self.stale_watch.render_state.connect(render.show_render_state)
        self.stale_watch.render_state.connect(results.show_render_state)
        self.stale_watch.folder_changed.connect(render.forget_thumbnails)
        render.process.finished.connect(lambda *_: self.stale_watch.check_now())
        results.run.finished.connect(lambda *_: self.stale_watch.check_now())

    def _tabify(self, titles: list[str]) -> None:
        present = [t for t in titles if t in self.docks]
        for a, b in itertools.pairwise(present):
            self.tabifyDockWidget(self.docks[a], self.docks[b])

    def _readable_tabs(self) -> None:
        """Dock tabs show their whole titles ("Terrain", never "Te…"): no eliding, and
        scroll arrows when a group's tabs are wider than its docks."""
        from PySide6.QtWidgets import QTabBar

        for bar in self.findChildren(QTabBar):
            if bar.parent() is self:
                bar.setElideMode(Qt.TextElideMode.ElideNone)
                bar.setUsesScrollButtons(True)
                bar.setExpanding(False)

    def _readable_tabs_later(self, *_) -> None:
        """Qt makes a tab bar for docks tabified (or dragged) later: set it up too."""
        from PySide6.QtCore import QTimer

        QTimer.singleShot(0, self._readable_tabs)

    def _build_problems(self) -> None:
        self.problems = QListWidget()
        self.problems.setWordWrap(True)
        self.problems.itemActivated.connect(self._problem_clicked)
        self.problems.itemClicked.connect(self._problem_clicked)
        dock = QDockWidget("Problems", self)
        dock.setObjectName("dock-Problems")
        dock.setWidget(self.problems)
        self.addDockWidget(Qt.DockWidgetArea.BottomDockWidgetArea, dock)
        dock.hide()
        self.docks["Problems"] = dock
        from PySide6.QtCore import QTimer

        self._problems_timer = QTimer(self)
        self._problems_timer.setSingleShot(True)
        self._problems_timer.setInterval(300)
        self._problems_timer.timeout.connect(self._recheck_now)
        self.document.events.connect("project", self._recheck_problems)
        self._file_problems: list[str] = []
        # camera stations under the ground, judged over what is drawn as it is edited
        self.sync.problems_changed.connect(self._list_problems)

    def _withdraw_message(self, text: str) -> None:
        """An error's message leaves the status bar when the error goes (a later message
        about something else stays)."""
        if self.statusBar().currentMessage() == text:
            self.statusBar().clearMessage()

    def show_problems(self, lines: list[str], headline: str = "") -> None:
        """List problems inline (an empty list hides the Problems panel), each line as
        worded by :mod:`designer.gui.state.wording`; while listed they are checked again
        after every change, so fixed ones (also by an undo) go away. The headline of the
        problems listed before leaves the status bar with them ("Cannot open root.xml"
        does not outlast the next file opened)."""
        self._problems_project = self.document.project if lines else None
        self._file_problems = list(lines)
        self._list_problems()
        if not lines or headline:  # a check again without a headline keeps the old one
            self._withdraw_message(getattr(self, "_problems_headline", ""))
            self._problems_headline = headline if lines else ""
        if lines and headline:
            self.statusBar().showMessage(headline, 10000)

    def _list_problems(self) -> None:
        """The Problems list: the file's problems (:meth:`show_problems`), then those
        found over what is drawn (camera stations under the ground)."""
        lines = self._file_problems + self.sync.station_problems()
        self.problems.clear()
        self.problems.addItems(lines)
        self.docks["Problems"].setVisible(bool(lines))

    def _recheck_problems(self, **_) -> None:
        if getattr(self, "_problems_project", None) is None:
            return
        if self.document.project == self._problems_project:
            return
        self._problems_timer.start()

    def _recheck_now(self) -> None:
        if getattr(self, "_problems_project", None) is None:
            return
        doc = self.document
        path = doc.path or doc.base_dir / "untitled.xml"
        plan = files.plan_save(doc.project, path, doc.base_dir,
                               self.file_actions.scratch_files)
        self.show_problems(plan.problems)
        if not plan.problems and not self.sync.station_problems():
            self.statusBar().showMessage("no problems left", 5000)

    def _problem_clicked(self, item) -> None:
        title = files.panel_for_problem(item.text())
        if title in self.docks:
            self.docks[title].show()
            self.docks[title].raise_()

    def _build_menus(self) -> None:
        bar = self.menuBar()
        self.file_actions.build_menu(bar.addMenu("&File"))
        file_menu = bar.actions()[0].menu()
        file_menu.addSeparator()
        self.site_flight_actions.build_menu(file_menu)
        file_menu.addSeparator()
        file_menu.addAction(self._action("Save screens&hot…", None, self._screenshot_dialog))
        file_menu.addAction(self._action("&Quit", QKeySequence.StandardKey.Quit, self.close))

        edit = bar.addMenu("&Edit")
        undo = self.undo_stack.createUndoAction(self, "&Undo")
        undo.setShortcut(QKeySequence.StandardKey.Undo)
        redo = self.undo_stack.createRedoAction(self, "&Redo")
        redo.setShortcuts([QKeySequence.StandardKey.Redo, QKeySequence("Ctrl+Y")])
        for action in (undo, redo):  # also from a floating panel
            action.setShortcutContext(Qt.ShortcutContext.ApplicationShortcut)
        self.undo_action, self.redo_action = undo, redo
        edit.addActions([undo, redo])
        edit.addSeparator()
        mode = self.view.interaction.set_mode
        edit.addAction(self._action("&Navigate", "Esc", lambda: mode("navigate")))
        edit.addAction(self._action("&Place GCPs by clicking", "P", lambda: mode("place")))
        edit.addAction(self._action("Draw survey &area", "A", lambda: mode("area")))

        view = bar.addMenu("&View")
        view.addAction(self._action("&Reset view", "R", self.view.reset_view))
        view.addAction(self._action("&Top view", "T", self.view.view_top))
        view.addAction(self._action("&Frame all", "F", self.frame_all))
        view.addSeparator()
        for key, text in LAYERS:
            action = self._action(text, None, None)
            action.setCheckable(True)
            action.setChecked(True)
            action.toggled.connect(lambda on, k=key: self.view.set_layer_visible(k, on))
            view.addAction(action)
        coverage = self._action("Coverage &heat map", "H", None)
        coverage.setCheckable(True)
        coverage.toggled.connect(self.sync.set_coverage_enabled)
        view.addAction(coverage)
        self.coverage_action = coverage
        view.addSeparator()
        for dock in self.docks.values():
            view.addAction(dock.toggleViewAction())

        helpmenu = bar.addMenu("&Help")
        helpmenu.addAction(self._action("&Mouse and keys", "F1", self._help))

    def _action(self, text: str, shortcut, slot) -> QAction:
        action = QAction(text, self)
        if shortcut is not None:
            action.setShortcut(QKeySequence(shortcut) if isinstance(shortcut, str)
                               else shortcut)
        if slot is not None:
            action.triggered.connect(slot)
        return action

    def _build_status(self) -> None:
        self.coords = QLabel("")
        self.coords.setMinimumWidth(420)
        self.busy = QLabel("")
        self.statusBar().addPermanentWidget(self.busy)
        self.statusBar().addPermanentWidget(self.coords)
        self.view.ground_hovered.connect(self._hover)
        self.tasks.busy_changed.connect(lambda b: self.busy.setText("computing…" if b else ""))

    def _hover(self, xyz) -> None:
        if xyz is None:
            self.coords.setText("")
            return
        if len(xyz) == 0:
            self.coords.setText("off the terrain")
            return
        self.coords.setText(f"{wording.point_text(xyz)} (world)")

    def frame_all(self) -> None:
        """Fit the view to the terrain, the cameras and the GCPs."""
        points = [np.zeros((0, 3))]
        if self.sync.stations is not None:
            points.append(self.sync.stations.C_world)
        if self.sync.targets is not None:
            points.append(self.sync.targets.true_xyz)
        self.view.frame_all(np.vstack(points))

    def _file_state(self, path, dirty) -> None:
        """The title: the file, '*' when there are changes to save, and for a project
        never saved '(new, not saved)'."""
        doc = self.document
        name = doc.path.name if doc.path else "untitled.xml (new, not saved)"
        self.setWindowTitle(f"{name}[*] — {doc.project.name} — designer")
        self.setWindowModified(doc.changed)

    # ------------------------------------------------------------------ misc
    def _help(self) -> None:
        QMessageBox.information(self, "Mouse and keys", (
            "Left drag: turn · middle drag or Shift+left: pan · wheel or right drag: zoom\n"
            "P: place GCPs (click the terrain; drag a GCP to move it; Delete removes the "
            "selected rows)\nA: draw the survey area (click vertices, double-click to close)"
            "\nEsc: navigate · R: reset view · T: top view · H: coverage heat map\n"
            "Ctrl+Z / Ctrl+Shift+Z: undo / redo · Ctrl+S: save"))

    def _screenshot_dialog(self) -> None:
        from PySide6.QtWidgets import QFileDialog

        path, _ = QFileDialog.getSaveFileName(self, "Save screenshot", "designer.png",
                                              "PNG (*.png)")
        if path:
            self.save_screenshot(Path(path))

    def save_screenshot(self, path: Path, widget: QWidget | None = None) -> None:
        self.view.render_now()
        (widget or self).grab().save(str(path))

    def open_project(self, path: Path) -> bool:
        return self.file_actions.open(path)

    def close_without_prompt(self) -> None:
        """Close and drop unsaved changes (screenshots, benchmarks)."""
        self._discard = True
        self.close()

    def closeEvent(self, event) -> None:
        if not getattr(self, "_discard", False) and not self.file_actions.maybe_save():
            event.ignore()
            return
        for panel in self.panels.values():
            if hasattr(panel, "shutdown"):
                panel.shutdown()
        if hasattr(self, "stale_watch"):
            self.stale_watch.shutdown()
        self.tasks.shutdown()
        self.view.close_view()
        from PySide6.QtWidgets import QApplication

        QApplication.instance().removeEventFilter(self.input_guard)
        self.error_bar.uninstall()
        event.accept()
