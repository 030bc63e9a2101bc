"""Processing panel (the project's <processing>, edited through the undo stack) and the
dense products of a reconstruction in the Results panel."""

from __future__ import annotations

import json

import numpy as np
import pytest
from PySide6.QtCore import Qt
from PySide6.QtWidgets import QComboBox, QDoubleSpinBox, QLineEdit, QSpinBox

from designer.evaluate.writers import write_distances_ply
from designer.gui.state.reconstruct_job import ReconstructJob
from designer.project import load_project
from designer.sfm.settings import resolve_processing
from tests.gui.helpers import add_hills_and_flight, field, problems, set_field, wait_idle

pytestmark = pytest.mark.gui


def _choose(combo: QComboBox, data) -> None:
    combo.setCurrentIndex(combo.findData(data))


def test_processing_panel_edits_the_project(qtbot, window, tmp_path):
    w = window
    assert w.file_actions.new("survey")
    wait_idle(qtbot, w)
    panel = w.panels["Processing"]
    w.docks["Processing"].raise_()
    assert w.document.project.processing is None
    marking = field(w, QDoubleSpinBox, "processing.gcps.marking_sigma_px")
    assert not marking.isEnabled()  # no <processing>: nothing to edit

    qtbot.mouseClick(panel.enabled, Qt.MouseButton.LeftButton)
    p = w.document.project.processing
    assert p is not None and p.calibration.mode == "fixed" and p.dense == "none"
    assert marking.isEnabled()
    before = w.undo_stack.count()
    _choose(field(w, QComboBox, "processing.calibration.mode"), "radial")
    _choose(field(w, QComboBox, "processing.gcps.mode"), "bundle")
    set_field(qtbot, marking, "0.7")
    _choose(field(w, QComboBox, "processing.position_prior.mode"), "rtk")
    set_field(qtbot, field(w, QSpinBox, "processing.matching.max_features"), "3000")
    _choose(field(w, QComboBox, "processing.dense"), "cpu")
    p = w.document.project.processing
    assert (p.calibration.mode, p.gcps.mode, p.gcps.marking_sigma_px, p.position_prior.mode,
            p.matching.max_features, p.dense) == ("radial", "bundle", 0.7, "rtk", 3000, "cpu")
    assert w.undo_stack.count() == before + 6
    assert "0.02 m horizontal" in panel.prior_sigmas.text()  # the RTK defaults
    assert "dense cloud" in w.panels["Results"].settings_label.text()

    # invalid input is refused, the project keeps its value
    set_field(qtbot, marking, "60")
    assert w.document.project.processing.gcps.marking_sigma_px == 0.7
    assert "GCP marking error σ: 60 is out of range; allowed: 0 to 50 px" in \
        panel.input_label.text()

    # a control subset by count, then by ids
    qtbot.mouseClick(panel.subset, Qt.MouseButton.LeftButton)
    assert w.document.project.processing.gcps.control.count == 5  # half the 10 targets
    ids = field(w, QLineEdit, "Control ids")
    ids.setText("GCP01, GCP03,GCP05")
    ids.editingFinished.emit()
    control = w.document.project.processing.gcps.control
    assert control.ids == ("GCP01", "GCP03", "GCP05") and control.count is None

    # saved and read back: designer reconstruct uses exactly these settings
    path = tmp_path / "processing.xml"
    assert w.file_actions.save_to(path), problems(w)
    assert load_project(path).processing == w.document.project.processing
    resolved = resolve_processing(tmp_path, path)
    assert resolved == w.document.project.processing
    args = ReconstructJob(path, tmp_path / "out").commands()[0]
    assert args[args.index("--project") + 1] == str(path)

    # every step undoes
    while w.document.project.processing is not None:
        w.undo_stack.undo()
    assert not panel.enabled.isChecked() and not marking.isEnabled()


def test_results_show_the_dense_cloud_and_the_dod(qtbot, window, tmp_path):
    from designer.evaluate.compare import reference_mesh
    from designer.evaluate.raster_products import write_raster_products
    from designer.sfm.dense import DenseCloud, write_dense_ply

    w = window
    add_hills_and_flight(w)
    wait_idle(qtbot, w)
    project_path = tmp_path / "hills.xml"
    assert w.file_actions.save_to(project_path), problems(w)
    job = ReconstructJob(project_path, w.panels["Results"].survey_dir(), "known-poses")
    hf = w.sync.terrain.heightfield
    # a dense cloud with a dome of 5 cm over the true terrain, as the dense stage writes it
    x, y = (g.ravel() for g in np.meshgrid(np.arange(-40.0, 40.0, 0.5),
                                           np.arange(-40.0, 40.0, 0.5)))
    dome_m = 0.05 * (1 - (x**2 + y**2) / 40**2)
    xyz = np.column_stack([x, y, hf.height_at(x, y) + dome_m])
    job.compare_dir.mkdir(parents=True)
    write_dense_ply(job.out_dir / "dense.ply", DenseCloud(xyz, np.full(xyz.shape, 128,
                                                                       np.uint8)))
    rasters = write_raster_products(job.out_dir, xyz, reference_mesh(project_path),
                                    None, 1.0, 0.02)
    summary = {"dense": {"status": "ok", "points": len(xyz), "matcher": "cpu-sgm",
                         "dome_amplitude_m": rasters["dome"]["amplitude_m"]}}
    (job.out_dir / "summary.json").write_text(json.dumps(summary))
    sparse = xyz[::50]
    write_distances_ply(job.distances_ply, sparse, np.full(len(sparse), 0.01))

    assert w.file_actions.new(None)
    assert w.open_project(project_path)
    wait_idle(qtbot, w)
    results = w.panels["Results"]
    assert results.dense.isVisible() or not w.docks["Results"].isVisible()
    assert results.dense.products is not None
    dome = rasters["dome"]["amplitude_m"]
    # the amplitude is the fit's peak minus its mean over the DoD's edge cells: the 5 cm
    # dome is −2 cm on average along the edge of the 80 m square (its corners reach −5 cm)
    edge = (np.abs(x) >= 39.0) | (np.abs(y) >= 39.0)
    assert dome == pytest.approx(0.05 - dome_m[edge].mean(), abs=0.015)
    assert f"dome amplitude {1000 * dome:+.1f} mm" in results.dense.summary.text()
    assert not results.dense.image.pixmap().isNull()  # dod.png in the panel
    # the view shows the dense cloud, coloured by its distance to the true surface
    r = results.result
    assert r is not None and r.name == "dense.ply" and len(r.points_world) == len(xyz)
    assert np.median(r.distances_m) == pytest.approx(np.median(dome_m), abs=0.005)
    assert w.view.has_layer("cloud")

    qtbot.mouseClick(results.dense.sparse_button, Qt.MouseButton.LeftButton)
    wait_idle(qtbot, w)
    assert len(results.result.points_world) == len(sparse)
    qtbot.mouseClick(results.dense.dense_button, Qt.MouseButton.LeftButton)
    wait_idle(qtbot, w)
    assert results.result.name == "dense.ply"
