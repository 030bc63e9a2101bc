"""Effects: each image effect switched on or off, its parameters in physical units.

Lens distortion is part of the camera (Camera panel), not an effect.
"""

from __future__ import annotations

import dataclasses

from PySide6.QtWidgets import QCheckBox, QDoubleSpinBox, QGroupBox

from designer.gui import edits
from designer.gui.panels.base import Panel
from designer.gui.widgets import dspin, form, ispin, model_getter, readout
from designer.project import model as m


def _cos4() -> QCheckBox:
    return QCheckBox("natural cos⁴ fall-off of the lens")


def _object_distance() -> QDoubleSpinBox:
    box = dspin(0, 1e6, 2, 1, "m")
    box.setSpecialValueText("each image's distance to the ground")
    return box


#: effect name → (title, default value, [(label, field, widget factory)]); a field given
#: as (field, to_widget, to_model) converts between the model value and the widget's
EFFECTS = {
    "vignetting": ("vignetting", m.Vignetting(0.2), [
        ("corner fall-off (ρ²)", "corner_falloff", lambda: dspin(0, 1, 3, 0.05)),
        ("ρ⁴ term", "rho4", lambda: dspin(-1, 1, 3, 0.05)),
        ("ρ⁶ term", "rho6", lambda: dspin(-1, 1, 3, 0.05)),
        ("", "natural_cos4", _cos4)]),
    "defocus": ("defocus (thin lens)", m.Defocus(2.8, 50.0), [
        ("f-number", "f_number", lambda: dspin(0.5, 64, 2, 0.5)),
        ("focused at", "focus_distance_m", lambda: dspin(0.1, 1e6, 2, 1, "m")),
        ("object distance", ("object_distance_m", lambda v: 0.0 if v is None else v,
                             lambda v: None if v == 0 else v), _object_distance)]),
    "sensor": ("sensor (photon shot noise, dark current, read noise, ADC)",
               m.Sensor(full_well_e=20000.0, read_noise_e=3.0), [
        ("full well", "full_well_e", lambda: dspin(1, 1e7, 0, 1000, "e⁻")),
        ("read noise", "read_noise_e", lambda: dspin(0, 1e4, 2, 0.5, "e⁻")),
        ("dark current", "dark_current_e_per_s", lambda: dspin(0, 1e6, 2, 0.5, "e⁻/s")),
        ("exposure time (shutter)", "exposure_time_s", lambda: dspin(0, 60, 5, 0.0005, "s")),
        ("ADC", "adc_bits", lambda: ispin(1, 16, "bits")),
        ("white at", "exposure_scale", lambda: dspin(0, 100, 3, 0.05, "× full well")),
        ("seed", "seed", lambda: ispin(0, 2**31 - 1))]),
    "sensor_noise": ("sensor noise (Gaussian, in DN)", m.SensorNoise(1.5, 0), [
        ("σ", "sigma_dn", lambda: dspin(0, 100, 2, 0.5, "DN")),
        ("seed", "seed", lambda: ispin(0, 2**31 - 1))]),
    "blur": ("optical blur (Gaussian)", m.Blur(0.5), [
        ("σ", "sigma_px", lambda: dspin(0, 50, 3, 0.1, "px"))]),
    "motion_blur": ("motion blur", m.MotionBlur(0.001, 8.0), [
        ("exposure time (shutter)", "exposure_time_s", lambda: dspin(0, 1, 5, 0.0005, "s")),
        ("ground speed", "speed_m_s", lambda: dspin(0, 100, 2, 1, "m/s"))]),
    "jpeg": ("JPEG compression", m.Jpeg(92), [
        ("quality", "quality", lambda: ispin(1, 100))]),
}
# every effect shown is a field of the model (one it does not show is left as it is)
assert set(EFFECTS) <= {f.name for f in dataclasses.fields(m.Effects)}


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
