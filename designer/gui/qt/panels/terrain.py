"""Terrain: generate procedural hills (live preview) or a flat plane; import a DEM or a mesh;
choose what is rendered beyond its extent (the surroundings)."""

from __future__ import annotations

import dataclasses
from pathlib import Path

from PySide6.QtWidgets import (
    QFileDialog,
    QGroupBox,
    QLabel,
)

from designer.gui.qt.boxes import file_box, readouts, wrapped_label
from designer.gui.qt.field_rules import ruled_dspin
from designer.gui.qt.panels.base import ERROR_STYLE, Panel
from designer.gui.qt.widgets import combo, dspin, form, format_number, ispin
from designer.project import model as m
from designer.project.scene_limits import GRID_TOL, MAX_TERRAIN_NODES

KINDS = [("procedural hills", "procedural"), ("flat plane", "flat"),
         ("DEM file (GeoTIFF, ESRI ASCII)", "dem"), ("mesh file (PLY, OBJ, STL)", "mesh")]

#: the surroundings choices: the kind's default (None: nothing written to the file), or
#: one of the modes declared explicitly
SURROUNDINGS = (None, *m.SURROUNDINGS_MODES)
SURROUNDINGS_TIP = ("What is rendered beyond the extent. auto: the terrain continues as far "
                    "as the images see (hills, plane or DEM edge heights, and the texture), "
                    "so no image sees past its edge; none: the extent only, pixels beyond it "
                    "show the background. The default is auto for flat and procedural "
                    "terrain, none for DEM and mesh files.")
#: the largest hills' wavelength, as the file allows it (XSD PositiveLength: > 0, ≤ 1e6 m)
HILL_SIZE_MAX_M = 1e6


def grid_problem(size_m: float, spacing_m: float) -> bool:
    """True when ``size_m`` is no whole number (≥ 1) of ``spacing_m`` grid cells (the
    tolerance of the project's own check)."""
    if spacing_m <= 0:
        return True
    n = round(size_m / spacing_m)
    return n < 1 or abs(n * spacing_m - size_m) > GRID_TOL * size_m


def default_source(kind: str, terrain: m.Terrain) -> m.TerrainSource:
    e = terrain.extent
    if kind == "flat":
        return m.FlatTerrain(0.0)
    spacing = min(e.width_m, e.length_m) / 200
    if any(abs(size / spacing - round(size / spacing)) > 1e-9 for size in (e.width_m,
                                                                          e.length_m)):
        spacing = 1.0  # a whole number of cells along both sides is required
    return m.ProceduralTerrain(seed=1, grid_spacing_m=spacing, roughness=0.3,
                               min_height_m=-5.0, max_height_m=5.0)


class TerrainPanel(Panel):
    title = "Terrain"
    parts = frozenset({"terrain"})

    def build(self, layout) -> None:
        self.kind = combo(KINDS)
        self.kind.currentIndexChanged.connect(self._kind_changed)
        top = form()
        top.addRow("source", self.kind)
        self.surroundings = self.bindings.bind(
            combo([(str(mode), mode) for mode in SURROUNDINGS]),
            "scene.terrain.surroundings", "Terrain surroundings")
        self.surroundings.setToolTip(SURROUNDINGS_TIP)
        top.addRow("surroundings", self.surroundings)
        self.surroundings_note = QLabel()
        self.surroundings_note.setWordWrap(True)
        top.addRow("", self.surroundings_note)
        layout.addLayout(top)

        extent = QGroupBox("extent (world X east, Y north; m)")
        f = form(extent)
        # min below max, and a whole number of grid cells, checked where they are typed
        for name, label in (("min_X", "min X"), ("min_Y", "min Y"), ("max_X", "max X"),
                            ("max_Y", "max Y")):
            f.addRow(label, self.bindings.bind(
                ruled_dspin(lambda v, n=name: self._edge_problem(n, v), -1e8, 1e8, 3, 10, "m"),
                f"scene.terrain.extent.{name}", f"Terrain extent {label}"))
        layout.addWidget(extent)

        self.procedural = QGroupBox("procedural hills")
        f = form(self.procedural)
        src = "scene.terrain.source"
        f.addRow("seed", self.bindings.bind(ispin(0, 2**31 - 1), f"{src}.seed", "Terrain seed"))
        f.addRow("grid spacing", self.bindings.bind(
            ruled_dspin(self._spacing_problem, 0.01, 1000, 3, 0.1, "m"),
            f"{src}.grid_spacing_m", "Terrain grid spacing"))
        f.addRow("roughness", self.bindings.bind(
            dspin(0, 1, 2, 0.05), f"{src}.roughness", "Terrain roughness"))
        # lowest ≤ highest is checked where it is typed, in the numbers typed
        f.addRow("lowest", self.bindings.bind(
            ruled_dspin(self._lowest_problem, -1e4, 1e4, 2, 1, "m"), f"{src}.min_height_m",
            "Terrain lowest height"))
        f.addRow("highest", self.bindings.bind(
            ruled_dspin(self._highest_problem, -1e4, 1e4, 2, 1, "m"), f"{src}.max_height_m",
            "Terrain highest height"))
        hill_size = dspin(0.0, HILL_SIZE_MAX_M, 3, 10, "m", low_open=True)
        hill_size.setToolTip("Wavelength of the largest hills (more than 0 m); the hills are "
                             "fixed to the world, so a larger extent keeps every hill")
        f.addRow("hill size", self.bindings.bind(hill_size, f"{src}.hill_size_m",
                                                 "Terrain hill size"))
        layout.addWidget(self.procedural)

        self.flat = QGroupBox("flat plane")
        f = form(self.flat)
        f.addRow("height Z", self.bindings.bind(dspin(-1e4, 1e4, 3, 1, "m"),
                                                "scene.terrain.source.height_m",
                                                "Flat terrain height"))
        layout.addWidget(self.flat)

        self.file_box, self.file_label = file_box("file", "Import…", self._import)
        layout.addWidget(self.file_box)

        self.size_label, self.relief_label = readouts(layout, "grid", "relief")
        self.error_label = wrapped_label(ERROR_STYLE)
        layout.addWidget(self.error_label)
        self.sync.terrain_changed.connect(self._show_result)

    # ------------------------------------------------------------------ model → view
    def refresh(self) -> None:
        self._offer_surroundings(self.project.scene.terrain)
        super().refresh()
        terrain = self.project.scene.terrain
        blocked = self.kind.blockSignals(True)
        self.kind.setCurrentIndex(self.kind.findData(terrain.kind))
        self.kind.blockSignals(blocked)
        self.procedural.setVisible(terrain.kind == "procedural")
        self.flat.setVisible(terrain.kind == "flat")
        self.file_box.setVisible(terrain.kind in ("dem", "mesh"))
        if terrain.kind in ("dem", "mesh"):
            self.file_label.setText(terrain.source.file)

    def _offer_surroundings(self, terrain: m.Terrain) -> None:
        """The surroundings choices for the terrain's kind: its default named, and auto
        greyed out for a mesh (only a height field can be continued)."""
        from designer.scene.surroundings import surroundings_mode

        default = surroundings_mode(dataclasses.replace(terrain, surroundings=None))
        mesh = terrain.kind == "mesh"
        items = self.surroundings.model()
        for i, mode in enumerate(SURROUNDINGS):
            if mode is None:
                text = f"{default} (default)"
            else:
                text = "auto (not for a mesh)" if mesh and mode == "auto" else mode
            self.surroundings.setItemText(i, text)
        items.item(SURROUNDINGS.index("auto")).setEnabled(not mesh)
        note, error = "", False
        if mesh and terrain.surroundings == "auto":
            note, error = ("auto cannot continue a mesh terrain (only a flat, procedural or "
                           "DEM terrain can be continued): choose none, or import the "
                           "terrain as a DEM"), True
        elif mesh:
            note = ("a mesh terrain is rendered as it is: pixels beyond it show the "
                    "background")
        elif surroundings_mode(terrain) == "none":
            note = "pixels beyond the extent show the background"
        self.surroundings_note.setText(note)
        self.surroundings_note.setStyleSheet(ERROR_STYLE if error else "")
        self.surroundings_note.setVisible(bool(note))

    def _show_result(self) -> None:
        result = self.sync.terrain
        self.error_label.setText(self.sync.errors.get("terrain", ""))
        if result is None:
            self.size_label.setText("–")
            self.relief_label.setText("–")
            return
        if result.heightfield is not None:
            ny, nx = result.heightfield.heights_m.shape
            shown = ("" if result.display.stride == 1
                     else f"; shown every {result.display.stride}th node")
            self.size_label.setText(f"{nx} × {ny} = {nx * ny:,} vertices{shown}")
            z = result.heightfield.heights_m
        else:
            self.size_label.setText(f"mesh, {result.n_vertices:,} vertices")
            z = result.mesh.vertices_world[:, 2]
        self.relief_label.setText(f"{z.min():.2f} … {z.max():.2f} m")

    # ------------------------------------------------------------------ view → model
    def _heights(self) -> tuple[float, float] | None:
        src = self.project.scene.terrain.source
        if not isinstance(src, m.ProceduralTerrain):
            return None
        return src.min_height_m, src.max_height_m

    def _lowest_problem(self, value: float) -> str:
        heights = self._heights()
        if heights is None or value <= heights[1]:
            return ""
        return (f"lowest ({format_number(value, 2)} m) must be below highest "
                f"({format_number(heights[1], 2)} m)")

    def _highest_problem(self, value: float) -> str:
        heights = self._heights()
        if heights is None or value >= heights[0]:
            return ""
        return (f"highest ({format_number(value, 2)} m) must be above lowest "
                f"({format_number(heights[0], 2)} m)")

    def _spacing(self) -> float | None:
        src = self.project.scene.terrain.source
        return src.grid_spacing_m if isinstance(src, m.ProceduralTerrain) else None

    def _edge_problem(self, name: str, value: float) -> str:
        """Why extent edge ``name`` (min_X …) cannot be ``value``, in the numbers typed."""
        e = self.project.scene.terrain.extent
        axis, is_min = name[-1], name.startswith("min")
        other = getattr(e, f"{'max' if is_min else 'min'}_{axis}")
        label, other_label = (f"min {axis}", f"max {axis}") if is_min else (f"max {axis}",
                                                                             f"min {axis}")
        if (value >= other) if is_min else (value <= other):
            return (f"{label} ({format_number(value, 3)} m) must be "
                    f"{'below' if is_min else 'above'} {other_label} "
                    f"({format_number(other, 3)} m)")
        spacing = self._spacing()
        size = abs(other - value)
        if spacing is not None and grid_problem(size, spacing):
            side = "width" if axis == "X" else "length"
            return (f"{label} ({format_number(value, 3)} m) leaves a {side} of "
                    f"{format_number(size, 3)} m, not a whole number of "
                    f"{format_number(spacing, 3)} m grid cells; change the grid spacing "
                    "first or keep whole cells")
        # what the new extent would break in other panels, refused here rather than
        # reported there afterwards
        extent = dataclasses.replace(e, **{name: value})
        typed = f"{label} ({format_number(value, 3)} m)"
        return (self._texture_broken(extent, typed) or self._gcps_off(extent, typed)
                or self._buildings_off(extent, typed) or self._area_off(extent, typed))

    def _texture_broken(self, extent: m.Extent, typed: str) -> str:
        from designer.scene.build import tile_problem  # the scene builder loads lazily

        tex = self.project.scene.texture
        if not isinstance(tex.source, m.ProceduralTexture):
            return ""
        texel = tex.source.texel_size_m
        reason = tile_problem(extent.width_m, extent.length_m, tex.repeat_X, tex.repeat_Y,
                              texel, tex.source.pattern)
        if not reason:
            return ""
        return (f"{typed} would break the texture: texel size {format_number(texel, 4)} m "
                f"makes {reason} in the Texture panel first")

    def _gcps_off(self, extent: m.Extent, typed: str) -> str:
        off = [t for t in self.project.targets if not extent.contains(t.true.X, t.true.Y)]
        if not off:
            return ""
        named = ", ".join(f"{t.id} at X {format_number(t.true.X, 3)}, Y "
                          f"{format_number(t.true.Y, 3)}" for t in off[:3])
        more = f" and {len(off) - 3} more" if len(off) > 3 else ""
        count = "1 GCP" if len(off) == 1 else f"{len(off)} GCPs"
        return (f"{typed} would leave {count} off the terrain ({named}{more}); move "
                f"{'it' if len(off) == 1 else 'them'} in the GCPs panel first or keep the "
                f"extent around {'it' if len(off) == 1 else 'them'}")

    def _buildings_off(self, extent: m.Extent, typed: str) -> str:
        """The first building a footprint corner (or a mesh's origin) of which ``extent``
        would leave off the terrain, as the checks would report it afterwards."""
        for b in self.project.scene.buildings:
            points = b.footprint or ((b.position,) if b.position is not None else ())
            for p in points:
                if not extent.contains(p.X, p.Y):
                    where = "its corner" if b.footprint else "its origin"
                    return (f"{typed} would leave building {b.id} off the terrain ({where} "
                            f"at X {format_number(p.X, 3)}, Y {format_number(p.Y, 3)}); "
                            "move it in the Buildings panel first or keep the extent around "
                            "it")
        return ""

    def _area_off(self, extent: m.Extent, typed: str) -> str:
        plan = self.project.trajectory.flight_plan
        if plan is None:
            return ""
        off = [(i + 1, x, y) for i, (x, y) in enumerate(plan.area)
               if not extent.contains(x, y)]
        if not off:
            return ""
        named = "; ".join(f"corner {i} at X {format_number(x, 3)}, Y {format_number(y, 3)}"
                          for i, x, y in off[:3])
        more = f" and {len(off) - 3} more" if len(off) > 3 else ""
        one = len(off) == 1
        count = "1 corner" if one else f"{len(off)} corners"
        return (f"{typed} would leave {count} of the flight area off the terrain ({named}"
                f"{more}); move {'it' if one else 'them'} in the Flight panel first or keep "
                f"the extent around {'it' if one else 'them'}")

    def _spacing_problem(self, value: float) -> str:
        """Why the procedural grid spacing cannot be ``value`` over the extent."""
        e = self.project.scene.terrain.extent
        if value <= 0:
            return ""  # the field's range says so
        for side, size, edges in (("width", e.width_m, "min X to max X"),
                                  ("length", e.length_m, "min Y to max Y")):
            if grid_problem(size, value):
                return (f"grid spacing {format_number(value, 3)} m does not divide the "
                        f"extent's {side} ({format_number(size, 3)} m, {edges}) into whole "
                        "cells")
        nodes = (e.width_m / value + 1) * (e.length_m / value + 1)
        if nodes > MAX_TERRAIN_NODES:
            return (f"grid spacing {format_number(value, 3)} m gives {nodes:,.0f} grid nodes "
                    f"over the extent, more than {MAX_TERRAIN_NODES:,.0f}; use a coarser "
                    "spacing")
        return ""

    def _kind_changed(self) -> None:
        kind = self.kind.currentData()
        terrain = self.project.scene.terrain
        if kind == terrain.kind:
            return
        if kind in ("dem", "mesh"):
            self._import(kind)
            self.refresh()
            return
        source = default_source(kind, terrain)
        self.editor.edit(self._with_terrain(dataclasses.replace(terrain, source=source)),
                         f"Terrain: {kind}")

    def _with_terrain(self, terrain: m.Terrain) -> m.Project:
        scene = dataclasses.replace(self.project.scene, terrain=terrain)
        return dataclasses.replace(self.project, scene=scene)

    def _import(self, kind: str | None = None) -> None:
        kind = kind or self.project.scene.terrain.kind
        pattern = ("DEM (*.tif *.tiff *.asc)" if kind == "dem"
                   else "mesh (*.ply *.obj *.stl)")
        path, _ = QFileDialog.getOpenFileName(self, f"Import {kind.upper()}",
                                              str(self.editor.document.base_dir), pattern)
        if path:
            self.import_file(kind, Path(path))

    def import_file(self, kind: str, path: Path) -> None:
        """Use a DEM or mesh file as terrain; the extent becomes the file's (off the UI
        thread: a large DEM takes a while to read)."""
        rel = self.relative_path(str(path))
        project = self.project

        def extent_of_file() -> m.Extent:
            if kind == "dem":
                from designer.scene.dem import load_dem

                x0, x1, y0, y1 = load_dem(path, project.crs).extent_m
            else:
                from designer.scene.mesh import load_mesh

                v = load_mesh(path).vertices_world
                o = project.origin
                x0, y0 = v[:, 0].min() + o.E0, v[:, 1].min() + o.N0
                x1, y1 = v[:, 0].max() + o.E0, v[:, 1].max() + o.N0
            return m.Extent(float(x0), float(y0), float(x1), float(y1))

        def done(extent: m.Extent) -> None:
            source = m.DemTerrain(rel) if kind == "dem" else m.MeshTerrain(rel)
            # a declared choice of surroundings stays, but for auto, which a mesh refuses
            around = self.project.scene.terrain.surroundings
            around = None if kind == "mesh" and around == "auto" else around
            self.editor.edit(self._with_terrain(m.Terrain(extent, source, around)),
                             f"Import {kind.upper()} {path.name}")

        def failed(error: BaseException) -> None:
            self.error_label.setText(f"{path.name}: {error}")

        self.sync.tasks.submit("import-terrain", extent_of_file, on_done=done, on_error=failed)
