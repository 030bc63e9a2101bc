"""Results that resist outliers (problem 6 of the user test): one point 1.4 km below
the terrain must not make the summary or the histogram useless; the colour range is the
user's to set; a click on a point reads its distance; the last reconstruction comes
back with the project."""

from __future__ import annotations

import numpy as np
import pytest
from PySide6.QtCore import Qt

from designer.evaluate.writers import write_distances_ply
from designer.gui.state.reconstruct_job import ReconstructJob
from tests.gui.cloud_helpers import cloud_seen_from_above, isolated_point, point_on_screen
from tests.gui.helpers import (
    add_hills_and_flight,
    cloud_with_outlier,
    problems,
    wait_idle,
)

pytestmark = pytest.mark.gui


def test_one_outlier_does_not_sway_the_summary(qtbot, window, tmp_path):
    w = window
    add_hills_and_flight(w)
    wait_idle(qtbot, w)
    path, xyz = cloud_with_outlier(w, tmp_path)
    results = w.panels["Results"]
    w.docks["Results"].raise_()
    results.open_cloud(path)
    wait_idle(qtbot, w)
    rows = {results.stats.item(r, 0).text(): results.stats.item(r, 1).text()
            for r in range(results.stats.rowCount())}
    first = [results.stats.item(r, 0).text() for r in range(4)]
    assert first[:3] == ["points", "median", "NMAD"]
    # NMAD ≈ the 10 mm σ (slopes make the perpendicular distance a little shorter)
    nmad_mm = float(rows["NMAD"].split()[0])
    assert 6.0 < nmad_mm < 11.0
    outliers = next(k for k in rows if k.startswith("outliers"))
    assert rows[outliers].startswith("1 ")
    assert "5 × NMAD" in outliers
    assert float(rows["RMSE without outliers"].split()[0]) < 11.0
    assert "RMSE, all points" in rows  # still there, but after the robust figures
    # the outlier is listed with its distance and place
    assert results.outlier_table.rowCount() == 1
    assert results.state.text().endswith("; 1 outlier"), results.state.text()
    assert results.outlier_label.text() == "1 outlier:"
    assert results.outlier_table.item(0, 0).text().startswith("-1")
    assert float(results.outlier_table.item(0, 1).text()) == pytest.approx(xyz[123, 0])
    # colours and histogram: a range of centimetres, the outlier counted as clipped
    r = results.result
    assert 0.01 < r.limit_m < 0.05
    lo, hi = results.histogram_range_mm
    assert (lo, hi) == pytest.approx((-1000 * r.limit_m, 1000 * r.limit_m))
    below = int(np.sum(r.distances_m < -r.limit_m))
    assert below >= 1 and f"outside: {below:,} below" in results.clipped_label.text()
    ax = results.figure.axes[0]
    assert ax.get_xlim() == pytest.approx((lo, hi))
    assert len(ax.patches) > 20 and max(p.get_height() for p in ax.patches) < 0.2 * len(xyz)

    # the range control: typed, it recolours the cloud and redraws the histogram
    box = results.range_spin
    box.setFocus()
    box.selectAll()
    qtbot.keyClicks(box.lineEdit(), "5")
    qtbot.keyClick(box.lineEdit(), Qt.Key.Key_Return)
    lut = w.view.cloud_lookup_table()
    assert lut.scalar_range == pytest.approx((-5.0, 5.0))  # mm, as the histogram
    assert results.figure.axes[0].get_xlim() == pytest.approx((-5.0, 5.0))
    below = int(np.sum(r.distances_m < -0.005))
    assert f"{below:,} below" in results.clipped_label.text()


def test_click_on_a_point_reads_its_distance(qtbot, window, tmp_path):
    w = window
    add_hills_and_flight(w)
    wait_idle(qtbot, w)
    path, _xyz = cloud_with_outlier(w, tmp_path, n=400)
    results = w.panels["Results"]
    results.open_cloud(path)
    wait_idle(qtbot, w)
    cloud_seen_from_above(w)
    r = results.result
    k = isolated_point(w, r.points_world)
    pos = point_on_screen(w, r.points_world[k])
    qtbot.mouseClick(w.view.plotter, Qt.MouseButton.LeftButton, pos=pos)
    expected = f"{1000 * r.distances_m[k]:+.1f} mm"
    assert expected in results.picked.text()
    assert f"E {r.points_world[k, 0]:.3f}" in results.picked.text()
    assert expected in w.statusBar().currentMessage()


def test_last_reconstruction_reopens_with_the_project(qtbot, window, tmp_path):
    w = window
    add_hills_and_flight(w)
    wait_idle(qtbot, w)
    project_path = tmp_path / "hills.xml"
    assert w.file_actions.save_to(project_path), problems(w)
    folder = w.panels["Results"].survey_dir()
    job = ReconstructJob(project_path, folder, "known-poses")
    hf = w.sync.terrain.heightfield
    xyz = np.column_stack([np.arange(-20.0, 20.0), np.zeros(40),
                           hf.height_at(np.arange(-20.0, 20.0), np.zeros(40)) + 0.02])
    job.compare_dir.mkdir(parents=True)
    write_distances_ply(job.distances_ply, xyz, np.full(40, 0.02))
    w.panels["Results"].clear()
    assert w.file_actions.new(None)
    wait_idle(qtbot, w)
    assert w.panels["Results"].result is None and not w.view.has_layer("cloud")
    assert w.open_project(project_path)
    wait_idle(qtbot, w)
    r = w.panels["Results"].result
    assert r is not None and len(r.points_world) == 40
    assert r.path == job.distances_ply
    assert w.view.has_layer("cloud")
