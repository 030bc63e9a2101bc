"""The image viewer marks the GCPs where the render exported them for that image
(``ground-truth/gcp_observations.csv``: a target behind a building left out, a
rolling-shutter image's points where its rows' poses put them), not where the plan's
single pose projects them; an image newer than the table falls back to the plan."""

from __future__ import annotations

import os

import numpy as np
import pytest
from PySide6.QtCore import Qt
from PySide6.QtTest import QTest

from designer.export.tables import GcpObservation, write_gcp_observations_csv
from designer.gui.state.image_marks import exported_marks
from designer.project.interiors import render_interior
from tests.gui.helpers import problems, render_blank_frames, wait_idle

pytestmark = pytest.mark.gui


def _open_viewer(qtbot, w, panel, k: int):
    item = next(panel.thumbs.item(i) for i in range(panel.thumbs.count())
                if panel.thumbs.item(i).data(Qt.ItemDataRole.UserRole) == k)
    panel.thumbs.scrollToItem(item)
    qtbot.wait(100)
    centre = panel.thumbs.viewport().mapTo(w, panel.thumbs.visualItemRect(item).center())
    panel.viewer = None
    QTest.mouseDClick(w.windowHandle(), Qt.MouseButton.LeftButton,
                      Qt.KeyboardModifier.NoModifier, centre)
    qtbot.waitUntil(lambda: getattr(panel, "viewer", None) is not None
                    and panel.viewer.isVisible(), timeout=5000)
    return panel.viewer


def test_the_viewer_draws_the_exported_gcp_points_of_the_image(qtbot, window, monkeypatch,
                                                                tmp_path):
    w = window
    assert w.file_actions.new("survey")
    wait_idle(qtbot, w)
    assert w.file_actions.save_to(tmp_path / "survey.xml"), problems(w)
    project = w.document.project
    plan = w.sync.plan
    # the plan's image that sees the most GCPs
    k = max(range(len(plan.image_names)), key=lambda i: len(plan.observations(i)))
    planned = plan.observations(k)
    assert len(planned) >= 2, planned
    W, H = render_interior(project.cameras[0], project.render.resolution_scale).image_size_px
    name = plan.image_names[k]
    panel = render_blank_frames(qtbot, w, monkeypatch, tmp_path,
                                [{"index": k, "name": name, "width": int(W), "height": int(H)}])
    image = next((tmp_path / "output" / "images").iterdir())
    assert image.name == name

    # the render's table: the first GCP hidden (behind a building), the others shifted
    # by 3.5 px (a rolling-shutter image's rows)
    exported = [GcpObservation(gid, name, np.array([u + 3.5, v - 2.0]))
                for gid, u, v in planned[1:]]
    exported.append(GcpObservation(planned[0][0], "OTHER.png", np.array([10.0, 10.0])))
    table = tmp_path / "output" / "ground-truth" / "gcp_observations.csv"
    table.parent.mkdir(parents=True)
    write_gcp_observations_csv(table, exported)
    viewer = _open_viewer(qtbot, w, panel, k)
    drawn = {gid: (u, v) for gid, u, v in viewer.observations}
    assert sorted(drawn) == sorted(gid for gid, _, _ in planned[1:])
    for gid, u, v in planned[1:]:
        assert np.allclose(drawn[gid], (u + 3.5, v - 2.0), atol=1e-6), gid
    assert planned[0][0] not in viewer.windowTitle()
    viewer.close()

    # an image newer than the table (rendered after it): the plan's projection
    later = table.stat().st_mtime + 5
    os.utime(image, (later, later))
    assert exported_marks(image) is None
    viewer = _open_viewer(qtbot, w, panel, k)
    assert sorted(viewer.observations) == sorted(planned)
