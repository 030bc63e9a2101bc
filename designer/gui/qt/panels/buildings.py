"""Buildings: houses and flat-roofed blocks standing on the terrain (docs/world.md,
Buildings and structures). New buildings are 10 m × 8 m rectangles placed beside the
terrain's centre, clear of the GCP targets; their footprints are edited in the project
file, their roof, wall and ridge heights here, every edit on the undo stack."""

from __future__ import annotations

import dataclasses

from PySide6.QtWidgets import QGroupBox

from designer.gui.qt.boxes import chosen_index, item_chooser, refill_chooser
from designer.gui.qt.field_rules import ruled_like
from designer.gui.qt.panels.base import Panel
from designer.gui.qt.widgets import combo, declared_field, form, readout
from designer.gui.state.edits import AbsentElement
from designer.project import model as m
from designer.project.geometry import point_in_polygon
from designer.project.validate_shared import plain_number

#: a new building's footprint (m east × m north) and heights (m above its base)
NEW_SIZE_M = (10.0, 8.0)
NEW_EAVE_M = {"gable": 6.0, "flat": 9.0}
#: a gable or hip roof chosen for a flat building rises this much above the eaves (m)
NEW_RISE_M = 3.0


class BuildingsPanel(Panel):
    title = "Buildings"
    parts = frozenset({"objects", "terrain", "targets"})

    def build(self, layout) -> None:
        self.chooser, (self.add_house, self.add_block), self.remove = item_chooser(
            layout, "building", self._show_selected,
            [("add a house", lambda: self._add("gable")),
             ("add a block", lambda: self._add("flat"))], self._remove)

        self.selected = QGroupBox("selected building")
        f = form(self.selected)
        self.roof = combo([(r, r) for r in m.ROOF_SHAPES])
        f.addRow("roof", self.bindings.bind(self.roof, self._roof_access(), "Building roof"))
        f.addRow("walls", self.bindings.bind(declared_field(m.Building, "eave_height_m"),
                                             self._access("eave_height_m"),
                                             "Building eave height"))
        ridge = ruled_like(declared_field(m.Building, "ridge_height_m"), self._ridge_problem)
        f.addRow("ridge", self.bindings.bind(ridge, self._access("ridge_height_m"),
                                             "Building ridge height"))
        self.footprint_label = readout()
        f.addRow("footprint", self.footprint_label)
        layout.addWidget(self.selected)

    # ------------------------------------------------------------------ access
    def _index(self) -> int:
        """The chosen building; the first when none is chosen yet."""
        return chosen_index(self.chooser)

    def _extruded(self, p: m.Project, name: str) -> m.Building:
        k = self._index()
        if not 0 <= k < len(p.scene.buildings):
            raise AbsentElement(f"scene.buildings[{k}].{name}", name, None)
        b = p.scene.buildings[k]
        if b.file is not None or (name == "ridge_height_m" and b.ridge_height_m is None):
            raise AbsentElement(f"scene.buildings[{k}].{name}", name, b)
        return b

    def _put(self, p: m.Project, **changes) -> m.Project:
        buildings = list(p.scene.buildings)
        k = self._index()
        buildings[k] = dataclasses.replace(buildings[k], **changes)
        return dataclasses.replace(p, scene=dataclasses.replace(
            p.scene, buildings=tuple(buildings)))

    def _access(self, name: str):
        def get(p: m.Project):
            return getattr(self._extruded(p, name), name)

        def put(p: m.Project, value):
            b = self._extruded(p, name)
            changes = {name: value}
            if name == "eave_height_m" and b.ridge_height_m is not None:
                changes["ridge_height_m"] = b.ridge_height_m - b.eave_height_m + value
            return self._put(p, **changes)

        return get, put

    def _ridge_problem(self, ridge_m: float) -> str:
        """Why a ridge of ``ridge_m`` cannot top the chosen building ("" when it can)."""
        buildings = self.project.scene.buildings
        k = self._index()
        if not 0 <= k < len(buildings) or ridge_m > buildings[k].eave_height_m:
            return ""
        return (f"ridge ({plain_number(ridge_m)} m) must be above the walls "
                f"({plain_number(buildings[k].eave_height_m)} m)")

    def _roof_access(self):
        """The roof shape; a pitched roof gets a ridge NEW_RISE_M above the eaves, a flat
        one loses its ridge."""
        def get(p: m.Project):
            return self._extruded(p, "roof").roof

        def put(p: m.Project, roof: str):
            b = self._extruded(p, "roof")
            if roof == "flat":
                return self._put(p, roof=roof, ridge_height_m=None, ridge_direction_deg=None)
            ridge = b.ridge_height_m if b.ridge_height_m is not None else (
                b.eave_height_m + NEW_RISE_M)
            return self._put(p, roof=roof, ridge_height_m=ridge)

        return get, put

    # ------------------------------------------------------------------ model → view
    def refresh(self) -> None:
        refill_chooser(self.chooser, [(f"{b.id} ({b.roof if b.file is None else b.file})", b.id)
                                      for b in self.project.scene.buildings])
        self._show_selected()

    def _show_selected(self) -> None:
        super().refresh()
        buildings = self.project.scene.buildings
        k = self._index()
        self.remove.setEnabled(bool(buildings))
        if 0 <= k < len(buildings):
            b = buildings[k]
            if b.file is not None:
                text = f"mesh {b.file} at ({b.position.X:.1f}, {b.position.Y:.1f})"
            else:
                xs, ys = [q.X for q in b.footprint], [q.Y for q in b.footprint]
                text = (f"{len(b.footprint)} corners, {max(xs) - min(xs):.1f} m × "
                        f"{max(ys) - min(ys):.1f} m from ({min(xs):.1f}, {min(ys):.1f})")
            self.footprint_label.setText(text)
        else:
            self.footprint_label.setText("–")

    # ------------------------------------------------------------------ view → model
    def _add(self, roof: str) -> None:
        p = self.project
        ids = {b.id for b in p.scene.buildings}
        name = "house" if roof == "gable" else "block"
        n = 1 + sum(1 for b in p.scene.buildings if b.id.startswith(name))
        while f"{name}{n}" in ids:
            n += 1
        footprint = self._free_spot(p)
        eave = NEW_EAVE_M[roof]
        b = m.Building(f"{name}{n}", footprint, roof, eave,
                       eave + NEW_RISE_M if roof == "gable" else None)
        self.editor.edit(dataclasses.replace(p, scene=dataclasses.replace(
            p.scene, buildings=(*p.scene.buildings, b))), f"Add building {b.id}")
        self.chooser.setCurrentIndex(self.chooser.count() - 1)

    @staticmethod
    def _free_spot(p: m.Project) -> tuple[m.PathPoint, ...]:
        """A NEW_SIZE_M rectangle inside the terrain, clear of targets and other
        buildings' corners: tried on rings around the centre, the centre if none is."""
        e = p.scene.terrain.extent
        cx, cy = (e.min_X + e.max_X) / 2, (e.min_Y + e.max_Y) / 2
        w, h = NEW_SIZE_M
        taken = [(t.true.X, t.true.Y) for t in p.targets] + [
            (q.X, q.Y) for b in p.scene.buildings for q in b.footprint]
        for ring in range(0, 6):
            for dx, dy in ((1, 0), (0, 1), (-1, 0), (0, -1), (1, 1), (-1, -1), (1, -1),
                           (-1, 1)):
                x0, y0 = cx + ring * dx * (w + 2) - w / 2, cy + ring * dy * (h + 2) - h / 2
                rect = [(x0, y0), (x0 + w, y0), (x0 + w, y0 + h), (x0, y0 + h)]
                inside = all(e.contains(x, y) for x, y in rect)
                margin = [(x0 - 1, y0 - 1), (x0 + w + 1, y0 - 1), (x0 + w + 1, y0 + h + 1),
                          (x0 - 1, y0 + h + 1)]
                if inside and not any(point_in_polygon(x, y, margin) for x, y in taken):
                    return tuple(m.PathPoint(x, y) for x, y in rect)
                if ring == 0:
                    break
        x0, y0 = cx - w / 2, cy - h / 2
        return tuple(m.PathPoint(x, y) for x, y in
                     ((x0, y0), (x0 + w, y0), (x0 + w, y0 + h), (x0, y0 + h)))

    def _remove(self) -> None:
        p, k = self.project, self._index()
        buildings = list(p.scene.buildings)
        if not 0 <= k < len(buildings):
            return
        gone = buildings.pop(k)
        self.editor.edit(dataclasses.replace(p, scene=dataclasses.replace(
            p.scene, buildings=tuple(buildings))), f"Remove building {gone.id}")
