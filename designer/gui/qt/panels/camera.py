"""Camera: presets of real cameras, interior orientation and distortion, derived FOV/GSD."""

from __future__ import annotations

import dataclasses

from PySide6.QtWidgets import QGroupBox, QLineEdit

from designer.errors import DesignerError
from designer.gui.qt.boxes import readouts, wrapped_label
from designer.gui.qt.panels.base import ERROR_STYLE, Panel
from designer.gui.qt.widgets import (
    INVALID_STYLE,
    combo,
    declared_field,
    form,
    model_getter,
    readout,
)
from designer.gui.state import camera_presets, edits
from designer.gui.state.edits import AbsentElement, get_path
from designer.project import model as m
from designer.project.declare import declared_field as declared

CAM = "cameras[0]"
BROWN = ("k1", "k2", "k3", "p1", "p2")
FISHEYE = ("k1", "k2", "k3", "k4")
ID_TIP = ("the name the flight plan, the photos and the rigs use for this camera; a new id "
          "renames it there too")


def camera_id_problem(project: m.Project, new_id: str, index: int = 0) -> str:
    """Why ``new_id`` cannot be camera ``index``'s id ("" when it can)."""
    if not new_id:
        return ("Camera id: an id is required (the flight, the photos and the rigs name "
                "their camera by it); not applied")
    problem = edits.identifier_problem(new_id)
    if problem:
        return f"Camera id: {problem}; not applied"
    others = {c.id for k, c in enumerate(project.cameras) if k != index}
    if new_id in others:
        return f"Camera id: another camera is called “{new_id}”; not applied"
    if new_id in {r.name for r in project.trajectory.rigs}:
        return f"Camera id: a rig is called “{new_id}”; not applied"
    return ""


def _pixel_aspect():
    """The pixel aspect (pixel height / width; the file's limits); its lowest step, 0,
    shows "square (from the sizes)": the file states none, the sensor and image sizes
    must then give square pixels."""
    box = declared_field(m.Camera, "pixel_aspect")
    box.setMinimum(0.0)
    box.setSpecialValueText("square (from the sizes)")
    return box


class CameraPanel(Panel):
    title = "Camera"
    parts = frozenset({"cameras", "trajectory"})

    def build(self, layout) -> None:
        top = form()
        self.preset = combo([("custom", None)]
                            + [(p.name, p.key) for p in camera_presets.PRESETS])
        self.preset.currentIndexChanged.connect(self._preset_chosen)
        top.addRow("preset", self.preset)
        self.id_field = self.bindings.bind(_line(), (model_getter(f"{CAM}.id"), self._set_id),
                                           "Camera id")
        self.id_field.setObjectName(f"{CAM}.id")
        self.id_field.setToolTip(ID_TIP)
        top.addRow("id", self.id_field)
        top.addRow("name", self.bindings.bind(_line(), (
            model_getter(f"{CAM}.name", lambda v: v or ""),
            lambda p, v: edits.replace_path(p, f"{CAM}.name", v or None)), "Camera name"))
        layout.addLayout(top)

        io = QGroupBox("interior orientation")
        f = form(io)
        for field in ("focal_length_mm", "sensor_width_mm", "sensor_height_mm",
                      "image_width_px", "image_height_px", "principal_point_x_mm",
                      "principal_point_y_mm"):
            label = declared(m.Camera, field).label
            f.addRow(label, self.bindings.bind(declared_field(m.Camera, field), f"{CAM}.{field}",
                                               f"Camera {label}"))
        aspect = self.bindings.bind(_pixel_aspect(), (
            model_getter(f"{CAM}.pixel_aspect", lambda v: v or 0.0),
            lambda p, v: edits.replace_path(p, f"{CAM}.pixel_aspect", v or None)),
            "Camera pixel aspect")
        aspect.setObjectName(f"{CAM}.pixel_aspect")
        f.addRow(declared(m.Camera, "pixel_aspect").label, aspect)
        layout.addWidget(io)

        dist = QGroupBox("lens distortion (OpenCV's meaning and order)")
        f = form(dist)
        self.model = combo([("none (pinhole)", "none"), ("Brown–Conrady", "brown"),
                            ("fisheye, equidistant", "fisheye")])
        self.model.currentIndexChanged.connect(self._model_chosen)
        f.addRow("model", self.model)
        self.coeffs: dict[str, object] = {}
        for name in BROWN + ("k4",):
            # the file's limits (k4 is the fisheye's; the others are declared alike)
            box = declared_field(m.FisheyeEquidistantDistortion if name == "k4"
                                 else m.BrownConradyDistortion, name)
            self.bindings.bind(box, (
                model_getter(f"{CAM}.distortion.{name}"),
                lambda p, v, n=name: edits.replace_path(p, f"{CAM}.distortion.{n}", v)),
                f"Distortion {name}")
            self.coeffs[name] = box
            f.addRow(name, box)
        self._dist_form = f
        layout.addWidget(dist)

        shutter = QGroupBox("rolling shutter (0 s: a global shutter)")
        f = form(shutter)
        f.addRow("readout", self.bindings.bind(declared_field(m.RollingShutter, "readout_s"), (
            model_getter(f"{CAM}.rolling_shutter", lambda rs: rs.readout_s if rs else 0.0),
            _set_readout), "Rolling-shutter readout"))
        f.addRow("first row", self.bindings.bind(combo([
            ("top (top to bottom)", "top-to-bottom"),
            ("bottom (bottom to top)", "bottom-to-top")]), (
            model_getter(f"{CAM}.rolling_shutter", _direction),
            lambda p, v: edits.replace_path(p, f"{CAM}.rolling_shutter.direction", v)),
            "Rolling-shutter direction"))
        self.shutter_label = readout()
        f.addRow("during readout", self.shutter_label)
        layout.addWidget(shutter)

        self.pitch_label, self.fov_label, self.gsd_label = readouts(
            layout, "pixel pitch", "field of view", "GSD")
        self.error_label = wrapped_label(ERROR_STYLE)
        layout.addWidget(self.error_label)
        self.sync.stations_changed.connect(self._readouts)

    # ------------------------------------------------------------------ model → view
    def refresh(self) -> None:
        project = self.project
        super().refresh()
        self._id_verdict("")  # the field shows the project's id again
        cam = project.cameras[0] if project.cameras else None
        match = camera_presets.matching_preset(cam) if cam else None
        _select(self.preset, match.key if match else None)
        d = cam.distortion if cam else None
        kind = ("brown" if isinstance(d, m.BrownConradyDistortion) else
                "fisheye" if isinstance(d, m.FisheyeEquidistantDistortion) else "none")
        _select(self.model, kind)
        names = BROWN if kind == "brown" else FISHEYE if kind == "fisheye" else ()
        for name, box in self.coeffs.items():
            self._dist_form.setRowVisible(box, name in names)
        self._readouts()

    def _readouts(self) -> None:
        from designer.project.interiors import interior_from_camera

        project = self.project
        if not project.cameras:
            return
        cam = project.cameras[0]
        try:
            interior = interior_from_camera(cam)
        except DesignerError as error:
            self.error_label.setText(str(error))
            for label in (self.pitch_label, self.fov_label, self.gsd_label):
                label.setText("–")
            return
        self.error_label.setText("")
        px, py = interior.pixel_pitch_x_mm, interior.pixel_pitch_y_mm
        self.pitch_label.setText(f"{1000 * px:.4f} × {1000 * py:.4f} µm "
                                 f"({interior.image_width_px * interior.image_height_px / 1e6:.1f}"
                                 " MP)")
        h, v, diag = interior.field_of_view_deg()
        self.fov_label.setText(f"{h:.1f}° × {v:.1f}° (diagonal {diag:.1f}°)")
        stations = self.sync.stations
        if stations is not None and stations.calc is not None:
            c = stations.calc
            self.gsd_label.setText(
                f"{100 * c.gsd_m:.2f} cm at {c.altitude_agl_m:.1f} m above ground; footprint "
                f"{c.footprint_across_m:.1f} × {c.footprint_along_m:.1f} m")
        else:
            gsd = 100 * 100 * px / cam.focal_length_mm
            self.gsd_label.setText(f"{gsd:.2f} cm at 100 m")
        self.shutter_label.setText(self._shutter_text(cam))

    def _shutter_text(self, cam: m.Camera) -> str:
        """How far the ground moves in the image while the rows are read."""
        if cam.readout_s == 0:
            return "global shutter"
        tl = self.project.trajectory.time_line
        if tl is None:
            return "needs the flight's time line (Flight panel)"
        stations = self.sync.stations
        motion_m = tl.speed_m_s * cam.readout_s
        if stations is not None and stations.calc is not None:
            return (f"{100 * motion_m:.1f} cm flown, {motion_m / stations.calc.gsd_m:.1f} px "
                    "between the first and the last row")
        return f"{100 * motion_m:.1f} cm flown"

    # ------------------------------------------------------------------ view → model
    def _set_id(self, project: m.Project, new_id: str) -> m.Project:
        """A new id renames the camera everywhere it is used; an id that is empty or not
        an id is refused (the field keeps the text, red, and says why)."""
        new_id = new_id.strip()
        if not project.cameras:
            return project
        problem = camera_id_problem(project, new_id)
        self._id_verdict(problem)
        if problem:
            return project
        return edits.set_camera(project, dataclasses.replace(project.cameras[0], id=new_id))

    def _id_verdict(self, message: str) -> None:
        box = self.id_field
        if message == self.input_errors.get(box, ""):
            return
        box.setProperty("invalid", bool(message))
        box.setStyleSheet(INVALID_STYLE if message else "")
        box.setToolTip(message or ID_TIP)
        self._field_verdict(box, message)

    def _preset_chosen(self) -> None:
        key = self.preset.currentData()
        if key is None:
            return
        p = camera_presets.preset(key)
        current = self.project.cameras[0].id if self.project.cameras else None
        preset_keys = {q.key for q in camera_presets.PRESETS}
        # an id that only named the previous preset follows the new one; a user's own
        # id stays
        cam_id = p.key if current is None or current in preset_keys else current
        self.editor.edit(edits.set_camera(self.project, p.camera(cam_id)), f"Camera {p.name}")

    def _model_chosen(self) -> None:
        kind = self.model.currentData()
        distortion = {"none": None, "brown": m.BrownConradyDistortion(),
                      "fisheye": m.FisheyeEquidistantDistortion()}[kind]
        cam = self.project.cameras[0]
        if type(cam.distortion) is type(distortion):
            return
        self.editor.edit(edits.set_camera(self.project,
                                          dataclasses.replace(cam, distortion=distortion)),
                         f"Distortion {kind}")


def _set_readout(project: m.Project, readout_s: float) -> m.Project:
    """Readout 0 removes the rolling shutter (a global shutter); another keeps its
    direction."""
    rs = get_path(project, f"{CAM}.rolling_shutter")
    new = None if readout_s == 0 else m.RollingShutter(
        readout_s, rs.direction if rs is not None else "top-to-bottom")
    return edits.replace_path(project, f"{CAM}.rolling_shutter", new)


def _direction(rs: m.RollingShutter | None) -> str:
    if rs is None:  # a global shutter reads no rows: the field is off
        raise AbsentElement(f"{CAM}.rolling_shutter.direction", "rolling_shutter", None)
    return rs.direction


def _line() -> QLineEdit:
    return QLineEdit()


def _select(box, data) -> None:
    blocked = box.blockSignals(True)
    index = box.findData(data)
    box.setCurrentIndex(index if index >= 0 else 0)
    box.blockSignals(blocked)
