"""Scene objects (mesh files placed in the world) are drawn in the 3D view."""

from __future__ import annotations

import numpy as np
import pytest

from designer.gui.qt.scene_view import OBJECT_COLOUR
from designer.gui.state import edits
from designer.gui.state.view_geometry import shade_rgb
from designer.project import model as m
from tests.gui.helpers import wait_idle

pytestmark = pytest.mark.gui


def _bounds_world(w) -> np.ndarray:
    mesh = w.view.layer_data("objects")
    assert mesh is not None, "no objects drawn"
    points = np.asarray(mesh.points, dtype=float) + w.view.offset
    return np.array([points.min(axis=0), points.max(axis=0)])


def test_validation_cube_is_drawn_where_its_placement_puts_it(qtbot, window):
    w = window
    assert w.file_actions.new("validation-cube")  # cube.obj: unit cube scaled 4×
    wait_idle(qtbot, w)
    assert w.view.layer_data("objects").n_cells == 12  # six squares, two triangles each
    np.testing.assert_allclose(_bounds_world(w), [[-2, -2, 0], [2, 2, 4]], atol=1e-5)

    # An edit of the placement moves (and turns) it; undo puts it back.
    project = w.document.project
    placement = m.Placement(m.Point3(5.0, -3.0, 1.0), 0.0, 0.0, 45.0, scale=2.0)
    w.editor.edit(edits.replace_path(project, "scene.objects[0].placement", placement),
                  "move the cube")
    wait_idle(qtbot, w)
    half = np.sqrt(2.0)  # a 2 m square turned by 45°: its corners on the axes
    np.testing.assert_allclose(_bounds_world(w), [[5 - half, -3 - half, 1],
                                                  [5 + half, -3 + half, 3]], atol=1e-5)
    w.undo_stack.undo()
    wait_idle(qtbot, w)
    np.testing.assert_allclose(_bounds_world(w), [[-2, -2, 0], [2, 2, 4]], atol=1e-5)

    # On screen, from above: the cube's top face in its colour under the project's sun.
    for layer in ("targets", "frusta", "footprints", "flight", "area"):
        w.view.set_layer_visible(layer, False)
    w.view.view_top()
    w.view.render_now()
    image = w.view.plotter.screenshot(return_img=True).astype(int)
    ren = w.view.plotter.renderer
    ren.SetWorldPoint(*(np.array([0.0, 0.0, 4.0]) - w.view.offset), 1.0)
    ren.WorldToDisplay()
    u, v, _ = ren.GetDisplayPoint()
    top = image[image.shape[0] - 1 - round(v), round(u), :3]
    expected = shade_rgb(np.array([1.0]), OBJECT_COLOUR)[0]  # flat face in full sun
    assert np.abs(top - expected).max() <= 3, (top, expected)
    # and hiding the layer shows the ground there instead
    w.view.set_layer_visible("objects", False)
    w.view.render_now()
    image = w.view.plotter.screenshot(return_img=True).astype(int)
    assert np.abs(image[image.shape[0] - 1 - round(v), round(u), :3] - expected).max() > 3


def test_a_missing_object_file_is_a_message_not_a_crash(qtbot, window):
    w = window
    project = w.document.project
    obj = m.SceneObject("box", "does-not-exist.obj",
                        m.Placement(m.Point3(0.0, 0.0, 0.0), 0.0, 0.0, 0.0))
    w.editor.edit(edits.replace_path(project, "scene.objects", (obj,)), "add an object")
    wait_idle(qtbot, w)
    assert w.view.layer_data("objects") is None
    assert "does-not-exist.obj" in w.sync.errors["objects"]
