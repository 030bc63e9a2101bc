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
