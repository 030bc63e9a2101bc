"""Texture: a procedural pattern or an image file, its tiling, texel size and interpolation."""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import numpy as np
from PySide6.QtCore import Qt
from PySide6.QtGui import QImage, QPixmap
from PySide6.QtWidgets import QFileDialog, QGroupBox, QLabel

from designer.checks.plan_report import texture_repeat_warning
from designer.gui.qt.boxes import file_box, readouts, wrapped_label
from designer.gui.qt.field_rules import ruled_dspin, ruled_ispin
from designer.gui.qt.panels.base import ERROR_STYLE, Panel
from designer.gui.qt.widgets import combo, declared_field, form, format_number, ispin, readout
from designer.gui.state import derived
from designer.project import model as m

PATTERNS = ["grass", "soil", "gravel", "noise", "checkerboard", "slanted-edge"]
def rgb_pixmap(rgb: np.ndarray, side_px: int) -> QPixmap:
    """A QPixmap of an (H, W, 3) uint8 image scaled to fit ``side_px``."""
    step = max(1, math.ceil(max(rgb.shape[:2]) / (2 * side_px)))
    small = np.ascontiguousarray(rgb[::step, ::step, :3])
    h, w = small.shape[:2]
    image = QImage(small.data, w, h, 3 * w, QImage.Format.Format_RGB888).copy()
    return QPixmap.fromImage(image).scaled(side_px, side_px, Qt.AspectRatioMode.KeepAspectRatio,
                                           Qt.TransformationMode.SmoothTransformation)


class TexturePanel(Panel):
    title = "Texture"
    parts = frozenset({"texture", "terrain", "trajectory", "cameras", "render"})

    def build(self, layout) -> None:
        top = form()
        self.kind = combo([("procedural pattern", "procedural"), ("image file", "image")])
        self.kind.currentIndexChanged.connect(self._kind_changed)
        top.addRow("source", self.kind)
        layout.addLayout(top)

        self.procedural = QGroupBox("procedural")
        f = form(self.procedural)
        src = "scene.texture.source"
        f.addRow("pattern", self.bindings.bind(combo([(p, p) for p in PATTERNS]),
                                               f"{src}.pattern", "Texture pattern"))
        f.addRow("seed", self.bindings.bind(ispin(0, 2**31 - 1), f"{src}.seed", "Texture seed"))
        # the tile's texels (extent / repeat / texel size) are checked where typed
        f.addRow("texel size", self.bindings.bind(
            ruled_dspin(lambda v: self._tile_problem(texel_m=v), 0.0001, 10, 4, 0.001, "m"),
            f"{src}.texel_size_m", "Texel size"))
        layout.addWidget(self.procedural)

        self.image, self.file_label = file_box("image", "Choose…", self._choose)
        layout.addWidget(self.image)

        tiling = QGroupBox("tiling and sampling")
        f = form(tiling)
        f.addRow("repeat X", self.bindings.bind(
            ruled_ispin(lambda v: self._tile_problem(repeat_x=v), 1, 10000),
            "scene.texture.repeat_X", "Texture repeat X"))
        f.addRow("repeat Y", self.bindings.bind(
            ruled_ispin(lambda v: self._tile_problem(repeat_y=v), 1, 10000),
            "scene.texture.repeat_Y", "Texture repeat Y"))
        f.addRow("interpolation", self.bindings.bind(
            combo([("linear", "linear"), ("closest", "closest")]),
            "scene.texture.interpolation", "Texture interpolation"))
        layout.addWidget(tiling)

        self.variation = QGroupBox("non-repeating variation")
        self.variation.setCheckable(True)
        self.variation.toggled.connect(self._toggle_variation)
        f = form(self.variation)
        var = "scene.texture.variation"
        for label, name in (("seed", "seed"), ("scale", "scale_m"), ("strength", "strength"),
                            ("octaves", "octaves")):
            f.addRow(label, self.bindings.bind(declared_field(m.TextureVariation, name),
                                               f"{var}.{name}", f"Texture variation {label}"))
        self.repeat_label = readout()
        f.addRow("repeat", self.repeat_label)
        layout.addWidget(self.variation)

        self.tile_label, self.texel_label, self.ratio_label = readouts(
            layout, "tile", "texel on the ground", "texels per image pixel")
        self.preview = QLabel()
        self.preview.setMinimumHeight(160)
        self.preview.setAlignment(Qt.AlignmentFlag.AlignCenter)
        layout.addWidget(self.preview)
        self.error_label = wrapped_label(ERROR_STYLE)
        layout.addWidget(self.error_label)
        self.sync.texture_changed.connect(self._show_texture)
        self.sync.stations_changed.connect(self._readouts)

    def _tile_problem(self, texel_m: float | None = None, repeat_x: int | None = None,
                      repeat_y: int | None = None) -> str:
        """Why the typed value (one of the three) cannot be, named from its field."""
        from designer.scene.build import tile_problem  # the scene builder loads lazily

        tex, e = self.project.scene.texture, self.project.scene.terrain.extent
        if not isinstance(tex.source, m.ProceduralTexture):
            return ""
        if (texel_m is not None and texel_m <= 0) or (repeat_x or 1) < 1 or (repeat_y or 1) < 1:
            return ""  # the field's range says so
        reason = tile_problem(e.width_m, e.length_m, repeat_x or tex.repeat_X,
                              repeat_y or tex.repeat_Y, texel_m or tex.source.texel_size_m,
                              tex.source.pattern)
        if not reason:
            return ""
        typed = (f"texel size {format_number(texel_m, 4)} m" if texel_m is not None else
                 f"repeat X {repeat_x}" if repeat_x is not None else f"repeat Y {repeat_y}")
        if texel_m is not None:
            reason = reason.replace(f" of {format_number(texel_m, 4)} m,", ",")
        return f"{typed} makes {reason}"

    # ------------------------------------------------------------------ model → view
    def refresh(self) -> None:
        super().refresh()
        tex = self.project.scene.texture
        # an orthophoto shows as its file (it is placed by its geotransform, not tiled)
        is_image = isinstance(tex.source, m.ImageTexture | m.OrthophotoTexture)
        blocked = self.kind.blockSignals(True)
        self.kind.setCurrentIndex(1 if is_image else 0)
        self.kind.blockSignals(blocked)
        self.procedural.setVisible(not is_image)
        self.image.setVisible(is_image)
        if is_image:
            self.file_label.setText(tex.source.file)
        blocked = self.variation.blockSignals(True)
        self.variation.setVisible(not isinstance(tex.source, m.OrthophotoTexture))
        self.variation.setChecked(tex.variation is not None)
        self.variation.blockSignals(blocked)
        self._readouts()

    def _readouts(self) -> None:
        project = self.project
        e, tex = project.scene.terrain.extent, project.scene.texture
        self.tile_label.setText(f"{e.width_m / tex.repeat_X:.3g} × "
                                f"{e.length_m / tex.repeat_Y:.3g} m")
        tx, ty = derived.texel_size_m(project, self.sync.texture_rgb)
        if math.isnan(tx):
            self.texel_label.setText("–")
            self.ratio_label.setText("–")
            return
        size = "" if self.sync.texture_rgb is None else (
            f" ({self.sync.texture_rgb.shape[1]} × {self.sync.texture_rgb.shape[0]} px)")
        self.texel_label.setText(f"{1000 * tx:.2f} × {1000 * ty:.2f} mm{size}")
        stations = self.sync.stations
        self._repeat_readout(stations)
        if stations is not None and stations.calc is not None:
            # the images are rendered at the render's resolution scale: their GSD counts
            scale = project.render.resolution_scale
            gsd = derived.rendered_gsd_m(stations.calc.gsd_m, stations.interior, scale)
            ratio = gsd / max(tx, ty)
            hint = "" if ratio >= 2 else " — fewer than 2: the texture will look blurred"
            where = "" if scale == 1.0 else f" (render scale {scale:g})"
            self.ratio_label.setText(f"{ratio:.1f} at the rendered image's GSD "
                                     f"{100 * gsd:.2f} cm{where}{hint}")
        else:
            self.ratio_label.setText("–")

    def _repeat_readout(self, stations) -> None:
        """The plan's texture-repeat warning, at the flight's nominal GSD."""
        project = self.project
        if stations is None or stations.calc is None:
            self.repeat_label.setText("–")
            return
        w_px, h_px = stations.interior.image_size_px
        footprint = (w_px * stations.calc.gsd_m, h_px * stations.calc.gsd_m)
        warning = texture_repeat_warning(project.scene.texture, project.scene.terrain.extent,
                                         footprint)
        self.repeat_label.setText(warning or "the texture does not repeat inside an image")

    def _show_texture(self) -> None:
        self.error_label.setText(self.sync.errors.get("texture", "")
                                 if self.sync.texture_rgb is None else "")
        if self.sync.texture_rgb is not None:
            self.preview.setPixmap(rgb_pixmap(self.sync.texture_rgb, 160))
        else:
            self.preview.clear()
        self._readouts()

    # ------------------------------------------------------------------ view → model
    def _set_source(self, source, text: str) -> None:
        tex = dataclasses.replace(self.project.scene.texture, source=source)
        scene = dataclasses.replace(self.project.scene, texture=tex)
        self.editor.edit(dataclasses.replace(self.project, scene=scene), text)

    def _toggle_variation(self, on: bool) -> None:
        tex = self.project.scene.texture
        variation = None
        if on:
            e = self.project.scene.terrain.extent
            tile_m = max(e.width_m / tex.repeat_X, e.length_m / tex.repeat_Y)
            variation = m.TextureVariation(seed=1, scale_m=round(2 * tile_m, 2), strength=0.35)
        scene = dataclasses.replace(self.project.scene,
                                    texture=dataclasses.replace(tex, variation=variation))
        self.editor.edit(dataclasses.replace(self.project, scene=scene),
                         f"Texture variation {'on' if on else 'off'}")

    def _kind_changed(self) -> None:
        if self.kind.currentData() == "image":
            if not self._choose():
                self.refresh()
        else:
            self._set_source(m.ProceduralTexture("grass", 1, 0.01), "Texture: procedural")

    def _choose(self) -> bool:
        path, _ = QFileDialog.getOpenFileName(
            self, "Texture image", str(self.editor.document.base_dir),
            "images (*.png *.jpg *.jpeg *.tif *.tiff)")
        if path:
            self._set_source(m.ImageTexture(self.relative_path(path)),
                             f"Texture image {Path(path).name}")
        return bool(path)
