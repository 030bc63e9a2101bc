"""File → Import site, Import flight and Export flight plan, used with the mouse: the
menus clicked, the file dialogs answered as a person would."""

from __future__ import annotations

import shutil

import numpy as np
import pytest
from PySide6.QtCore import Qt
from PySide6.QtTest import QTest

from designer.flight.qgc import read_plan
from designer.flight.wpml import read_wpml
from designer.project import load_project
from tests.flight.helpers import EXAMPLE
from tests.gui.flight_helpers import _flown_images
from tests.gui.helpers import answer_file_dialogs, choose_menu, problems, wait_idle

pytestmark = pytest.mark.gui


def test_import_site_builds_opens_and_refuses_a_bad_dem(qtbot, window, sample_site,
                                                        tmp_path):
    w = window
    path = tmp_path / "site.xml"
    answer_file_dialogs([sample_site["dem"], sample_site["orthophoto"], path])
    choose_menu(qtbot, w, "File", "Import site (DEM + orthophoto)…")
    wait_idle(qtbot, w)
    assert w.document.path == path and path.is_file()
    assert problems(w) == []
    project = w.document.project
    assert project == load_project(path)
    assert project.scene.terrain.source.file.endswith("dem.tif")
    assert project.scene.texture.source.file.endswith("orthophoto.tif")
    assert project.crs.startswith("EPSG:")

    # a file that is no GeoTIFF: the command's one-line error, nothing written
    bad = tmp_path / "notes.tif"
    bad.write_text("not a raster\n")
    answer_file_dialogs([bad])  # refused at once: no orthophoto or save dialog follows
    choose_menu(qtbot, w, "File", "Import site (DEM + orthophoto)…")
    lines = problems(w)
    assert len(lines) == 1 and "notes.tif" in lines[0], lines
    assert not (tmp_path / "bad.xml").exists()
    assert w.document.path == path  # the open project stays


def test_an_imported_orthophoto_lies_where_its_geotransform_puts_it(qtbot, window,
                                                                   sample_site, tmp_path):
    """The 3D view drapes the orthophoto as the renderer does: each drawn terrain vertex
    gets the orthophoto pixel of its own position, not a tile stretched over the extent."""
    from designer.scene.build import build_orthophoto
    from designer.scene.orthophoto import orthophoto_uv

    w = window
    path = tmp_path / "site.xml"
    answer_file_dialogs([sample_site["dem"], sample_site["orthophoto"], path])
    choose_menu(qtbot, w, "File", "Import site (DEM + orthophoto)…")
    wait_idle(qtbot, w)
    qtbot.waitUntil(lambda: w.sync.texture is not None, timeout=30000)
    project = w.document.project
    ortho = build_orthophoto(project.scene.texture, project.scene.terrain, path.parent,
                             project.crs)
    mesh = w.view.plotter.actors["terrain"].mapper.dataset
    points_world = np.asarray(mesh.points, float) + w.view.offset
    expected = orthophoto_uv(ortho, points_world[:, :2], project.crs)
    drawn = np.asarray(mesh.active_texture_coordinates, float)
    assert np.abs(drawn - expected).max() < 1e-5
    tiled = w.sync.terrain.display.uv  # what was drawn before: the extent as one tile
    assert np.abs(tiled - expected).max() > 1e-3




def test_import_flight_from_images_replays_the_poses_and_undoes(qtbot, window, tmp_path):
    w = window
    base = tmp_path / "base" / "survey.xml"
    shutil.copytree(EXAMPLE.parent, base.parent)
    assert w.open_project(base)
    wait_idle(qtbot, w)
    planned = w.document.project
    poses = _flown_images(tmp_path / "flown", 6)

    answer_file_dialogs([tmp_path / "flown"])
    choose_menu(qtbot, w, "File", "Import flight", "From a folder of images…")
    wait_idle(qtbot, w)
    assert problems(w) == []
    eos = w.document.project.trajectory.exterior_orientations
    assert [e.name for e in eos] == [f"DJI_{k + 1:04d}.JPG" for k in range(6)]
    C = np.array([[e.X, e.Y, e.Z] for e in eos])
    assert np.abs(C - np.array([p.C_world for p in poses])).max() < 0.01
    # the view draws the imported photos: six frusta, and six footprints on the ground
    # around the nadir point of each photo
    geometry = w.sync.stations.geometry
    assert geometry.n_stations == 6
    assert len(geometry.frustum_points) == 6 * 5  # apex + 4 corners each
    footprints = geometry.footprint_points.reshape(6, -1, 3)
    assert np.abs(footprints[:, :, :2].mean(axis=1) - C[:, :2]).max() < 15.0
    assert (footprints[:, :, 2] < C[:, None, 2] - 30.0).all()  # on the ground, far below
    assert w.view.plotter.actors["frusta"].GetVisibility()
    assert w.view.plotter.actors["footprints"].GetVisibility()
    # the Flight panel's figures for the imported photos: numbers or words, never nan
    qtbot.waitUntil(lambda: w.sync.plan is not None, timeout=30000)
    flight = w.panels["Flight"]
    figures = [flight.real_gsd.text(), flight.real_overlap.text(), flight.real_images.text()]
    assert all(figures) and not any("nan" in t for t in figures), figures
    assert w.document.dirty

    # one undo step brings the planned flight back
    w.activateWindow()
    qtbot.waitUntil(w.isActiveWindow)  # under load a key sent before is lost
    QTest.keyClick(w.windowHandle(), Qt.Key.Key_Z, Qt.KeyboardModifier.ControlModifier)
    wait_idle(qtbot, w)
    assert w.document.project == planned


def test_import_flight_from_a_bad_csv_changes_nothing(qtbot, window, tmp_path):
    w = window
    base = tmp_path / "base" / "survey.xml"
    shutil.copytree(EXAMPLE.parent, base.parent)
    assert w.open_project(base)
    wait_idle(qtbot, w)
    before = w.document.project
    bad = tmp_path / "reference.csv"
    bad.write_text("Label,X,Y\nIMG_1.JPG,1,2\n")
    answer_file_dialogs([bad])
    choose_menu(qtbot, w, "File", "Import flight", "From a geo.txt or reference CSV…")
    lines = problems(w)
    assert len(lines) == 1 and "reference.csv" in lines[0], lines
    assert w.document.project == before


def test_export_flight_plan_in_each_format_reads_back(qtbot, window, tmp_path):
    w = window
    base = tmp_path / "base" / "survey.xml"
    shutil.copytree(EXAMPLE.parent, base.parent)
    assert w.open_project(base)
    wait_idle(qtbot, w)
    n_images = w.sync.stations.n_images

    qgc = "QGroundControl plan, heights relative to take-off (*.plan)"
    answer_file_dialogs([(tmp_path / "mission", qgc)])
    choose_menu(qtbot, w, "File", "Export flight plan…")
    assert problems(w) == []
    plan = tmp_path / "mission.plan"  # the file type's suffix is added
    points = read_plan(plan)
    assert len(points) == n_images

    wpml = "DJI WPML mission, heights above mean sea level (*.kmz)"
    answer_file_dialogs([(tmp_path / "mission.kmz", wpml)])
    choose_menu(qtbot, w, "File", "Export flight plan…")
    assert problems(w) == []
    flown = read_wpml(tmp_path / "mission.kmz")
    assert len(flown) == n_images
    # both files give the same photo positions (the planned exposures)
    lonlat_qgc = np.array([[p.lon_deg, p.lat_deg] for p in points])
    lonlat_wpml = np.array([[p.lon_deg, p.lat_deg] for p in flown])
    assert np.abs(lonlat_qgc - lonlat_wpml).max() < 1e-9


def test_flight_figures_that_do_not_exist_are_said_in_words():
    from designer.gui.qt.panels.flight import _gsd_text

    nan = float("nan")
    assert _gsd_text(0.0492, 0.0635, 0.0532) == (
        "4.92 to 6.35 cm over the area, median 5.32 cm at the centres of the images over it")
    assert _gsd_text(0.0492, 0.0635, nan).endswith("no image is centred over it")
    assert "nan" not in _gsd_text(nan, nan, nan)


def _dem_with_voids(path, void_everywhere: bool):
    """A small metric GeoTIFF DEM: all nodata, or with a void in every row and column
    (so no void-free rectangle remains)."""
    import rasterio
    from affine import Affine

    heights = np.full((12, 12), 100.0, np.float32)
    if void_everywhere:
        heights[:] = np.nan
    else:
        heights[np.arange(12), np.arange(12)] = np.nan
        heights[np.arange(12), np.arange(11, -1, -1)] = np.nan
    with rasterio.open(path, "w", driver="GTiff", width=12, height=12, count=1,
                       dtype="float32", crs="EPSG:32633", nodata=np.nan,
                       transform=Affine(2.0, 0, 500000.0, 0, -2.0, 5000000.0)) as dst:
        dst.write(heights, 1)
    return path


def _reject_further_file_dialogs(qtbot):
    """Cancel every file dialog that opens from now on; the titles of those seen."""
    from PySide6.QtCore import QTimer
    from PySide6.QtWidgets import QApplication, QFileDialog

    seen: list[str] = []

    def watch() -> None:
        dialog = QApplication.activeModalWidget()
        if isinstance(dialog, QFileDialog) and dialog.isVisible():
            seen.append(dialog.windowTitle())
            dialog.reject()
        timer.start()

    timer = QTimer()
    timer.setSingleShot(True)
    timer.setInterval(50)
    timer.timeout.connect(watch)
    timer.start()
    return seen, timer


@pytest.mark.parametrize("void_everywhere", [True, False])
def test_import_site_checks_the_dem_as_soon_as_it_is_chosen(qtbot, window, tmp_path,
                                                            void_everywhere):
    """A DEM without a usable void-free part is refused right after it is chosen (no
    orthophoto or save dialog follows), and the message speaks of the DEM alone — no
    orthophoto was given."""
    w = window
    dem = _dem_with_voids(tmp_path / "holes.tif", void_everywhere)
    answer_file_dialogs([dem])
    qtbot.wait(10)
    seen, timer = _reject_further_file_dialogs(qtbot)
    try:
        choose_menu(qtbot, w, "File", "Import site (DEM + orthophoto)…")
        qtbot.wait(100)
    finally:
        timer.stop()
    assert seen == [], f"dialogs opened after the bad DEM: {seen}"
    lines = problems(w)
    assert len(lines) == 1 and "holes.tif" in lines[0], lines
    assert "orthophoto" not in lines[0].lower(), lines
    assert "void" in lines[0].lower() or "no data" in lines[0].lower(), lines
    assert not list(tmp_path.glob("*.xml"))


def test_site_project_without_orthophoto_speaks_of_the_dem_alone(tmp_path):
    from designer.errors import DesignerError
    from designer.survey.site_project import site_project

    dem = _dem_with_voids(tmp_path / "holes.tif", False)
    with pytest.raises(DesignerError) as error:
        site_project(dem, None, tmp_path / "site.xml")
    assert "orthophoto" not in str(error.value)


def test_import_site_checks_the_orthophoto_before_asking_where_to_save(qtbot, window,
                                                                       sample_site,
                                                                       tmp_path):
    """An orthophoto that cannot make a site with the DEM is refused right after it is
    chosen: no save dialog follows, its message names it, nothing is written."""
    from PySide6.QtCore import QTimer
    from PySide6.QtWidgets import QApplication, QFileDialog

    w = window
    bad = tmp_path / "scan.tif"
    bad.write_text("not a raster\n")
    answer_file_dialogs([sample_site["dem"], bad])
    saves: list[str] = []

    def cancel_save_dialogs() -> None:
        dialog = QApplication.activeModalWidget()
        if isinstance(dialog, QFileDialog) and dialog.isVisible() \
                and "save" in dialog.windowTitle():
            saves.append(dialog.windowTitle())
            dialog.reject()

    timer = QTimer()
    timer.setInterval(50)
    timer.timeout.connect(cancel_save_dialogs)
    timer.start()
    try:
        choose_menu(qtbot, w, "File", "Import site (DEM + orthophoto)…")
        qtbot.wait(100)
    finally:
        timer.stop()
    assert saves == [], f"asked where to save after the bad orthophoto: {saves}"
    lines = problems(w)
    assert len(lines) == 1 and "scan.tif" in lines[0], lines
    assert not list(tmp_path.glob("*.xml"))
