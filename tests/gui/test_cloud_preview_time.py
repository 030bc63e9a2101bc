"""The 3D view's cloud shadows at a moment of the flight: drifted by the wind as the
render drifts them (designer.scene.cloud_shadows)."""

from __future__ import annotations

import numpy as np
import pytest

from designer.gui.state import derived, edits
from designer.project import model as m
from tests.gui.cloud_shadow_helpers import cloudy_hut


def test_the_shadows_drift_by_the_wind_between_two_moments(tmp_path):
    project = cloudy_hut()
    terrain = derived.compute_terrain(project, tmp_path)
    early = derived.compute_cloud_preview(project, terrain, time_s=10.0)
    late = derived.compute_cloud_preview(project, terrain, time_s=11.0)
    np.testing.assert_array_equal(early.points_world, late.points_world)
    ny = len(np.unique(early.points_world[:, 1]))
    a, b = early.darkening.reshape(ny, -1), late.darkening.reshape(ny, -1)
    assert np.abs(a - b).max() > 0.3  # the shadows moved …
    # … 3.125 m east in 1 s: 8 grid steps (edge columns, blurred from outside, left out)
    np.testing.assert_allclose(b[:, 8 + 4:-4], a[:, 4:-8 - 4], atol=0.02)


@pytest.mark.gui
def test_the_view_draws_the_shadows_at_the_chosen_photo(qtbot, window, tmp_path):
    """The Lighting panel's "drawn at": the selected photo (none: the flight's start),
    then a photo chosen with the keyboard; the view's shadows are the render's at its
    time."""
    from PySide6.QtCore import Qt
    from PySide6.QtWidgets import QComboBox, QScrollArea

    from tests.gui.helpers import open_panel, wait_idle

    w = window
    project = edits.ensure_flight_plan(cloudy_hut())
    project = edits.replace_path(project, "trajectory.time_line",
                                 m.TimeLine("2026-06-21T09:30:00Z", speed_m_s=5.0, turn_s=8.0))
    w.editor.edit(project, "a cloudy flight over a hut")
    wait_idle(qtbot, w)
    terrain = w.sync.terrain

    def drawn() -> np.ndarray:
        return np.asarray(w.view._meshes["cloud-shadows"].point_data["shadow"])[:, 3]

    def expected(time_s: float) -> np.ndarray:
        preview = derived.compute_cloud_preview(w.document.project, terrain, time_s=time_s)
        return np.round(255 * preview.darkening)

    panel = open_panel(w, "Lighting")
    box = panel.findChild(QComboBox, "cloud-moment")
    assert box.currentText() == "the selected photo (none yet: the flight's start)"
    assert box.itemText(1) == "the flight's start"
    assert box.count() == 2 + len(w.sync.stations.stations)
    start_shadow = expected(0.0)
    np.testing.assert_allclose(drawn(), start_shadow, atol=1)

    panel.findChild(QScrollArea).ensureWidgetVisible(box)
    box.setFocus()
    for _ in range(21):
        qtbot.keyClick(box, Qt.Key.Key_Down)
    wait_idle(qtbot, w)
    assert w.sync.cloud_moment == w.sync.cloud_station == 19
    t = w.sync.cloud_time_s()
    assert t > 30 and f"({t:.0f} s after take-off)" in box.currentText()
    late_shadow = expected(t)
    assert np.abs(late_shadow - start_shadow).max() > 100  # the shadows moved
    np.testing.assert_allclose(drawn(), late_shadow, atol=1)
