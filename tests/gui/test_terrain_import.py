"""Terrain panel: importing a DEM (GeoTIFF, ESRI ASCII) or a mesh (OBJ, PLY) through the
file dialog; the terrain, its extent and the drawn mesh are the file's."""

from __future__ import annotations

import numpy as np
import pytest
from PySide6.QtCore import Qt
from PySide6.QtWidgets import QComboBox

from designer.project import load_project
from designer.project import model as m
from tests.gui.helpers import answer_file_dialog, problems, wait_idle

pytestmark = pytest.mark.gui

# A 31 × 21 grid of 2 m cells whose centres run from (1001, 2001) to (1061, 2041).
X0, Y0, CELL, COLS, ROWS = 1001.0, 2001.0, 2.0, 31, 21


def _height(x, y):
    return 100.0 + 0.1 * (x - X0) - 0.05 * (y - Y0) + 2.0 * np.sin((x - X0) / 9.0)


def _grid():
    x = X0 + CELL * np.arange(COLS)
    y = Y0 + CELL * np.arange(ROWS)
    X, Y = np.meshgrid(x, y)  # rows go north
    return X, Y, _height(X, Y)


def _write_asc(path) -> None:
    _X, _Y, Z = _grid()
    lines = [f"ncols {COLS}", f"nrows {ROWS}", f"xllcorner {X0 - CELL / 2}",
             f"yllcorner {Y0 - CELL / 2}", f"cellsize {CELL}"]
    lines += [" ".join(f"{z:.6f}" for z in row) for row in Z[::-1]]  # north row first
    path.write_text("\n".join(lines) + "\n")


def _write_geotiff(path) -> None:
    import rasterio
    from affine import Affine

    _X, _Y, Z = _grid()
    north = Y0 + CELL * (ROWS - 1) + CELL / 2
    with rasterio.open(path, "w", driver="GTiff", height=ROWS, width=COLS, count=1,
                       dtype="float64", crs="EPSG:32632",
                       transform=Affine(CELL, 0.0, X0 - CELL / 2, 0.0, -CELL, north)) as dst:
        dst.write(Z[::-1], 1)  # the first raster row is the northernmost


def _mesh():
    X, Y, Z = _grid()
    v = np.column_stack([X.ravel(), Y.ravel(), Z.ravel()])
    sw = (np.arange(ROWS - 1)[:, None] * COLS + np.arange(COLS - 1)[None, :]).ravel()
    f = np.vstack([np.column_stack([sw, sw + 1, sw + COLS + 1]),
                   np.column_stack([sw, sw + COLS + 1, sw + COLS])])
    return v, f


def _write_obj(path) -> None:
    v, f = _mesh()
    path.write_text("".join(f"v {x:.6f} {y:.6f} {z:.6f}\n" for x, y, z in v)
                    + "".join(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in f))


def _write_ply(path) -> None:
    from plyfile import PlyData, PlyElement

    v, f = _mesh()
    vertex = np.empty(len(v), dtype=[("x", "f8"), ("y", "f8"), ("z", "f8")])
    vertex["x"], vertex["y"], vertex["z"] = v.T
    face = np.empty(len(f), dtype=[("vertex_indices", "i4", (3,))])
    face["vertex_indices"] = f
    PlyData([PlyElement.describe(vertex, "vertex"), PlyElement.describe(face, "face")]).write(
        str(path))


FILES = {"dem.asc": ("dem", _write_asc), "dem.tif": ("dem", _write_geotiff),
         "terrain.obj": ("mesh", _write_obj), "terrain.ply": ("mesh", _write_ply)}


@pytest.mark.parametrize("name", list(FILES))
def test_import_through_the_terrain_panel(qtbot, window, tmp_path, name):
    w = window
    kind, write = FILES[name]
    path = tmp_path / "data" / name
    path.parent.mkdir()
    write(path)
    blank = w.document.project
    panel = w.panels["Terrain"]
    w.docks["Terrain"].raise_()

    # Choose the source kind; the file dialog opens; pick the file.
    answer_file_dialog(path)
    panel.kind.setCurrentIndex(panel.kind.findData(kind))
    qtbot.waitUntil(lambda: w.document.project.scene.terrain.kind == kind, timeout=20000)
    wait_idle(qtbot, w)
    terrain = w.document.project.scene.terrain
    assert terrain.source.file == f"data/{name}"  # relative to the project's folder
    e = terrain.extent
    assert (e.min_X, e.min_Y) == pytest.approx((X0, Y0))
    assert (e.max_X, e.max_Y) == pytest.approx((X0 + CELL * (COLS - 1), Y0 + CELL * (ROWS - 1)))
    assert panel.file_box.isVisibleTo(panel) and panel.file_label.text() == f"data/{name}"
    assert panel.error_label.text() == ""

    # The terrain computed and drawn is the file's: heights at the nodes, every vertex.
    result = w.sync.terrain
    X, Y, Z = _grid()
    if kind == "dem":
        hf = result.heightfield
        assert hf.heights_m.shape == (ROWS, COLS)
        np.testing.assert_allclose(hf.height_at(X.ravel(), Y.ravel()), Z.ravel(), atol=1e-6)
        assert panel.size_label.text().startswith(f"{COLS} × {ROWS} = {COLS * ROWS:,}")
    else:
        assert result.heightfield is None
        v, _f = _mesh()
        np.testing.assert_allclose(np.sort(result.mesh.vertices_world, axis=0),
                                   np.sort(v, axis=0), atol=1e-6)
        assert panel.size_label.text() == f"mesh, {COLS * ROWS:,} vertices"
    drawn = w.view.layer_data("terrain")
    assert drawn.n_points == COLS * ROWS
    lo = np.asarray(drawn.points).min(axis=0) + w.view.offset
    hi = np.asarray(drawn.points).max(axis=0) + w.view.offset
    np.testing.assert_allclose([lo[:2], hi[:2]], [[X0, Y0], [X.max(), Y.max()]], atol=1e-3)
    assert (lo[2], hi[2]) == pytest.approx((Z.min(), Z.max()), abs=1e-3)

    # The ground under a pixel in the middle of the view lies on the imported surface.
    ground = w.view.interaction.ground_at(w.view.plotter.width() / 2,
                                          w.view.plotter.height() / 2)
    assert ground is not None
    if kind == "dem":
        assert ground[2] == pytest.approx(float(hf.height_at(ground[0], ground[1])), abs=1e-3)
    else:  # a point on the triangulated surface: between the heights of its cell
        assert Z.min() - 1e-3 <= ground[2] <= Z.max() + 1e-3
        assert abs(ground[2] - _height(ground[0], ground[1])) < 0.2

    # A flight over it, saved: the file validates; undo goes back to the flat plane.
    qtbot.mouseClick(w.panels["Flight"].create, Qt.MouseButton.LeftButton)
    wait_idle(qtbot, w)
    assert w.sync.stations.n_images > 0
    plan = w.document.project.trajectory.flight_plan
    if kind == "mesh":  # flown above the mesh's mean height (no mean of a height field)
        assert plan.altitude_reference == pytest.approx(result.z_mean_m, abs=1e-3)
        assert w.findChild(QComboBox, "Altitude reference").currentData() == "given"
    else:
        assert plan.altitude_reference == "mean"
    assert w.file_actions.save_to(tmp_path / "imported.xml"), problems(w)
    loaded = load_project(tmp_path / "imported.xml")
    assert loaded.scene.terrain == terrain
    assert isinstance(loaded.scene.terrain.source, m.DemTerrain if kind == "dem"
                      else m.MeshTerrain)
    w.undo_stack.undo()
    w.undo_stack.undo()
    wait_idle(qtbot, w)
    assert w.document.project == blank
    assert w.sync.terrain.heightfield.heights_m.shape == (2, 2)


def test_a_broken_dem_is_reported_in_the_panel(qtbot, window, tmp_path):
    w = window
    path = tmp_path / "broken.asc"
    path.write_text("ncols 3\nnrows 2\nthis is not a grid\n")
    panel = w.panels["Terrain"]
    before = w.document.project
    answer_file_dialog(path)
    panel.kind.setCurrentIndex(panel.kind.findData("dem"))
    qtbot.waitUntil(lambda: "broken.asc" in panel.error_label.text(), timeout=20000)
    wait_idle(qtbot, w)
    assert w.document.project == before  # nothing changed
    assert panel.kind.currentData() == "flat"
