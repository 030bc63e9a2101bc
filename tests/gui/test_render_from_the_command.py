"""A render made by the command (``designer render``) while its project is open in the
window is noticed without an edit, a save or an open: the Render panel says the images
are up to date and shows their thumbnails."""

from __future__ import annotations

import subprocess
import sys

import pytest

from tests.gui.helpers import open_panel
from tests.gui.tiny_survey_helpers import save_tiny_survey, wait_state

pytestmark = [pytest.mark.gui, pytest.mark.blender, pytest.mark.slow]


def _render(qtbot, path, out, *options: str) -> None:
    """``designer render`` in its own process, the window's event loop running."""
    log = path.parent / "render.log"
    with log.open("w") as sink:
        proc = subprocess.Popen([sys.executable, "-m", "designer", "render", str(path),
                                 "-o", str(out), *options], stdout=sink,
                                stderr=subprocess.STDOUT, cwd=path.parent)
        try:
            qtbot.waitUntil(lambda: proc.poll() is not None, timeout=600000)
        finally:
            if proc.poll() is None:
                proc.kill()
                proc.wait()
    assert proc.returncode == 0, log.read_text()


def test_a_render_by_the_command_is_noticed_without_an_edit(qtbot, window, tmp_path):
    pytest.importorskip("bpy")
    w = window
    path, n = save_tiny_survey(qtbot, w, tmp_path)
    render = open_panel(w, "Render")
    wait_state(qtbot, w, lambda: True)
    assert not render.out_of_date.text().startswith(f"the {n} rendered")
    assert render.thumbs.count() == 0
    out = (path.parent / w.document.project.outputs.directory).resolve()
    assert not out.exists()
    project = w.document.project

    _render(qtbot, path, out)
    wait_state(qtbot, w, lambda: render.out_of_date.text().startswith(
        f"the {n} rendered images are up to date"), timeout_ms=60000)
    qtbot.waitUntil(lambda: render.thumbs.count() == n and all(
        not render.thumbs.item(k).icon().isNull() for k in range(n)), timeout=30000)
    paths = [render.thumbs.item(k).toolTip() for k in range(n)]
    assert all(p.startswith(str(out)) for p in paths), paths
    assert w.document.project is project  # no edit, no save, no open
    assert not w.document.changed


def test_thumbnails_follow_a_second_render_by_the_command(qtbot, window, tmp_path):
    """One image rendered by the command, then the rest (resumed): the panel first shows
    the one thumbnail and the others missing, then every thumbnail."""
    pytest.importorskip("bpy")
    w = window
    path, n = save_tiny_survey(qtbot, w, tmp_path)
    render = open_panel(w, "Render")
    out = (path.parent / w.document.project.outputs.directory).resolve()

    _render(qtbot, path, out, "--frames", "0")
    wait_state(qtbot, w, lambda: f"{n - 1} images not rendered" in render.out_of_date.text(),
               timeout_ms=60000)
    qtbot.waitUntil(lambda: render.thumbs.count() == 1, timeout=30000)

    _render(qtbot, path, out, "--resume")
    wait_state(qtbot, w, lambda: render.out_of_date.text().startswith(
        f"the {n} rendered images are up to date"), timeout_ms=60000)
    qtbot.waitUntil(lambda: render.thumbs.count() == n and all(
        not render.thumbs.item(k).icon().isNull() for k in range(n)), timeout=30000)
    assert not w.document.changed
