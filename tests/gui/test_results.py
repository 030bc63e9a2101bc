"""Results panel: a cloud coloured by its signed distance to the true terrain."""

from __future__ import annotations

import numpy as np
import pytest

from designer.gui.state import edits
from tests.gui.cloud_helpers import cloud_seen_from_above, point_on_screen
from tests.gui.helpers import add_hills_and_flight, problems, wait_idle, write_xyz_ply

pytestmark = pytest.mark.gui


def test_cloud_colours_follow_signed_distances(qtbot, window, tmp_path):
    w = window
    add_hills_and_flight(w)
    wait_idle(qtbot, w)
    assert w.file_actions.save_to(tmp_path / "hills.xml"), problems(w)
    hf = w.sync.terrain.heightfield

    # Points over grid nodes, lifted by a known offset: west half below the ground
    # (−), east half above (+), growing towards the edges.
    rng = np.random.default_rng(5)
    x = rng.uniform(-45, 45, 4000).round()
    y = rng.uniform(-45, 45, 4000).round()
    offset = np.where(x < 0, -1.0, 1.0) * (0.01 + 0.1 * np.abs(x) / 45)
    xyz = np.column_stack([x, y, hf.height_at(x, y) + offset])
    cloud = tmp_path / "cloud.ply"
    write_xyz_ply(cloud, xyz)

    results = w.panels["Results"]
    results.open_cloud(cloud)
    wait_idle(qtbot, w)
    r = results.result
    assert r is not None and len(r.points_world) == 4000
    d = r.distances_m
    # designer.evaluate's distance: the sign of the offset, at most its size (on a slope
    # the perpendicular distance is shorter than the vertical offset)
    assert np.all(np.sign(d) == np.sign(offset))
    assert np.all(np.abs(d) <= np.abs(offset) + 1e-9)
    assert np.all(np.abs(d) >= 0.5 * np.abs(offset))
    assert results.stats.rowCount() > 5
    assert results.state.text().startswith("cloud.ply: 4,000 points")

    # What the view draws: these distances as scalars, a diverging map centred on 0.
    drawn = w.view.layer_data("cloud")
    np.testing.assert_allclose(np.asarray(drawn["signed distance (mm)"]), 1000 * d)
    lut = w.view.cloud_lookup_table()
    lo, hi = lut.scalar_range
    assert lo == pytest.approx(-hi) and hi == pytest.approx(1000 * r.limit_m)  # mm
    colours = np.array([lut.map_value(1000 * v) for v in d])[:, :3]
    above, below = d > 0, d < 0
    assert np.all(colours[above, 0] > colours[above, 2])   # red above the ground
    assert np.all(colours[below, 2] > colours[below, 0])   # blue below
    # darker (further from the white of zero) the larger |d|, on both sides
    for side in (above, below):
        lightness = colours[side].sum(axis=1)[np.argsort(np.abs(d[side]))]
        assert np.all(np.diff(lightness) <= 1e-9)
        assert lightness[0] > lightness[-1] + 0.5
    assert "signed distance (mm)" in w.view.plotter.scalar_bars

    # And on screen: seen from above, points east of the centre are red, west blue.
    cloud_seen_from_above(w)
    image = w.view.plotter.screenshot(return_img=True)
    reds = blues = 0
    for k in np.flatnonzero(np.abs(offset) > 0.08)[:200]:
        at = point_on_screen(w, xyz[k])
        pixel = image[at.y(), at.x()].astype(int)
        if offset[k] > 0:
            reds += pixel[0] > pixel[2] + 40
        else:
            blues += pixel[2] > pixel[0] + 40
    n_pos = np.count_nonzero(offset[np.flatnonzero(np.abs(offset) > 0.08)[:200]] > 0)
    assert reds >= 0.9 * n_pos
    assert blues >= 0.9 * (200 - n_pos)


def test_gcp_error_table(qtbot, window, tmp_path):
    w = window
    project = edits.add_target(edits.add_target(w.document.project, 10.0, 5.0), -20.0, 15.0,
                               role="check")
    w.editor.edit(project, "two GCPs")
    wait_idle(qtbot, w)
    truth = w.sync.targets.true_xyz
    estimates = tmp_path / "gcp_residuals.csv"
    estimates.write_text("id,role,X,Y,Z\n"
                         f"GCP01,control,{truth[0, 0] + 0.01},{truth[0, 1]},{truth[0, 2]}\n"
                         f"GCP02,check,{truth[1, 0]},{truth[1, 1] - 0.02},"
                         f"{truth[1, 2] + 0.03}\n")
    results = w.panels["Results"]
    results.open_residuals(estimates)
    wait_idle(qtbot, w)
    table = results.gcp_table
    assert table.rowCount() == 2
    assert [table.item(0, c).text() for c in range(6)] == [
        "GCP01", "control", "+10.0", "+0.0", "+0.0", "10.0"]
    assert table.item(1, 3).text() == "-20.0" and table.item(1, 4).text() == "+30.0"
    assert "check (1): RMSE XY 20.0 mm, Z 30.0 mm" in results.rmse.text()
