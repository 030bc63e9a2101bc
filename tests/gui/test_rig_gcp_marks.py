"""A rig survey's images show the GCPs where that image sees them: the Render panel's
image viewer draws each mark at the GCP projected with the image's own pose and camera
(not with its station's planning camera), and the GCP panel counts every image of the
rig that sees a GCP."""

from __future__ import annotations

import numpy as np
import pytest
from PySide6.QtCore import Qt
from PySide6.QtTest import QTest

from designer.core.projection import project_points
from designer.project.interiors import render_interior
from designer.survey.project_poses import project_images
from tests.gui.helpers import open_panel, problems, render_blank_frames, wait_idle

pytestmark = pytest.mark.gui



def _rig_project(qtbot, w, tmp_path):
    assert w.file_actions.new("survey-structures")  # a five-camera rig and an orbit
    wait_idle(qtbot, w)
    assert w.file_actions.save_to(tmp_path / "rig.xml"), problems(w)
    project = w.document.project
    return project, project_images(project, w.sync.terrain.heightfield)


def _seen(project, images, k: int, gcp_xyz) -> tuple[np.ndarray, np.ndarray]:
    """Which GCPs fall inside image k and where (px), projected with its own pose and
    camera at the render's resolution."""
    station = images.stations[k]
    interior = render_interior(project.camera(images.camera_ids[k]),
                               project.render.resolution_scale)
    proj = project_points(gcp_xyz, station.C_world, station.R_cam_to_world, interior)
    return proj.in_image[0], proj.uv_px[0]


def test_oblique_image_marks_are_its_own_projection(qtbot, window, monkeypatch, tmp_path):
    w = window
    project, images = _rig_project(qtbot, w, tmp_path)
    targets = w.sync.targets
    # the first station's five images (nadir and four obliques) are rendered
    frames = []
    for k in range(5):
        W, H = render_interior(project.camera(images.camera_ids[k]),
                               project.render.resolution_scale).image_size_px
        frames.append({"index": k, "name": images.stations[k].image_name,
                       "width": int(W), "height": int(H)})
    panel = render_blank_frames(qtbot, w, monkeypatch, tmp_path, frames)
    assert panel.thumbs.count() == 5

    # an oblique image that sees GCPs its station's nadir image does not
    k = next(i for i in range(5) if images.camera_ids[i] != images.camera_ids[0]
             and _seen(project, images, i, targets.true_xyz)[0].any())
    inside, uv = _seen(project, images, k, targets.true_xyz)
    item = next(panel.thumbs.item(i) for i in range(5)
                if panel.thumbs.item(i).data(Qt.ItemDataRole.UserRole) == k)
    panel.thumbs.scrollToItem(item)
    qtbot.wait(100)
    centre = panel.thumbs.viewport().mapTo(w, panel.thumbs.visualItemRect(item).center())
    QTest.mouseDClick(w.windowHandle(), Qt.MouseButton.LeftButton,
                      Qt.KeyboardModifier.NoModifier, centre)
    qtbot.waitUntil(lambda: getattr(panel, "viewer", None) is not None
                    and panel.viewer.isVisible(), timeout=5000)
    viewer = panel.viewer
    assert images.stations[k].image_name in viewer.windowTitle()
    drawn = {gid: (u, v) for gid, u, v in viewer.observations}
    expected = {targets.ids[i]: tuple(uv[i]) for i in np.flatnonzero(inside)}
    assert sorted(drawn) == sorted(expected)
    for gid, (u, v) in drawn.items():
        assert np.allclose((u, v), expected[gid], atol=1e-6), gid
    # the ring is painted there, on the picture of this image's size
    image = viewer.pixmap.toImage()
    assert (image.width(), image.height()) == (frames[k]["width"], frames[k]["height"])
    gid, (u, v) = next(iter(drawn.items()))
    ring = [image.pixelColor(int(u + r), int(v)) for r in range(4, 40)
            if 0 <= u + r < image.width()]
    assert any(c.red() > 200 and c.green() < 90 for c in ring), gid


def test_gcp_panel_counts_every_image_of_the_rig(qtbot, window, tmp_path):
    w = window
    project, images = _rig_project(qtbot, w, tmp_path)
    targets = w.sync.targets
    raycaster = w.sync.terrain.raycaster
    # each image, with its own pose and camera: inside it and not behind the terrain
    expected = np.zeros(len(targets.ids), dtype=int)
    for k, station in enumerate(images.stations):
        inside = _seen(project, images, k, targets.true_xyz)[0]
        g = np.flatnonzero(inside)
        hidden = raycaster.occluded(targets.true_xyz[g], np.repeat(
            np.reshape(station.C_world, (1, 3)), len(g), axis=0), tol_m=0.01)
        expected[g[~hidden]] += 1
    assert expected.sum() > 2 * len(w.sync.stations.stations)  # the obliques count
    panel = open_panel(w, "GCPs")
    from designer.gui.qt.panels.gcps import IMAGES_COLUMN

    shown = {panel.table.item(r, 0).text(): int(panel.table.item(r, IMAGES_COLUMN).text())
             for r in range(panel.table.rowCount())}
    assert shown == dict(zip(targets.ids, expected.tolist(), strict=True))
