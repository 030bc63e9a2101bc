"""Render: quality preset with its cost (measured here, or the reference figures until
then), workers, start/cancel, per-image progress and thumbnails. Rendering runs in
``designer render`` processes: the window never waits."""

from __future__ import annotations

from dataclasses import fields
from pathlib import Path

import shiboken6
from PySide6.QtCore import QSize, Qt, QTimer
from PySide6.QtGui import QIcon, QImage, QPixmap
from PySide6.QtWidgets import (
    QCheckBox,
    QGroupBox,
    QHBoxLayout,
    QLabel,
    QLineEdit,
    QListView,
    QListWidget,
    QListWidgetItem,
    QProgressBar,
    QPushButton,
)

from designer.core.layout import images_dir
from designer.gui.qt.boxes import follow_process, log_view
from designer.gui.qt.command_process import RenderProcess
from designer.gui.qt.field_rules import ruled_dspin
from designer.gui.qt.panels.base import Panel
from designer.gui.qt.panels.out_of_date import OutOfDate
from designer.gui.qt.widgets import combo, form, format_number, ispin, readout
from designer.gui.state import derived
from designer.gui.state.render_figures import preset_cost_lines, up_to_date_line
from designer.gui.state.wording import count, duration, estimate_basis
from designer.project import model as m
from designer.render.pipeline import ImagesKept, continue_hint
from designer.render_time.model import load_speed
from designer.render_time.timing import RenderTimes

THUMB_PX = 120
#: what the panel says when Render could not save the project
SAVE_FIRST = "save the project (without problems) before rendering"
#: decimals of the resolution scale field: enough for the halvings down to 1/16 (0.0625),
#: so every scale the panel offers is shown and typed as it is
SCALE_DECIMALS = 4
#: how the cancel text names the resume box and the action that continues
RESUME_OPTION = "'resume' ticked"
RERUN = "start the render"


def _from_event(cls, event: dict | None):
    """The dataclass ``cls`` from the fields an event carries (None without the event or
    when a field is missing)."""
    if event is None:
        return None
    try:
        return cls(**{f.name: event[f.name] for f in fields(cls)})
    except KeyError:
        return None


def _part_pixels(sizes: list[tuple[str, int]], scale: float) -> tuple[str, int, float] | None:
    """The first (name, size, scaled size) that ``scale`` makes no whole number of
    pixels (or less than one), None when every size scales to whole pixels."""
    for name, size in sizes:
        scaled = size * scale
        if abs(scaled - round(scaled)) > 1e-6 or round(scaled) < 1:
            return name, size, scaled
    return None


def scale_problem(cameras, scale: float) -> str:
    """Why ``scale`` cannot be the render's resolution scale for ``cameras`` ("" when it
    can): it must give whole pixels; names the nearest scale that does."""
    sizes = [(f"{label} of {c.id}", n) for c in cameras
             for label, n in (("width", c.image_width_px), ("height", c.image_height_px))]
    bad = _part_pixels(sizes, scale)
    if bad is None:
        return ""
    name, size, scaled = bad
    import numpy as np

    step = 10 ** -SCALE_DECIMALS
    # every scale of the field at once, as _part_pixels judges one
    scales = np.arange(1, 10 ** SCALE_DECIMALS + 1) * step
    scaled_all = scales[:, None] * np.array([n for _, n in sizes], dtype=float)[None, :]
    whole = np.round(scaled_all)
    ok = ((np.abs(scaled_all - whole) <= 1e-6) & (whole >= 1)).all(axis=1)
    valid = [float(v) for v in scales[ok]]
    nearest = min(valid, key=lambda v: (abs(v - scale), -v)) if valid else None
    hint = (f"; nearest scale giving whole pixels: {format_number(nearest, SCALE_DECIMALS)}"
            if nearest is not None else "")
    return (f"resolution scale {format_number(scale, SCALE_DECIMALS)}: the image {name} "
            f"{size} × {format_number(scale, SCALE_DECIMALS)} = {format_number(scaled, 3)} px "
            f"is not a whole number of pixels{hint}")


def thumb_size(width_px: int, height_px: int) -> QSize:
    """The picture of an image of this size in the thumbnail list: its shape, the
    longer side THUMB_PX."""
    w, h = max(1, int(width_px)), max(1, int(height_px))
    if w >= h:
        return QSize(THUMB_PX, max(1, round(THUMB_PX * h / w)))
    return QSize(max(1, round(THUMB_PX * w / h)), THUMB_PX)


def thumb_item(picture: QSize) -> QSize:
    """An item of the thumbnail list: the picture and, under it, two lines (the image's
    name and its render time)."""
    return QSize(THUMB_PX + 16, picture.height() + 40)


def _thumbnail(path: str) -> QImage:
    """Read and shrink an image (runs in a worker thread: QImage is not a widget)."""
    image = QImage(path)
    if image.isNull():
        return image
    return image.scaled(THUMB_PX, THUMB_PX, Qt.AspectRatioMode.KeepAspectRatio,
                        Qt.TransformationMode.SmoothTransformation)


class RenderPanel(Panel):
    title = "Render"
    parts = frozenset({"render", "cameras", "trajectory", "outputs"})

    def build(self, layout) -> None:
        settings = QGroupBox("quality")
        f = form(settings)
        self.preset = combo([(p, p) for p in m.PRESET_SAMPLES])
        f.addRow("preset", self.bindings.bind(self.preset, "render.preset", "Render preset"))
        self.cost = readout()
        self.cost.setWordWrap(True)
        f.addRow("cost", self.cost)  # its lines say whose figures they are
        # a scale giving part pixels is refused where it is typed (it would block the
        # render), with the nearest scale that gives whole pixels
        f.addRow("resolution scale", self.bindings.bind(
            ruled_dspin(self._scale_problem, 0.01, 1, SCALE_DECIMALS, 0.05),
            "render.resolution_scale", "Resolution scale"))
        f.addRow("workers", self.bindings.bind(ispin(1, 256), "render.workers",
                                               "Render workers"))
        f.addRow("image format", self.bindings.bind(
            combo([(x, x) for x in ("png", "jpeg", "tiff", "exr")]), "render.output_format",
            "Image format"))
        f.addRow("output folder", self.bindings.bind(QLineEdit(), "outputs.directory",
                                                     "Output folder"))
        layout.addWidget(settings)

        row = QHBoxLayout()
        self.start_button = QPushButton("Render")
        self.start_button.clicked.connect(self.start)
        self.cancel_button = QPushButton("Cancel")
        self.cancel_button.setEnabled(False)
        self.cancel_button.clicked.connect(self.cancel)
        self.resume = QCheckBox("resume")
        self.resume.setChecked(True)
        self.resume.setToolTip("keep images that are already complete")
        row.addWidget(self.start_button)
        row.addWidget(self.cancel_button)
        row.addWidget(self.resume)
        layout.addLayout(row)
        self.out_of_date = OutOfDate("render-out-of-date")
        layout.addWidget(self.out_of_date)
        self.progress = QProgressBar()
        layout.addWidget(self.progress)
        self.state = QLabel("")
        self.state.setWordWrap(True)
        layout.addWidget(self.state)
        self.thumbs = QListWidget()
        self.thumbs.setViewMode(QListView.ViewMode.IconMode)
        self.thumbs.setIconSize(thumb_size(4, 3))
        self.thumbs.setResizeMode(QListView.ResizeMode.Adjust)
        self.thumbs.setMinimumHeight(260)
        self.thumbs.setMovement(QListView.Movement.Static)
        self.thumbs.setUniformItemSizes(True)
        self.thumbs.setGridSize(thumb_item(self.thumbs.iconSize()))
        self.thumbs.setWordWrap(True)
        self.thumbs.setToolTip("click an image to select its photo (its station marked in "
                               "the 3D view, the cloud shadows drawn at its moment); "
                               "double-click it to open it with the GCPs it sees")
        layout.addWidget(self.thumbs)
        self.log = log_view(500, 120)
        layout.addWidget(self.log)

        self.process = RenderProcess(self)
        follow_process(self.process, self.log, self.on_event, self._finished)
        self.sync.stations_changed.connect(self._cost)
        self.frames_done: dict[int, float] = {}
        self.skipped: set[int] = set()
        #: images each the first a worker rendered (their time includes Cycles' set-up)
        self.first_of_worker: set[int] = set()
        self.image_names: list[str] = []
        self.n_frames = 0
        self.out_dir: Path | None = None
        self._watching_problems = False
        # the folder whose images the thumbnails show (a render's, or one found up to date)
        self._thumbs_dir: Path | None = None
        self.editor.document.events.connect("reset", lambda **_: self._project_replaced())
        self.thumbs.itemActivated.connect(self.open_image)
        self.thumbs.itemClicked.connect(self._select_photo)
        self.sync.photo_selected.connect(self._show_selected_photo)
        self.thumbs.itemDoubleClicked.connect(self.open_image)

    def _select_photo(self, item: QListWidgetItem) -> None:
        """A thumbnail clicked selects the photo of its image (designer.gui.qt.
        photo_selection); an image the current stations no longer have selects none."""
        index = item.data(Qt.ItemDataRole.UserRole)
        name = self.image_names[index] if index < len(self.image_names) else None
        k = self.sync.photo_of_image(name) if name is not None else None
        if k is None:
            self.sync.message.emit(f"{name or 'this image'}: not a photo of the flight as "
                                   "it is now (rendered before it changed)")
            return
        self.sync.select_photo(k)

    def _show_selected_photo(self, station: int | None) -> None:
        """The selected photo's thumbnail (the first of a rig station's) made current
        and scrolled to; none selected, or not among the thumbnails: none current."""
        for i in range(self.thumbs.count()):
            item = self.thumbs.item(i)
            index = item.data(Qt.ItemDataRole.UserRole)
            if (station is not None and index < len(self.image_names)
                    and self.sync.photo_of_image(self.image_names[index]) == station):
                self.thumbs.setCurrentItem(item)
                self.thumbs.scrollToItem(item)
                return
        self.thumbs.setCurrentItem(None)

    def _scale_problem(self, scale: float) -> str:
        return scale_problem(self.project.cameras, scale)

    # ------------------------------------------------------------------ readouts
    def refresh(self) -> None:
        super().refresh()
        self._cost()

    def _cost(self) -> None:
        stations = self.sync.stations
        if stations is None:
            self.cost.setText("– (no stations yet)")
            return
        n = len(stations.render_costs)
        lines = preset_cost_lines({
            preset: (spp, derived.render_estimate(self.project, stations.render_costs, preset))
            for preset, spp in m.PRESET_SAMPLES.items()})
        # the records of this project's kind of image (the first image's), as the figures
        speed = load_speed(stations.render_costs[0] if n else None)
        self.cost.setText("\n".join(lines) + f"\n({estimate_basis(speed)})")

    def show_render_state(self, state) -> None:
        """The render folder against the project (``output_state.RenderState`` or None):
        the out-of-date line, and a button that re-renders only what changed. A state
        checked before a render that is still running is old news: not shown."""
        if state is None or self.process.running:
            self.out_of_date.show_state(None)
            self.start_button.setText("Render")
            return
        self.out_of_date.show_state(
            None if state.ok else state.text,
            up_to_date_line(state.n_images),
            says_it=bool(state.stale))  # "12 images out of date: …", said once
        if state.n_images:
            self._show_rendered()
        redo = len(state.stale) + len(state.missing)
        self.start_button.setText(f"Re-render {redo} changed image{'s' if redo != 1 else ''}"
                                  if not state.ok and redo else "Render")
        self.start_button.setToolTip("keeps the images that are up to date (resume) and "
                                     "renders the others" if redo else "")

    def _project_replaced(self) -> None:
        """Another project was opened (or a new one made): the thumbnails were of the one
        before (a render that runs keeps its own)."""
        if not self.process.running:
            self.thumbs.clear()
            self._thumbs_dir = None

    def forget_thumbnails(self) -> None:
        """The output folder changed on disk (a render by the command): the thumbnails
        shown from it are read again with its next state (a render that runs here keeps
        its own)."""
        if not self.process.running and self._thumbs_dir is not None:
            self._thumbs_dir = None

    def _show_rendered(self) -> None:
        """The thumbnails of the images in the project's output folder, when the list
        shows no other images of that folder (e.g. a project opened with its render)."""
        doc = self.editor.document
        stations = self.sync.stations
        if doc.path is None or stations is None:
            return
        out_dir = (doc.path.parent / self.project.outputs.directory).resolve()
        if self._thumbs_dir == out_dir and self.thumbs.count():
            return
        self.out_dir = out_dir
        self.image_names = list(stations.image_names)
        self.thumbs.clear()
        self._thumbs_dir = out_dir
        self._thumb_shape(thumb_size(*derived.rendered_size_px(
            stations.interior, self.project.render.resolution_scale)))
        for index in range(len(self.image_names)):
            path = self._image_path(index)
            if path is not None:
                self._add_thumbnail(index, path, 0.0, "(rendered before)")

    def settings(self):
        window = self.window()
        return getattr(window, "settings", None)

    # ------------------------------------------------------------------ run
    def start(self) -> None:
        doc = self.editor.document
        window = self.window()
        refused = _refused_field(window)
        if refused:
            # the project still has the field's old value: a render would quietly use it
            self.state.setText(f"not rendered: a field refused what was typed: {refused}")
            return
        if doc.dirty or doc.path is None:
            if not hasattr(window, "file_actions") or not window.file_actions.save():
                self._refuse_start()
                return
        project_path = doc.path
        self.out_dir = (project_path.parent / self.project.outputs.directory).resolve()
        self.frames_done = {}
        self.skipped: set[int] = set()
        self.first_of_worker = set()
        self.n_frames = self.sync.stations.n_images if self.sync.stations else 0
        self.image_names = list(self.sync.stations.image_names) if self.sync.stations else []
        self.progress.setRange(0, max(1, self.n_frames))
        self.progress.setValue(0)
        self.thumbs.clear()
        self._thumbs_dir = self.out_dir
        if self.sync.stations is not None:  # the rendered images' shape, until one is read
            self._thumb_shape(thumb_size(*derived.rendered_size_px(
                self.sync.stations.interior, self.project.render.resolution_scale)))
        self.log.clear()
        # the command's own account of the run: what a stop kept, how long it took
        self.interrupted: dict | None = None
        self.finished_event: dict | None = None
        # re-rendering what changed is a resume: up-to-date images are kept
        resume = self.resume.isChecked() or self.out_of_date.stale
        argv = RenderProcess.command(project_path, self.out_dir, resume=resume)
        self.process.start(argv, cwd=project_path.parent)
        # the folder is being brought up to date: what it lacked before is no news now;
        # the check after the render says how it is then
        self.show_render_state(None)
        self.start_button.setEnabled(False)
        self.cancel_button.setEnabled(True)
        self.state.setText(f"rendering into {self.out_dir} …")

    def _refuse_start(self) -> None:
        """Say why nothing renders, until the project is saved or its problems fixed."""
        self.state.setText(SAVE_FIRST)
        problems = getattr(self.window(), "problems", None)
        if problems is not None and not self._watching_problems:
            self._watching_problems = True
            problems.model().modelReset.connect(self._problems_relisted)
            self.editor.document.events.connect("file", self._file_changed)

    def _problems_relisted(self) -> None:
        # the list is cleared and refilled in one go: look once it is refilled
        QTimer.singleShot(0, self, self._check_refusal)

    def _file_changed(self, **_) -> None:
        self._check_refusal()

    def _check_refusal(self) -> None:
        if not shiboken6.isValid(self.state) or self.state.text() != SAVE_FIRST:
            return
        doc = self.editor.document
        problems = getattr(self.window(), "problems", None)
        if not doc.dirty and doc.path is not None:
            self.state.setText("saved: ready to render")
        elif problems is not None and problems.count() == 0:
            self.state.setText("no problems left: Render saves the project and renders it")

    def cancel(self) -> None:
        self.process.cancel()
        self.state.setText("stopping: workers finish cleanly, only complete images stay")

    def on_event(self, event: dict) -> None:
        kind = event.get("event")
        if kind == "worker_started":
            self.log.appendPlainText(f"worker {event.get('worker')} started "
                                     f"({len(event.get('frames', []))} frames)")
        elif kind == "scene_ready":
            self.log.appendPlainText(f"scene ready in {float(event.get('seconds', 0)):.1f} s")
        elif kind in ("frame_done", "frame_skipped"):
            index = int(event["index"])
            if kind == "frame_skipped":
                self.skipped.add(index)
                self.frames_done[index] = 0.0
                self._add_thumbnail(index, self._image_path(index), 0.0)
            else:
                self.frames_done[index] = float(event.get("seconds", 0.0))
                if event.get("order") == 0:
                    self.first_of_worker.add(index)
                self._add_thumbnail(index, event.get("path") or self._image_path(index),
                                    self.frames_done[index])
            self.progress.setValue(len(self.frames_done))
            self.state.setText(self._count_text())
        elif kind == "retry":
            self.log.appendPlainText(f"retrying frames {event.get('frames')}")
        elif kind == "interrupted":
            self.interrupted = event
        elif kind == "finished":
            self.finished_event = event

    @property
    def n_rendered(self) -> int:
        return len(self.frames_done) - len(self.skipped)

    def _count_text(self) -> str:
        """Images done of the total, those kept from before, the measured speed."""
        rendered = [s for i, s in self.frames_done.items() if i not in self.skipped]
        later = [s for i, s in self.frames_done.items()
                 if i not in self.skipped and i not in self.first_of_worker]
        kept = f" ({len(self.skipped)} complete before, kept)" if self.skipped else ""
        # a worker's first image also waits for Cycles to build its copy of the scene:
        # the speed is measured on the images after it once there are any
        speed = (f"{duration(sum(later) / len(later))} per image measured after each "
                 "worker's first" if later else
                 f"{duration(sum(rendered) / len(rendered))} per image measured (with "
                 "Cycles' set-up)" if rendered else "no image rendered yet")
        return f"{len(self.frames_done)} / {count(self.n_frames, 'image')}{kept}; {speed}"

    def _image_path(self, index: int) -> str | None:
        """The rendered image of station ``index`` in the output folder (or None)."""
        if self.out_dir is None or index >= len(self.image_names):
            return None
        folder = images_dir(self.out_dir)
        path = folder / self.image_names[index]
        if path.is_file():
            return str(path)
        found = sorted(folder.glob(Path(self.image_names[index]).stem + ".*"))
        return str(found[0]) if found else None

    def _add_thumbnail(self, index: int, path: str | None, seconds: float,
                       note: str = "(kept)") -> None:
        name = (Path(self.image_names[index]).stem if index < len(self.image_names)
                else f"#{index}")
        first = index in self.first_of_worker
        label = name + (f"\n{seconds:.1f} s" + (" with set-up" if first else "")
                        if seconds else f"\n{note}")
        item = QListWidgetItem(label)
        # the item's size is fixed, not measured: the thumbnail is read in a thread and
        # arrives after the list laid the item out (measured then, the item would be
        # the size of its text and the picture squeezed into it, the name cut off)
        item.setSizeHint(self.thumbs.gridSize())
        item.setData(Qt.ItemDataRole.UserRole, index)
        item.setData(Qt.ItemDataRole.UserRole + 1, path)
        item.setToolTip((path or "") + (
            "\nthe first image of its worker: its time includes Cycles building the scene"
            if first else ""))
        self.thumbs.addItem(item)
        if path is None:
            return

        def show(image: QImage) -> None:
            if not image.isNull():
                self._thumb_shape(image.size())
                item.setIcon(QIcon(QPixmap.fromImage(image)))

        self.sync.tasks.submit(f"thumb-{index}", _thumbnail, path, on_done=show,
                               on_error=lambda _e: None)

    def _thumb_shape(self, picture: QSize) -> None:
        """Lay the thumbnails out for pictures of this size (the images' shape)."""
        if picture == self.thumbs.iconSize():
            return
        self.thumbs.setIconSize(picture)
        self.thumbs.setGridSize(thumb_item(picture))
        for i in range(self.thumbs.count()):
            self.thumbs.item(i).setSizeHint(thumb_item(picture))

    def _finished(self, code: int, stderr_tail: str) -> None:
        self.start_button.setEnabled(True)
        self.cancel_button.setEnabled(False)
        n = self.n_rendered
        kept = f", {len(self.skipped)} complete before (kept)" if self.skipped else ""
        if n:  # the render refined this machine's speed: every estimate uses it now
            self._cost()
            self.sync.stations_changed.emit()
        if code == 0:
            # the command's timing, the same seconds its last line in the log gives
            times = _from_event(RenderTimes, getattr(self, "finished_event", None))
            took = f" {times.text()}" if times is not None else ""
            self.state.setText(f"done: {count(n, 'image')} rendered{took}{kept} into "
                               f"{self.out_dir / 'images'}; ground truth in "
                               f"{self.out_dir / 'ground-truth'}; README.txt says which "
                               "file each program takes")
        elif code == 130 or self.process.cancelled:
            self.state.setText(self._cancel_text(n))
        else:
            lines = [line for line in stderr_tail.splitlines() if line.strip()]
            why = lines[-1].strip() if lines else "it gave no reason; the log below has its output"
            self.state.setText(f"render failed (exit {code}): {why}")

    def _cancel_text(self, n: int) -> str:
        """What a stopped render kept (the command counts it against the project: up to
        date, out of date, not rendered) and how to continue, given the resume box."""
        resume = self.resume.isChecked()
        images = _from_event(ImagesKept, getattr(self, "interrupted", None))
        if images is not None:
            return "cancelled: " + images.text(resume, resume_option=RESUME_OPTION,
                                               rerun=RERUN)
        # stopped before the command could count (e.g. while the scene was prepared)
        if n == 0:  # nothing finished: there is no "rest", the whole render is to do
            return "cancelled before this run finished an image; start the render again"
        return (f"cancelled after {count(n, 'image')}; "
                + continue_hint(resume, resume_option=RESUME_OPTION, rerun=RERUN))

    def open_image(self, item) -> None:
        """The full image with the GCP observations drawn on it, in a window."""
        from designer.gui.qt.image_viewer import ImageViewer

        path = item.data(Qt.ItemDataRole.UserRole + 1)
        index = int(item.data(Qt.ItemDataRole.UserRole))
        if not path:
            return
        from designer.gui.state.image_marks import exported_marks

        # the render's own GCP points for this image (buildings, rolling shutter), else
        # the GCPs projected with the plan's pose of it
        observations = exported_marks(path)
        if observations is None:
            plan = self.sync.plan
            observations = plan.observations(index) if plan is not None else []
        self.viewer = ImageViewer(path, observations, self)
        self.viewer.show()

    def shutdown(self) -> None:
        if self.process.running:
            self.process.cancel()
            if not self.process.process.waitForFinished(15000):
                self.process.kill()


def _refused_field(window) -> str:
    """The first refusal a panel of ``window`` shows for a field ("" when none does);
    it names the field and the way back (Esc)."""
    for panel in getattr(window, "panels", {}).values():
        for message in getattr(panel, "input_errors", {}).values():
            return message
    return ""
