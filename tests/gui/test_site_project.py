"""A real-site project (DEM + orthophoto) opens in the window: terrain, orthophoto texture
and the Texture panel showing the orthophoto's file."""

from __future__ import annotations

import pytest

from designer.cli.main import main
from tests.gui.helpers import problems, wait_idle

pytestmark = pytest.mark.gui


def test_site_project_opens_with_its_orthophoto(qtbot, window, sample_site, tmp_path):
    path = tmp_path / "site.xml"
    assert main(["new", str(path), "--site", str(sample_site["dem"]),
                 "--orthophoto", str(sample_site["orthophoto"])]) == 0
    assert window.open_project(path)
    wait_idle(qtbot, window)
    assert problems(window) == []
    panel = window.panels["Texture"]
    assert panel.image.isVisible() and not panel.procedural.isVisible()
    assert panel.file_label.text().endswith("orthophoto.tif")
    rgb = panel.sync.texture_rgb
    extent = window.editor.document.project.scene.terrain.extent
    # The orthophoto's pixels over the terrain extent (3 cm, plus a two-pixel margin).
    assert abs(rgb.shape[1] - extent.width_m / 0.03) <= 5
    assert abs(rgb.shape[0] - extent.length_m / 0.03) <= 5
