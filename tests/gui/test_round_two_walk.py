"""Round two, the last panels walked: Moving objects, Buildings, Vegetation, Effects,
Results and the site import. What is typed or chosen there either works or says why,
in the user's terms."""

from __future__ import annotations

import numpy as np
import pytest

from tests.gui.helpers import problems, wait_idle

pytestmark = pytest.mark.gui


def _geographic_orthophoto(path, dem) -> None:
    """An RGB orthophoto over the DEM's ground on an EPSG:4326 grid (about 5 cm cells)."""
    import rasterio
    from affine import Affine
    from pyproj import Transformer

    with rasterio.open(dem) as src:
        b, crs = src.bounds, src.crs
    to_geo = Transformer.from_crs(crs, 4326, always_xy=True)
    lon, lat = to_geo.transform([b.left, b.right, b.left, b.right],
                                [b.bottom, b.bottom, b.top, b.top])
    dlat = 0.05 / 111_132.0
    dlon = 0.05 / (111_320.0 * np.cos(np.radians(np.mean(lat))))
    cols = int(np.ceil((max(lon) - min(lon)) / dlon))
    rows = int(np.ceil((max(lat) - min(lat)) / dlat))
    rgb = np.full((3, rows, cols), 120, np.uint8)
    with rasterio.open(path, "w", driver="GTiff", width=cols, height=rows, count=3,
                       dtype="uint8", crs="EPSG:4326",
                       transform=Affine(dlon, 0, min(lon), 0, -dlat, max(lat))) as dst:
        dst.write(rgb)


def test_a_site_with_a_geographic_orthophoto_is_imported(qtbot, window, sample_site,
                                                          tmp_path):
    """An orthophoto in longitude/latitude: its pixel size is measured in metres, not in
    degrees (which made a GSD of 0 and an error about <gsd-m> the user never typed)."""
    w = window
    shown = []
    w.show_problems = lambda messages, title: messages and shown.append((title, messages))
    ortho = tmp_path / "ortho-wgs84.tif"
    _geographic_orthophoto(ortho, sample_site["dem"])
    assert w.site_flight_actions.make_site_project(sample_site["dem"], ortho,
                                                   tmp_path / "site.xml"), shown
    wait_idle(qtbot, w)
    assert shown == [] and problems(w) == []
    gsd = w.document.project.trajectory.flight_plan.gsd_m
    assert gsd == pytest.approx(2 * 0.05 * w.document.project.render.resolution_scale,
                                rel=0.05)


def test_a_moving_object_starting_after_the_last_photo_is_pointed_out(qtbot, window):
    """A start time after the flight leaves the object standing at the start of its path
    in every photo: the panel says so, with the time of the last photo."""
    from PySide6.QtCore import Qt
    from PySide6.QtWidgets import QDoubleSpinBox

    from designer.gui.state import edits
    from tests.gui.helpers import open_panel, set_field

    w = window
    w.editor.edit(edits.ensure_flight_plan(w.document.project), "flight")
    wait_idle(qtbot, w)
    panel = open_panel(w, "Moving objects")
    qtbot.mouseClick(panel.add_car, Qt.MouseButton.LeftButton)
    w.panels["Flight"].timed.setChecked(True)
    wait_idle(qtbot, w)
    assert panel.warning.text() == ""
    start = next(b for b in panel.findChildren(QDoubleSpinBox)
                 if b.objectName() == "Moving object start")
    set_field(qtbot, start, "99999")
    wait_idle(qtbot, w)
    assert w.document.project.scene.moving_objects[0].start_s == 99999
    text = panel.warning.text()
    assert "car1 starts at 99999 s, after the last photo" in text, text
    assert "stands at the start of its path in every photo" in text
    set_field(qtbot, start, "0")
    wait_idle(qtbot, w)
    assert panel.warning.text() == ""
