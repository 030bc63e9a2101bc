"""Honest render estimates (problem 9 of the user test), with Blender for real: the
estimate is calibrated by this machine's measured speed, a resumed render counts and
times only what it rendered, its kept images have thumbnails, and a thumbnail opens the
full image with the GCPs it sees drawn on it."""

from __future__ import annotations

import re

import numpy as np
import pytest
from PySide6.QtCore import Qt

from designer.gui.state import edits
from designer.project import model as m
from designer.render_time.model import load_speed
from tests.gui.helpers import problems, wait_idle

pytestmark = [pytest.mark.gui, pytest.mark.blender, pytest.mark.slow]


def test_resume_counts_thumbnails_and_calibrated_estimate(qtbot, window, tmp_path):
    pytest.importorskip("bpy")
    w = window
    project = edits.ensure_flight_plan(w.document.project)
    project = edits.set_flight(project, area=((-12.0, -12.0), (12.0, -12.0), (12.0, 12.0),
                                              (-12.0, 12.0)), altitude_agl_m=40.0)
    project = edits.add_target(project, 0.0, 0.0)
    project = edits.replace_path(project, "render", m.Render(
        preset="draft", resolution_scale=0.0625, workers=1))
    w.editor.edit(project, "a tiny survey")
    wait_idle(qtbot, w)
    assert w.file_actions.save_to(tmp_path / "tiny.xml"), problems(w)
    n = w.sync.stations.n_images
    assert 4 <= n <= 40
    panel = w.panels["Render"]
    assert "uncalibrated" in panel.cost.text()  # a fresh cache folder (tests/conftest.py)
    assert not load_speed().calibrated

    # render, cancel after two images
    panel.resume.setChecked(True)
    panel.start()
    qtbot.waitUntil(lambda: panel.n_rendered >= 2, timeout=300000)
    qtbot.mouseClick(panel.cancel_button, Qt.MouseButton.LeftButton)
    qtbot.waitUntil(lambda: panel.start_button.isEnabled(), timeout=120000)
    first = panel.n_rendered
    assert 2 <= first < n, panel.log.toPlainText()
    # the cancelled run already calibrated the estimates with the frames it finished
    # (a worker's first frame, which also builds the scene, is left out of the fit)
    assert load_speed().calibrated and load_speed().images >= 1
    assert "this machine" in panel.cost.text()

    # resume: the kept images are counted as kept, not as rendered
    panel.start()
    qtbot.waitUntil(lambda: panel.start_button.isEnabled(), timeout=600000)
    wait_idle(qtbot, w)
    text = panel.state.text()
    assert text.startswith(f"done: {n - first} images rendered"), text
    assert f"{first} complete before (kept)" in text
    match = re.search(r"Cycles ([\d.]+) s per image", text)
    assert match, text  # the command's own timing, the same line its log ends with
    per_image = float(match.group(1))
    assert per_image > 0
    assert panel.progress.value() == n == panel.thumbs.count()
    kept = [panel.thumbs.item(i) for i in range(n) if "(kept)" in panel.thumbs.item(i).text()]
    assert len(kept) == first
    assert all(not item.icon().isNull() for item in kept)  # pictures, read from disk

    # the estimate is now this machine's speed, refined by the resumed run's frames; the
    # panels show the model's figure for this project
    speed = load_speed()
    assert speed.source == "render" and speed.images >= n - first - 1
    from designer.gui.state import derived

    estimate = derived.render_estimate(w.document.project, w.sync.stations.render_costs,
                                       "draft")
    line = next(x for x in panel.cost.text().splitlines() if x.startswith("draft:"))
    from designer.gui.state.wording import duration

    assert (f"{duration(estimate.per_image_s)} per image, {duration(estimate.total_s)} "
            f"for {n} images") in line
    assert "this machine" in w.panels["Flight"].time_label.text()

    # a thumbnail opens the full image with the GCP it sees drawn on it
    plan = w.sync.plan
    seen = [k for k in range(n) if plan.observations(k)]
    assert seen
    item = next(panel.thumbs.item(i) for i in range(n)
                if panel.thumbs.item(i).data(Qt.ItemDataRole.UserRole) == seen[0])
    panel.thumbs.itemDoubleClicked.emit(item)
    viewer = panel.viewer
    assert viewer.isVisible() and "GCP01" in viewer.windowTitle()
    _gid, u, v = plan.observations(seen[0])[0]
    image = viewer.pixmap.toImage()
    W, H = image.width(), image.height()
    assert (W, H) == (5472 // 16, 3648 // 16)
    # ring pixels around the projected centre are the ring colour
    ring = [image.pixelColor(int(u + dx), int(v + dy)) for dx, dy in
            ((r, 0) for r in np.arange(5, 12)) if 0 <= u + dx < W and 0 <= v + dy < H]
    assert any(c.red() > 200 and c.green() < 90 for c in ring)
