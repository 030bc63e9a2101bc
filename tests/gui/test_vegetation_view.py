"""Plants in the 3D view: drawn where the renderer places them, in their colours, in a
real window; the View menu hides them; switching vegetation off removes them."""

from __future__ import annotations

import numpy as np
import pytest
from PySide6.QtCore import Qt
from PySide6.QtWidgets import QDoubleSpinBox

from designer.gui.state.view_geometry import flat_lit_rgb
from designer.scene.build import build_heightfield, build_terrain_mesh
from designer.scene.surfaces import Ground, merge_triangles
from designer.scene.vegetation import KIND_ALBEDO, WOOD_ALBEDO, vegetation_mesh_world
from tests.gui.helpers import field, open_panel, set_field, wait_idle

pytestmark = pytest.mark.gui


def _renderer_plants(project, base_dir):
    """The plants as the renderer's geometry (the DSM layer) builds them, upright."""
    hf = build_heightfield(project.scene.terrain, base_dir, project.crs)
    origin = np.array([project.origin.E0, project.origin.N0, project.origin.H0])
    mesh = build_terrain_mesh(project.scene.terrain, hf, base_dir, origin)
    return merge_triangles(vegetation_mesh_world(project, base_dir, Ground(hf, mesh), None))


def test_plants_are_drawn_where_the_renderer_places_them(qtbot, window):
    w = window
    panel = open_panel(w, "Vegetation")
    panel.enabled.setChecked(True)  # a group of shrubs
    qtbot.mouseClick(panel.add_buttons["tree"], Qt.MouseButton.LeftButton)
    set_field(qtbot, field(panel, QDoubleSpinBox, "Plant density"), "0.01")
    wait_idle(qtbot, w)
    project = w.document.project
    assert [g.kind for g in project.scene.vegetation.plants] == ["shrub", "tree"]

    drawn = w.view.layer_data("vegetation")
    vertices, faces = _renderer_plants(project, w.document.base_dir)
    assert len(faces) > 0 and drawn.n_cells == len(faces)
    # the same triangles, corner for corner (the view holds float32 local coordinates)
    corners = np.asarray(drawn.points)[drawn.faces.reshape(-1, 4)[:, 1:]] + w.view.offset
    assert np.abs(corners - vertices[faces]).max() < 2e-3
    # foliage in each kind's colour, trunks in the wood colour, lit as flat ground
    colours = {tuple(c) for c in np.asarray(drawn.cell_data["rgb"])}
    expected = {tuple(flat_lit_rgb(np.array([a]))[0])
                for a in (KIND_ALBEDO["shrub"], KIND_ALBEDO["tree"], WOOD_ALBEDO)}
    assert colours == expected
    assert w.sync.vegetation.n_plants > 0

    # View → Plants hides the layer, and shows it again
    action = next(a for a in w.menuBar().actions() if a.text() == "&View").menu()
    plants = next(a for a in action.actions() if a.text() == "Plants")
    plants.trigger()
    assert not w.view.plotter.actors["vegetation"].GetVisibility()
    plants.trigger()
    assert w.view.plotter.actors["vegetation"].GetVisibility()

    panel.enabled.setChecked(False)
    wait_idle(qtbot, w)
    assert not w.view.has_layer("vegetation")
