"""Moving objects: cars and people driving or walking across the site during the flight,
posed at each photo's time (docs/world.md, Moving objects). New objects cross the
terrain from west to east through its centre; their path points are edited in the
project file, their shape, speed, start and looping here, every edit on the undo stack."""

from __future__ import annotations

import dataclasses

from PySide6.QtWidgets import QCheckBox, QGroupBox, QLabel

from designer.gui.qt.boxes import chosen_index, item_chooser, refill_chooser
from designer.gui.qt.panels.base import ERROR_STYLE, Panel
from designer.gui.qt.widgets import combo, declared_field, form, readout
from designer.gui.state.edits import AbsentElement
from designer.project import model as m

#: the walking and driving speeds new objects get (m/s)
NEW_SPEED_M_S = {"car": 8.0, "person": 1.4}


class MovingObjectsPanel(Panel):
    title = "Moving objects"
    parts = frozenset({"objects", "trajectory"})

    def build(self, layout) -> None:
        self.chooser, (self.add_car, self.add_person), self.remove = item_chooser(
            layout, "moving-object", self._show_selected,
            [("add a car", lambda: self._add("car")),
             ("add a person", lambda: self._add("person"))], self._remove)

        self.selected = QGroupBox("selected object")
        f = form(self.selected)
        self.shape = combo([("car (4.5 × 1.8 × 1.5 m)", "car"),
                            ("person (0.5 × 1.75 m)", "person")])
        f.addRow("shape", self.bindings.bind(self.shape, self._access("shape"),
                                             "Moving object shape"))
        f.addRow("speed", self.bindings.bind(declared_field(m.MovingObject, "speed_m_s"),
                                             self._access("speed_m_s"),
                                             "Moving object speed"))
        f.addRow("starts at", self.bindings.bind(declared_field(m.MovingObject, "start_s"),
                                                 self._access("start_s"),
                                                 "Moving object start"))
        self.loop = QCheckBox("go round the path again")
        f.addRow("", self.bindings.bind(self.loop, self._access("loop"), "Moving object loop"))
        self.path_label = readout()
        f.addRow("path", self.path_label)
        layout.addWidget(self.selected)
        self.warning = QLabel()
        self.warning.setWordWrap(True)
        self.warning.setStyleSheet(ERROR_STYLE)
        layout.addWidget(self.warning)
        self.sync.stations_changed.connect(self._warn)

    # ------------------------------------------------------------------ access
    def _index(self) -> int:
        """The chosen object; the first when none is chosen yet."""
        return chosen_index(self.chooser)

    def _access(self, name: str):
        def get(p: m.Project):
            k = self._index()
            if not 0 <= k < len(p.scene.moving_objects):
                raise AbsentElement(f"scene.moving_objects[{k}].{name}", name, None)
            return getattr(p.scene.moving_objects[k], name)

        def put(p: m.Project, value):
            k = self._index()
            if not 0 <= k < len(p.scene.moving_objects):
                raise AbsentElement(f"scene.moving_objects[{k}].{name}", name, None)
            objects = list(p.scene.moving_objects)
            objects[k] = dataclasses.replace(objects[k], **{name: value})
            return dataclasses.replace(p, scene=dataclasses.replace(
                p.scene, moving_objects=tuple(objects)))

        return get, put

    # ------------------------------------------------------------------ model → view
    def refresh(self) -> None:
        refill_chooser(self.chooser, [(f"{obj.id} ({obj.shape or obj.file})", obj.id)
                                      for obj in self.project.scene.moving_objects])
        self._show_selected()
        self._warn()

    def _warn(self) -> None:
        objects = self.project.scene.moving_objects
        if objects and self.project.trajectory.time_line is None:
            self.warning.setText(
                "the moving objects need a time line: switch it on in the Flight panel")
            return
        last = self._last_photo_s()
        late = [o for o in objects if last is not None and o.start_s > last]
        self.warning.setText("\n".join(
            f"{o.id} starts at {o.start_s:g} s, after the last photo (at {last:.0f} s): it "
            "stands at the start of its path in every photo" for o in late))

    def _last_photo_s(self) -> float | None:
        """Seconds after take-off of the flight's last photo; None when unknown."""
        from designer.errors import DesignerError
        from designer.survey.timeline import project_station_times

        stations = self.sync.stations
        if stations is None or not stations.stations:
            return None
        try:
            times = project_station_times(self.project, stations.stations)
        except DesignerError:
            return None
        return max(t.time_s for t in times) if times else None

    def _show_selected(self) -> None:
        super().refresh()
        objects = self.project.scene.moving_objects
        k = self._index()
        self.remove.setEnabled(bool(objects))
        if 0 <= k < len(objects):
            obj = objects[k]
            self.shape.setEnabled(obj.shape in ("car", "person"))
            points = ", ".join(f"({p.X:.1f}, {p.Y:.1f})" for p in obj.path[:3])
            more = f" … {len(obj.path)} points" if len(obj.path) > 3 else ""
            self.path_label.setText(points + more)
        else:
            self.path_label.setText("–")

    # ------------------------------------------------------------------ view → model
    def _add(self, shape: str) -> None:
        p = self.project
        e = p.scene.terrain.extent
        y = (e.min_Y + e.max_Y) / 2
        ids = {o.id for o in p.scene.moving_objects}
        n = 1 + sum(1 for o in p.scene.moving_objects if o.shape == shape)
        while f"{shape}{n}" in ids:
            n += 1
        obj = m.MovingObject(f"{shape}{n}", (m.PathPoint(e.min_X, y), m.PathPoint(e.max_X, y)),
                             NEW_SPEED_M_S[shape], shape=shape)
        self.editor.edit(dataclasses.replace(p, scene=dataclasses.replace(
            p.scene, moving_objects=(*p.scene.moving_objects, obj))),
            f"Add moving {shape} {obj.id}")
        self.chooser.setCurrentIndex(self.chooser.count() - 1)

    def _remove(self) -> None:
        p, k = self.project, self._index()
        objects = list(p.scene.moving_objects)
        if not 0 <= k < len(objects):
            return
        gone = objects.pop(k)
        self.editor.edit(dataclasses.replace(p, scene=dataclasses.replace(
            p.scene, moving_objects=tuple(objects))), f"Remove moving object {gone.id}")
