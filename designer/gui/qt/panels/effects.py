"""Effects: each image effect switched on or off, its parameters in physical units.

Lens distortion is part of the camera (Camera panel), not an effect.
"""

from __future__ import annotations

import dataclasses

from PySide6.QtWidgets import QCheckBox, QDoubleSpinBox, QGroupBox

from designer.gui.qt.panels.base import Panel
from designer.gui.qt.widgets import declared_field, form, model_getter, readout
from designer.gui.state import edits
from designer.project import declare
from designer.project import model as m


def _object_distance() -> QDoubleSpinBox:
    box = declared_field(m.Defocus, "object_distance_m")
    box.setMinimum(0.0)  # 0 shows the special text: each image's own distance
    box.setSpecialValueText("each image's distance to the ground")
    # what switching defocus on gives (no distance of its own), shown greyed while it is
    # off, not the field's former minimum
    box.setValue(0.0)
    box.switched_on_value = 0.0
    return box


def _widget(cls: type, d: declare.Declared):
    if d.base is bool:
        return lambda: QCheckBox(d.label)
    if cls is m.Defocus and d.name == "object_distance_m":
        return _object_distance
    return lambda: declared_field(cls, d.name)


def _fields(cls: type) -> list:
    """[(label, field, widget factory)] of an effect's declared attributes; a field given
    as (field, to_widget, to_model) converts between the model value and the widget's."""
    out = []
    for d in declare.declared(cls):
        field = d.name
        if d.optional and d.base is float:  # none shows as 0, the field's special text
            field = (d.name, lambda v: 0.0 if v is None else v,
                     lambda v: None if v == 0 else v)
        out.append(("" if d.base is bool else d.label, field, _widget(cls, d)))
    return out


#: effect name → (title, default value when switched on, [(label, field, widget)]), all
#: from the effects' declarations (designer.project.declare), in the model's order
EFFECTS = {
    f.name: (declare.element_of(cls).title, declare.switched_on(cls), _fields(cls))
    for f in dataclasses.fields(m.Effects)
    for cls in [declare.field_class(m.Effects, f.name)]}


def _same(value):
    return value


class EffectsPanel(Panel):
    title = "Effects"
    parts = frozenset({"effects", "trajectory", "cameras"})

    def build(self, layout) -> None:
        self.groups: dict[str, QGroupBox] = {}
        for name, (title, default, fields) in EFFECTS.items():
            group = QGroupBox(title)
            group.setCheckable(True)
            group.toggled.connect(lambda on, n=name, d=default: self._toggle(n, d, on))
            f = form(group)
            for label, field, factory in fields:
                fl, to_widget, to_model = (field if isinstance(field, tuple)
                                           else (field, _same, _same))
                setter = (_set_shutter if fl == "exposure_time_s" else
                          lambda p, v, n=name, fl=fl, c=to_model: edits.replace_path(
                              p, f"effects.{n}.{fl}", c(v)))
                f.addRow(label, self.bindings.bind(factory(), (
                    model_getter(f"effects.{name}.{fl}", to_widget),
                    setter), f"{title} {label or fl}"))
            if name == "motion_blur":
                self.smear = readout()
                f.addRow("smear", self.smear)
            self.groups[name] = group
            layout.addWidget(group)
        self.sync.stations_changed.connect(self._readouts)

    def refresh(self) -> None:
        super().refresh()
        effects = self.project.effects
        for name, group in self.groups.items():
            blocked = group.blockSignals(True)
            group.setChecked(effects is not None and getattr(effects, name) is not None)
            group.blockSignals(blocked)
        self._readouts()

    def _readouts(self) -> None:
        effects = self.project.effects
        mb = effects.motion_blur if effects is not None else None
        stations = self.sync.stations
        if mb is None or stations is None or stations.calc is None:
            self.smear.setText("–")
            return
        length_m = mb.speed_m_s * mb.exposure_time_s
        scale = self.project.render.resolution_scale
        self.smear.setText(f"{100 * length_m:.1f} cm = "
                           f"{length_m / stations.calc.gsd_m * scale:.2f} px in the rendered image")

    def _toggle(self, name: str, default, on: bool) -> None:
        effects = self.project.effects
        if on and name == "defocus" and self.sync.stations is not None \
                and self.sync.stations.calc is not None:
            # focused on the ground the flight looks at, not at a fixed distance
            default = dataclasses.replace(default, focus_distance_m=round(
                self.sync.stations.calc.altitude_agl_m, 1))
        if on and name in SHUTTER and effects is not None:
            other = getattr(effects, SHUTTER[name])
            if other is not None:  # one camera, one shutter
                default = dataclasses.replace(default, exposure_time_s=other.exposure_time_s)
        self.editor.edit(edits.set_effect(self.project, name, default if on else None),
                         f"{EFFECTS[name][0]} {'on' if on else 'off'}")


#: the two effects that share the camera's exposure time (each names the other)
SHUTTER = {"sensor": "motion_blur", "motion_blur": "sensor"}


def _set_shutter(project: m.Project, value: float) -> m.Project:
    """The exposure time of the sensor and of the motion blur: one shutter, one value."""
    for name in SHUTTER:
        if project.effects is not None and getattr(project.effects, name) is not None:
            project = edits.replace_path(project, f"effects.{name}.exposure_time_s", value)
    return project
