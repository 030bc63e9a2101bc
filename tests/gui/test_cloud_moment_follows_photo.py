"""A photo selected anywhere in the window — a camera station clicked in the 3D view, a
render thumbnail clicked in the Render panel — moves the cloud shadows the view draws to
that photo's moment, while the Lighting panel's "drawn at" follows the selected photo
(its default); a moment the user chose there explicitly stays."""

from __future__ import annotations

import numpy as np
import pytest
from PySide6.QtCore import Qt
from PySide6.QtTest import QTest

from designer.core.layout import images_dir
from designer.gui.state import derived, edits
from designer.project import model as m
from tests.gui.cloud_helpers import point_on_screen
from tests.gui.cloud_shadow_helpers import cloudy_hut
from tests.gui.helpers import (
    choose_entry,
    open_panel,
    problems,
    render_blank_frames,
    wait_idle,
)

pytestmark = pytest.mark.gui


def _cloudy_flight(qtbot, w) -> None:
    project = edits.ensure_flight_plan(cloudy_hut())
    project = edits.replace_path(project, "trajectory.time_line",
                                 m.TimeLine("2026-06-21T09:30:00Z", speed_m_s=5.0, turn_s=8.0))
    w.editor.edit(project, "a cloudy flight over a hut")
    wait_idle(qtbot, w)


def _drawn(w) -> np.ndarray:
    return np.asarray(w.view.layer_data("cloud-shadows").point_data["shadow"])[:, 3]


def _expected(w, time_s: float) -> np.ndarray:
    preview = derived.compute_cloud_preview(w.document.project, w.sync.terrain,
                                            time_s=time_s)
    return np.round(255 * preview.darkening)


def _time_s(w, k: int) -> float:
    from designer.survey.timeline import project_station_times

    return project_station_times(w.document.project, w.sync.stations.stations)[k].time_s


def _lone_station(w, among) -> tuple[int, object]:
    """Of the stations ``among`` in the view, the one drawn farthest from every other
    station, and the widget pixel where its perspective centre is drawn."""
    C = w.sync.stations.C_world
    shown = w.view.in_view(C)
    among = [k for k in among if shown[k]]
    assert among, "none of the stations is in the view"
    px = np.array([[p.x(), p.y()] for p in (point_on_screen(w, c) for c in C)], float)
    gaps = [np.delete(np.hypot(*(px - px[k]).T), k).min() for k in among]
    k = int(among[int(np.argmax(gaps))])
    assert max(gaps) > 6, "the stations are drawn on top of each other"
    return k, point_on_screen(w, C[k])


def test_clicking_a_station_draws_the_shadows_at_its_photo(qtbot, window):
    w = window
    _cloudy_flight(qtbot, w)
    box = open_panel(w, "Lighting").cloud_moment
    assert box.currentText().startswith("the selected photo")
    start = _expected(w, 0.0)
    np.testing.assert_allclose(_drawn(w), start, atol=1)  # no photo selected yet

    n = len(w.sync.stations.stations)
    k, pixel = _lone_station(w, range(n // 2, n))
    qtbot.mouseClick(w.view.plotter, Qt.MouseButton.LeftButton, pos=pixel)
    wait_idle(qtbot, w)
    assert w.sync.selected_photo == k
    name = w.sync.stations.stations[k].image_name
    t = _time_s(w, k)
    assert t > 30
    assert box.currentText() == f"the selected photo: {name} ({t:.0f} s)"
    assert name in w.statusBar().currentMessage()
    late = _expected(w, t)
    assert np.abs(late - start).max() > 100  # the shadows moved
    np.testing.assert_allclose(_drawn(w), late, atol=1)

    # the flight's start chosen explicitly: another photo clicked leaves it
    choose_entry(qtbot, w, box, "the flight's start")
    wait_idle(qtbot, w)
    np.testing.assert_allclose(_drawn(w), start, atol=1)
    other, pixel = _lone_station(w, range(n // 4, n // 2))
    qtbot.mouseClick(w.view.plotter, Qt.MouseButton.LeftButton, pos=pixel)
    wait_idle(qtbot, w)
    assert w.sync.selected_photo == other
    assert box.currentText() == "the flight's start"
    np.testing.assert_allclose(_drawn(w), start, atol=1)


def test_clicking_a_thumbnail_draws_the_shadows_at_its_photo(qtbot, window, monkeypatch,
                                                              tmp_path):
    w = window
    _cloudy_flight(qtbot, w)
    assert w.file_actions.save_to(tmp_path / "cloudy.xml"), problems(w)
    stations = w.sync.stations
    n = len(stations.stations)
    lone, pixel = _lone_station(w, range(n // 4, n // 2))
    chosen = (lone, n - 2)
    frames = [{"index": k, "name": stations.image_names[k], "width": 60, "height": 40}
              for k in chosen]
    panel = render_blank_frames(qtbot, w, monkeypatch, tmp_path, frames)
    assert sorted(p.name for p in images_dir(tmp_path / "output").iterdir()) == sorted(
        f["name"] for f in frames)
    wait_idle(qtbot, w)
    np.testing.assert_allclose(_drawn(w), _expected(w, 0.0), atol=1)

    for k in chosen:
        item = next(panel.thumbs.item(i) for i in range(panel.thumbs.count())
                    if panel.thumbs.item(i).data(Qt.ItemDataRole.UserRole) == k)
        panel.thumbs.scrollToItem(item)
        qtbot.wait(50)
        centre = panel.thumbs.viewport().mapTo(w, panel.thumbs.visualItemRect(item).center())
        QTest.mouseClick(w.windowHandle(), Qt.MouseButton.LeftButton,
                         Qt.KeyboardModifier.NoModifier, centre)
        wait_idle(qtbot, w)
        assert w.sync.selected_photo == k
        np.testing.assert_allclose(_drawn(w), _expected(w, _time_s(w, k)), atol=1)
    box = w.panels["Lighting"].cloud_moment
    assert stations.image_names[chosen[-1]] in box.currentText()

    # the other way: the station clicked in the view makes its thumbnail the current one
    assert panel.thumbs.currentItem().data(Qt.ItemDataRole.UserRole) == chosen[-1]
    qtbot.mouseClick(w.view.plotter, Qt.MouseButton.LeftButton, pos=pixel)
    wait_idle(qtbot, w)
    assert w.sync.selected_photo == lone
    assert panel.thumbs.currentItem().data(Qt.ItemDataRole.UserRole) == lone
    np.testing.assert_allclose(_drawn(w), _expected(w, _time_s(w, lone)), atol=1)


def test_a_photo_chosen_in_drawn_at_is_selected_everywhere(qtbot, window, monkeypatch,
                                                           tmp_path):
    """A photo chosen in the Lighting panel's "drawn at" is the selected photo: its
    station marked in the 3D view, its thumbnail the current one, named in the status
    bar; the list keeps the photo chosen (it does not go back to "the selected photo")."""
    w = window
    _cloudy_flight(qtbot, w)
    assert w.file_actions.save_to(tmp_path / "cloudy.xml"), problems(w)
    stations = w.sync.stations
    n = len(stations.stations)
    chosen, other = 2, n - 2
    frames = [{"index": k, "name": stations.image_names[k], "width": 60, "height": 40}
              for k in (chosen, other)]
    render = render_blank_frames(qtbot, w, monkeypatch, tmp_path, frames)
    wait_idle(qtbot, w)
    assert w.sync.selected_photo is None
    assert render.thumbs.currentItem() is None

    box = open_panel(w, "Lighting").cloud_moment
    name = stations.image_names[chosen]
    entry = f"{name} ({_time_s(w, chosen):.0f} s after take-off)"
    choose_entry(qtbot, w, box, entry)
    wait_idle(qtbot, w)
    assert w.sync.selected_photo == chosen
    np.testing.assert_allclose(
        w.view.layer_data("selected-station").points,
        w.view.local(stations.C_world[chosen]), atol=1e-3)
    assert render.thumbs.currentItem().data(Qt.ItemDataRole.UserRole) == chosen
    assert name in w.statusBar().currentMessage()
    assert box.currentText() == entry
    assert w.sync.cloud_moment == chosen
    np.testing.assert_allclose(_drawn(w), _expected(w, _time_s(w, chosen)), atol=1)

    # another photo chosen there moves the selection with it
    entry = f"{stations.image_names[other]} ({_time_s(w, other):.0f} s after take-off)"
    choose_entry(qtbot, w, box, entry)
    wait_idle(qtbot, w)
    assert w.sync.selected_photo == other
    assert render.thumbs.currentItem().data(Qt.ItemDataRole.UserRole) == other
    assert box.currentText() == entry
    np.testing.assert_allclose(_drawn(w), _expected(w, _time_s(w, other)), atol=1)

    # the flight's start chosen keeps the selected photo
    choose_entry(qtbot, w, box, "the flight's start")
    wait_idle(qtbot, w)
    assert w.sync.selected_photo == other
    np.testing.assert_allclose(_drawn(w), _expected(w, 0.0), atol=1)
