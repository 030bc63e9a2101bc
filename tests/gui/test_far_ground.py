"""Far ground in the 3D view (issue 53, finding 11): beyond the lighter ring of
surroundings the view ended at a ridge against the sky; a plain, darker skirt continues
the ground from the rendered terrain's border to the horizon (no image sees it), and
goes with the surroundings when they are none."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from designer.core.heightfield import Heightfield
from designer.gui.state.view_geometry import FAR_GROUND_REACH, far_ground_display
from designer.project import template, write_project
from tests.gui.helpers import problems, wait_idle


def test_the_far_ground_starts_at_the_border_and_reaches_out():
    x = np.linspace(0.0, 100.0, 51)
    hf = Heightfield(0.0, 0.0, 2.0, 2.0, np.add.outer(0.1 * x, 0.05 * x))  # a slope
    far = far_ground_display(hf)
    n = len(far.points_world) // 2
    inner, outer = far.points_world[:n], far.points_world[n:]
    # the inner edge on the border, at the terrain's heights there
    on_border = ((np.isclose(inner[:, 0], 0) | np.isclose(inner[:, 0], 100))
                 | (np.isclose(inner[:, 1], 0) | np.isclose(inner[:, 1], 100)))
    assert on_border.all()
    np.testing.assert_allclose(inner[:, 2], hf.height_at_clamped(inner[:, 0], inner[:, 1]))
    # the outer edge FAR_GROUND_REACH half-sizes further out, level
    d = np.linalg.norm(outer[:, :2] - inner[:, :2], axis=1)
    np.testing.assert_allclose(d, FAR_GROUND_REACH * 50.0)
    assert np.ptp(outer[:, 2]) == 0
    assert far.faces.max() < len(far.points_world) and len(far.faces) == 2 * n


@pytest.mark.gui
def test_the_view_draws_far_ground_with_the_surroundings_only(qtbot, window, tmp_path):
    w = window
    project = template("survey").project
    path = tmp_path / "survey.xml"
    write_project(project, path)
    assert w.file_actions.open(path), problems(w)
    wait_idle(qtbot, w)
    assert w.view.has_layer("surroundings") and w.view.has_layer("surroundings:far")
    ring = np.asarray(w.view.layer_data("surroundings").points)
    far = np.asarray(w.view.layer_data("surroundings:far").points)
    assert np.ptp(far[:, 0]) > 2 * np.ptp(ring[:, 0])
    # none: the renders end at the extent, and so does the drawn ground
    terrain = dataclasses.replace(project.scene.terrain,
                                  surroundings="none")
    w.editor.edit(dataclasses.replace(project, scene=dataclasses.replace(
        project.scene, terrain=terrain)), "surroundings none")
    wait_idle(qtbot, w)
    assert not w.view.has_layer("surroundings:far")
