"""Vegetation: grass tufts, shrubs and trees scattered over the terrain by a seeded
process, kept clear of the GCP targets, swaying in the wind at each photo's time
(docs/world.md, Vegetation and wind). Groups of plants are added, edited and removed
here, every edit on the undo stack; mesh-file plants are given in the project file."""

from __future__ import annotations

import dataclasses

from PySide6.QtWidgets import QCheckBox, QGroupBox, QLabel

from designer.gui.qt.boxes import checked_group, chosen_index, item_chooser, refill_chooser
from designer.gui.qt.panels.base import Panel
from designer.gui.qt.widgets import combo, declared_field, form, readout
from designer.gui.state import edits
from designer.gui.state.edits import AbsentElement
from designer.gui.state.switched_on import FIRST_PLANT_KIND, new_plant_group
from designer.project import model as m

VEGETATION = "scene.vegetation"
WIND = "scene.vegetation.wind"
class VegetationPanel(Panel):
    title = "Vegetation"
    parts = frozenset({"objects", "trajectory", "terrain"})

    def build(self, layout) -> None:
        self.enabled = QCheckBox("plants on the terrain")
        self.enabled.toggled.connect(self._toggled)
        layout.addWidget(self.enabled)
        self.placement = QGroupBox("placement")
        f = form(self.placement)
        f.addRow("seed", self.bindings.bind(declared_field(m.Vegetation, "seed"),
                                            f"{VEGETATION}.seed",
                                            "Vegetation seed"))
        f.addRow("clear of targets", self.bindings.bind(
            declared_field(m.Vegetation, "clearance_m"), f"{VEGETATION}.clearance_m",
            "Vegetation target clearance"))
        layout.addWidget(self.placement)

        kinds = (("grass-tuft", "add grass"), ("shrub", "add shrubs"), ("tree", "add trees"))
        self.chooser, added, self.remove = item_chooser(
            layout, "plant-group", self._show_selected,
            [(label, lambda k=kind: self._add(k)) for kind, label in kinds], self._remove)
        self.add_buttons = {kind: button for (kind, _), button in zip(kinds, added, strict=True)}

        self.selected = QGroupBox("selected plants")
        f = form(self.selected)
        self.kind = combo([("grass tufts", "grass-tuft"), ("shrubs", "shrub"),
                           ("trees", "tree")])
        self.kind.switched_on_value = FIRST_PLANT_KIND  # greyed, as its fields below
        f.addRow("kind", self.bindings.bind(self.kind, self._access("kind"), "Plant kind"))
        # while there is no group, greyed, the group switching plants on gives
        first = new_plant_group(FIRST_PLANT_KIND)
        for label, name, undo in (("density", "density_per_m2", "Plant density"),
                                  ("height", "height_m", "Plant height"),
                                  ("height spread", "height_sd_m", "Plant height spread"),
                                  ("crown", "crown_m", "Plant crown")):
            box = declared_field(m.PlantGroup, name)
            box.switched_on_value = getattr(first, name)
            f.addRow(label, self.bindings.bind(box, self._access(name), undo))
        self.count_label = readout()
        f.addRow("plants", self.count_label)
        layout.addWidget(self.selected)

        self.wind, f, self.windy = checked_group("wind", "plants sway in the wind",
                                                 self._wind_toggled)
        for label, name, undo in (("amplitude", "amplitude_deg", "Wind amplitude"),
                                  ("gust period", "gust_period_s", "Wind gust period"),
                                  ("towards", "direction_deg", "Wind direction")):
            f.addRow(label, self.bindings.bind(declared_field(m.Wind, name), f"{WIND}.{name}",
                                               undo))
        self.wind_note = QLabel()
        self.wind_note.setWordWrap(True)
        f.addRow(self.wind_note)
        layout.addWidget(self.wind)

    # ------------------------------------------------------------------ access
    def _index(self) -> int:
        """The chosen group; the first when none is chosen yet."""
        return chosen_index(self.chooser)

    def _groups(self, p: m.Project) -> tuple[m.PlantGroup, ...]:
        return p.scene.vegetation.plants if p.scene.vegetation is not None else ()

    def _access(self, name: str):
        def get(p: m.Project):
            k, groups = self._index(), self._groups(p)
            if not 0 <= k < len(groups):
                raise AbsentElement(f"{VEGETATION}.plants[{k}].{name}", name, None)
            value = getattr(groups[k], name)
            if value is None and name in ("height_m", "crown_m") and groups[k].kind:
                value = m.PLANT_KINDS[groups[k].kind][0 if name == "height_m" else 1]
            return value

        def put(p: m.Project, value):
            k, groups = self._index(), list(self._groups(p))
            if not 0 <= k < len(groups):
                raise AbsentElement(f"{VEGETATION}.plants[{k}].{name}", name, None)
            groups[k] = dataclasses.replace(groups[k], **{name: value})
            return edits.replace_path(p, f"{VEGETATION}.plants", tuple(groups))

        return get, put

    # ------------------------------------------------------------------ model → view
    def refresh(self) -> None:
        veg = self.project.scene.vegetation
        blocked = self.enabled.blockSignals(True)
        self.enabled.setChecked(veg is not None)
        self.enabled.blockSignals(blocked)
        refill_chooser(self.chooser, [
            (f"{k + 1}: {g.kind or g.mesh} ({g.density_per_m2:g} /m²)", k)
            for k, g in enumerate(self._groups(self.project))])
        blocked = self.windy.blockSignals(True)
        self.windy.setChecked(veg is not None and veg.wind is not None)
        self.windy.blockSignals(blocked)
        self.windy.setEnabled(veg is not None)
        for button in self.add_buttons.values():
            button.setEnabled(True)
        self.wind_note.setText(
            "" if veg is None or veg.wind is None else
            "the plants sway with each photo's time" if self.project.trajectory.time_line
            else "no time line: the plants stand upright (switch it on in the Flight panel)")
        self._show_selected()

    def _show_selected(self) -> None:
        super().refresh()
        groups = self._groups(self.project)
        k = self._index()
        self.remove.setEnabled(bool(groups))
        if 0 <= k < len(groups):
            g = groups[k]
            self.kind.setEnabled(g.mesh is None)
            e = self.project.scene.terrain.extent
            area = (e.max_X - e.min_X) * (e.max_Y - e.min_Y)
            self.count_label.setText(f"about {g.density_per_m2 * area:,.0f} on the "
                                     f"{area:,.0f} m² terrain (fewer near targets)")
        else:
            self.count_label.setText("–")

    # ------------------------------------------------------------------ view → model
    def _toggled(self, on: bool) -> None:
        if on == (self.project.scene.vegetation is not None):
            return
        value = m.Vegetation((new_plant_group(FIRST_PLANT_KIND),)) if on else None
        self.editor.edit(edits.replace_path(self.project, VEGETATION, value),
                         "Vegetation " + ("on" if on else "off"))

    def _wind_toggled(self, on: bool) -> None:
        veg = self.project.scene.vegetation
        if veg is None or on == (veg.wind is not None):
            return
        self.editor.edit(edits.replace_path(self.project, WIND, m.Wind() if on else None),
                         "Wind " + ("on" if on else "off"))

    def _add(self, kind: str) -> None:
        p = self.project
        veg = p.scene.vegetation or m.Vegetation(())
        veg = dataclasses.replace(veg, plants=(*veg.plants, new_plant_group(kind)))
        self.editor.edit(edits.replace_path(p, VEGETATION, veg), f"Add {kind} plants")
        self.chooser.setCurrentIndex(self.chooser.count() - 1)

    def _remove(self) -> None:
        p, k = self.project, self._index()
        groups = list(self._groups(p))
        if not 0 <= k < len(groups):
            return
        groups.pop(k)
        value = (dataclasses.replace(p.scene.vegetation, plants=tuple(groups))
                 if groups else None)
        self.editor.edit(edits.replace_path(p, VEGETATION, value),
                         f"Remove plant group {k + 1}")
