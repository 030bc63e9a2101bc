"""Effects: each image effect switched on or off, its parameters in physical units.

Lens distortion is part of the camera (Camera panel), not an effect.
"""

from __future__ import annotations

from PySide6.QtWidgets import QGroupBox

from designer.gui import edits
from designer.gui.panels.base import Panel
from designer.gui.widgets import dspin, form, ispin, readout
from designer.project import model as m

#: effect name → (title, model class, default value, [(label, field, spin box factory)])
EFFECTS = {
    "vignetting": ("vignetting", m.Vignetting, m.Vignetting(0.2), [
        ("corner fall-off", "corner_falloff", lambda: dspin(0, 1, 3, 0.05))]),
    "sensor_noise": ("sensor noise", m.SensorNoise, m.SensorNoise(1.5, 0), [
        ("σ", "sigma_dn", lambda: dspin(0, 255, 2, 0.5, "DN")),
        ("seed", "seed", lambda: ispin(0, 2**31 - 1))]),
    "blur": ("optical blur (Gaussian)", m.Blur, m.Blur(0.5), [
        ("σ", "sigma_px", lambda: dspin(0, 50, 3, 0.1, "px"))]),
    "motion_blur": ("motion blur", m.MotionBlur, m.MotionBlur(0.001, 8.0), [
        ("exposure time", "exposure_time_s", lambda: dspin(0, 1, 5, 0.0005, "s")),
        ("ground speed", "speed_m_s", lambda: dspin(0, 100, 2, 1, "m/s"))]),
    "jpeg": ("JPEG compression", m.Jpeg, m.Jpeg(92), [
        ("quality", "quality", lambda: ispin(1, 100))]),
}


class EffectsPanel(Panel):
    title = "Effects"
    parts = frozenset({"effects", "trajectory", "cameras"})

    def build(self, layout) -> None:
        self.groups: dict[str, QGroupBox] = {}
        for name, (title, _cls, default, fields) in EFFECTS.items():
            group = QGroupBox(title)
            group.setCheckable(True)
            group.toggled.connect(lambda on, n=name, d=default: self._toggle(n, d, on))
            f = form(group)
            for label, field, factory in fields:
                f.addRow(label, self.bindings.bind(factory(), (
                    lambda p, n=name, fl=field: getattr(getattr(p.effects, n), fl),
                    lambda p, v, n=name, fl=field: edits.replace_path(p, f"effects.{n}.{fl}", v)),
                    f"{title} {label}"))
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
        self.editor.edit(edits.set_effect(self.project, name, default if on else None),
                         f"{EFFECTS[name][0]} {'on' if on else 'off'}")
