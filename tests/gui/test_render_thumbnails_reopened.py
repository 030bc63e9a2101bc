"""A project whose render output is up to date shows its images' thumbnails in the Render
panel when it is opened (the images were rendered outside this window: by the command)."""

from __future__ import annotations

import subprocess
import sys

import pytest

from tests.gui.helpers import wait_idle
from tests.gui.tiny_survey_helpers import save_tiny_survey, wait_state

pytestmark = [pytest.mark.gui, pytest.mark.blender, pytest.mark.slow]


def test_opening_a_rendered_project_shows_its_thumbnails(qtbot, window, tmp_path):
    pytest.importorskip("bpy")
    w = window
    path, n = save_tiny_survey(qtbot, w, tmp_path)
    out = (path.parent / w.document.project.outputs.directory).resolve()
    names = list(w.sync.stations.image_names)
    subprocess.run([sys.executable, "-m", "designer", "render", str(path), "-o", str(out)],
                   check=True, capture_output=True, cwd=tmp_path)
    render = w.panels["Render"]
    assert w.file_actions.new(None)
    wait_idle(qtbot, w)
    assert render.thumbs.count() == 0

    assert w.open_project(path)
    w.docks["Render"].raise_()
    wait_state(qtbot, w, lambda: render.out_of_date.text().startswith(f"the {n} rendered"))
    qtbot.waitUntil(lambda: render.thumbs.count() == n and all(
        not render.thumbs.item(k).icon().isNull() for k in range(n)), timeout=30000)
    shown = [render.thumbs.item(k).text().splitlines()[0] for k in range(n)]
    assert shown == [name.rsplit(".", 1)[0] for name in names]
    paths = [render.thumbs.item(k).toolTip() for k in range(n)]
    assert all(p.startswith(str(out)) for p in paths), paths

    # another project: the thumbnails of this one go
    assert w.file_actions.new(None)
    wait_idle(qtbot, w)
    assert render.thumbs.count() == 0
