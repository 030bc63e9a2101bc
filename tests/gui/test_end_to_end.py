"""The whole loop with the mouse and the panels: design a survey from scratch, render it
with Cycles, reconstruct it with COLMAP and look at the cloud coloured by its error.

New project → procedural terrain → 5 GCPs clicked in the 3D view → camera preset →
flight → save → render (Render panel: ``designer render`` in other processes) →
reconstruct (Results panel: ``designer reconstruct`` and ``designer compare`` in other
processes) → the cloud in the view, coloured by its signed distance to the true surface.

Kept small as tests/sfm keeps its survey: 600 × 400 px images (a6000 at resolution
scale 0.1, GSD 7.3 cm at 30 m), draft quality, a dozen images, one texture tile of 3 cm
texels (half the GSD, so SIFT finds repeatable features) over the whole terrain.
"""

from __future__ import annotations

import numpy as np
import pytest
from PySide6.QtCore import Qt
from PySide6.QtWidgets import QDoubleSpinBox, QSpinBox

from designer.gui.state.reconstruct_job import STAGES
from tests.gui.helpers import design_example, field, problems, set_field, wait_idle

pytestmark = [pytest.mark.gui, pytest.mark.blender, pytest.mark.slow]

#: the central 40 m × 40 m of the 100 m terrain
AREA = ((-20.0, -20.0), (20.0, -20.0), (20.0, 20.0), (-20.0, 20.0))


def _type_area(area_table, vertices) -> None:
    for r, (x, y) in enumerate(vertices):
        area_table.item(r, 0).setText(f"{x:.3f}")
        area_table.item(r, 1).setText(f"{y:.3f}")


def test_design_render_reconstruct_and_inspect_the_error(qtbot, window, tmp_path):
    pytest.importorskip("bpy")
    pytest.importorskip("pycolmap")
    w = window
    design_example(qtbot, w)  # new project, hills, 5 GCPs clicked, a6000, a grid flight

    # A small flight: 30 m above ground, 60/50 % overlap over the centre.
    flight = w.panels["Flight"]
    w.docks["Flight"].raise_()
    set_field(qtbot, field(w, QDoubleSpinBox, "trajectory.flight_plan.altitude_agl_m"), "30")
    set_field(qtbot, field(w, QDoubleSpinBox, "trajectory.flight_plan.front_overlap_percent"), "60")
    set_field(qtbot, field(w, QDoubleSpinBox, "trajectory.flight_plan.side_overlap_percent"), "50")
    _type_area(flight.area_table, AREA)
    # The rendered images: draft quality at a tenth of the a6000's 6000 × 4000 px.
    w.docks["Render"].raise_()
    set_field(qtbot, field(w, QDoubleSpinBox, "render.resolution_scale"), "0.1")
    set_field(qtbot, field(w, QSpinBox, "render.workers"), "2")
    # Texture texels of 3 cm (half the rendered GSD), one tile over the whole terrain: a
    # repeated tile would give SIFT the same features in several places.
    w.docks["Texture"].raise_()
    set_field(qtbot, field(w, QDoubleSpinBox, "scene.texture.source.texel_size_m"), "0.03")
    set_field(qtbot, field(w, QSpinBox, "scene.texture.repeat_X"), "1")
    set_field(qtbot, field(w, QSpinBox, "scene.texture.repeat_Y"), "1")
    wait_idle(qtbot, w)
    project = w.document.project
    assert project.trajectory.flight_plan.area == AREA
    assert project.render.preset == "draft" and project.render.resolution_scale == 0.1
    n = w.sync.stations.n_images
    assert 6 <= n <= 20, n
    # The Flight panel gives the GSD of the full-size camera and of the rendered image.
    assert "rendered image (600 × 400 px): GSD 7.34 cm" in flight.calc_label.text()

    assert w.file_actions.save_to(tmp_path / "survey.xml"), problems(w)

    # Render through the Render panel.
    render = w.panels["Render"]
    qtbot.mouseClick(render.start_button, Qt.MouseButton.LeftButton)
    qtbot.waitUntil(lambda: render.start_button.isEnabled(), timeout=400_000)
    wait_idle(qtbot, w)
    assert render.state.text().startswith(f"done: {n} images"), render.log.toPlainText()

    # Reconstruct through the Results panel: two commands in other processes.
    results = w.panels["Results"]
    w.docks["Results"].raise_()
    assert f"{n} rendered images" in results.survey_label.text()
    stages = []
    results.run.stage.connect(lambda index, _title: stages.append(index))
    # Cancel stops COLMAP at once (the window does not wait for its stage to end) …
    qtbot.mouseClick(results.reconstruct_button, Qt.MouseButton.LeftButton)
    qtbot.waitUntil(lambda: stages == [0], timeout=60_000)
    qtbot.mouseClick(results.cancel_button, Qt.MouseButton.LeftButton)
    qtbot.waitUntil(lambda: results.reconstruct_button.isEnabled(), timeout=10_000)
    assert results.stage_label.text() == "cancelled"
    assert not results.run.running and results.result is None
    assert not (results.job.out_dir / "cloud.ply").exists()
    # … and a new run starts afresh.
    stages.clear()
    qtbot.mouseClick(results.reconstruct_button, Qt.MouseButton.LeftButton)
    assert not results.reconstruct_button.isEnabled() and results.cancel_button.isEnabled()
    qtbot.waitUntil(lambda: results.reconstruct_button.isEnabled(), timeout=400_000)
    assert results.stage_label.text().startswith("done:"), results.log.toPlainText()
    qtbot.waitUntil(lambda: results.result is not None, timeout=60_000)
    wait_idle(qtbot, w)
    assert stages == sorted(stages) and stages[0] == 0 and stages[-1] == len(STAGES) - 1
    assert results.progress.value() == len(STAGES)
    job = results.job
    assert (job.out_dir / "cloud.ply").is_file()
    assert (job.compare_dir / "report.html").is_file()

    # The cloud: COLMAP's points with designer.evaluate's distances to the saved truth.
    r = results.result
    from designer.evaluate import read_point_cloud, reference_mesh, signed_distances

    cloud = read_point_cloud(job.out_dir / "cloud.ply")
    assert len(r.points_world) == len(cloud.xyz) > 1000
    np.testing.assert_allclose(r.points_world, cloud.xyz)
    truth = reference_mesh(tmp_path / "survey.xml")
    np.testing.assert_allclose(r.distances_m, signed_distances(
        cloud.xyz, (truth.vertices, truth.faces)), atol=1e-9)
    # With the true poses the surface is found without bias and with a scatter (NMAD)
    # of a fraction of the GSD (7.3 cm), even from draft renders (4 samples per pixel).
    d = r.distances_m
    assert abs(np.median(d)) < 0.01
    assert 1.4826 * np.median(np.abs(d - np.median(d))) < 0.04
    assert results.stats.rowCount() > 5
    assert results.gcp_table.rowCount() >= 1

    # Drawn in the view coloured by those distances: red above, blue below, darker
    # further from zero, on a symmetric scale.
    drawn = w.view.layer_data("cloud")
    np.testing.assert_allclose(np.asarray(drawn["signed distance (mm)"]), 1000 * d)
    lut = w.view.cloud_lookup_table()
    lo, hi = lut.scalar_range
    assert lo == pytest.approx(-hi) and hi == pytest.approx(1000 * r.limit_m)  # mm
    colours = np.array([lut.map_value(1000 * v) for v in d])[:, :3]
    above, below = 1000 * d > 0.1 * hi, 1000 * d < -0.1 * hi
    assert above.sum() > 100 and below.sum() > 100
    assert np.all(colours[above, 0] > colours[above, 2])
    assert np.all(colours[below, 2] > colours[below, 0])
    for side in (d > 0, d < 0):
        lightness = colours[side].sum(axis=1)[np.argsort(np.abs(d[side]))]
        assert np.all(np.diff(lightness) <= 1e-9)
        assert lightness[0] > lightness[-1] + 0.5
    assert "signed distance (mm)" in w.view.plotter.scalar_bars

    # On screen: seen from above with the cloud alone, the reddest and the bluest pixels
    # lie where the points furthest above and below the truth are.
    for layer in ("terrain", "targets", "frusta", "footprints", "flight", "area"):
        w.view.set_layer_visible(layer, False)
    w.view.view_top()
    w.view.render_now()
    image = w.view.plotter.screenshot(return_img=True).astype(int)
    ren = w.view.plotter.renderer
    h = image.shape[0]
    redness = []
    for k in np.r_[np.argsort(d)[:40], np.argsort(d)[-40:]]:
        ren.SetWorldPoint(*(r.points_world[k] - w.view.offset), 1.0)
        ren.WorldToDisplay()
        u, v, _ = ren.GetDisplayPoint()
        pixel = image[h - 1 - round(v), round(u)]
        redness.append(pixel[0] - pixel[2])
    below, above = np.array(redness[:40]), np.array(redness[40:])
    assert np.median(above) > 40 and np.median(below) < -40
