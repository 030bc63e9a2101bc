"""Helpers of the out-of-date tests (Blender for real): a tiny survey (2–8 images of
96 × 72 px, draft) rendered from the Render panel, the record a reconstruction of it
leaves, and waiting for the window's out-of-date lines to settle."""

from __future__ import annotations

import json

from designer.gui.state import edits
from designer.project import model as m
from tests.gui.helpers import problems, wait_idle


def wait_state(qtbot, w, predicate, timeout_ms: int = 120000) -> None:
    """Wait until the window has compared its outputs with the project and
    ``predicate()`` holds."""
    qtbot.waitUntil(lambda: not w.stale_watch.pending and not w.tasks.busy
                    and predicate(), timeout=timeout_ms)


def tiny_survey_project(project: m.Project, gcps: bool = False) -> m.Project:
    """``project`` with a 96 × 72 px camera flying a 20 m square at 40 m, a draft
    render, and (``gcps``) two GCPs."""
    project = edits.set_camera(project, m.Camera("cam96", 8.8, 13.2, 9.9, 960, 720))
    project = edits.set_flight(project, area=((-10.0, -10.0), (10.0, -10.0), (10.0, 10.0),
                                              (-10.0, 10.0)), altitude_agl_m=40.0,
                               front_overlap_percent=60.0, side_overlap_percent=50.0)
    project = edits.replace_path(project, "render", m.Render(
        preset="draft", resolution_scale=0.1, workers=1))
    if gcps:
        project = edits.add_target(edits.add_target(project, -3.0, 0.0), 3.0, 0.0)
    return project


def save_tiny_survey(qtbot, w, folder, gcps: bool = False):
    """The tiny survey made in the window and saved as ``folder``/tiny.xml; returns the
    path and its number of images."""
    w.editor.edit(tiny_survey_project(w.document.project, gcps), "a tiny survey")
    wait_idle(qtbot, w)
    path = folder / "tiny.xml"
    assert w.file_actions.save_to(path), problems(w)
    n = w.sync.stations.n_images
    assert 2 <= n <= 8
    return path, n


def render_from_the_panel(qtbot, w, n: int) -> None:
    """Press Render and wait until the ``n`` images are done."""
    from PySide6.QtCore import Qt

    render = w.panels["Render"]
    qtbot.mouseClick(render.start_button, Qt.MouseButton.LeftButton)
    qtbot.waitUntil(lambda: render.start_button.isEnabled(), timeout=600000)
    assert render.state.text().startswith(f"done: {n} images"), render.log.toPlainText()


def record_reconstruction(w, path, with_settings: bool = True) -> None:
    """What designer reconstruct leaves for the rendered images of ``path``: a distances
    cloud, the digests of the images it was made from and (``with_settings``)
    summary.json with the project's processing settings."""
    from designer.evaluate.writers import write_distances_ply
    from designer.gui.state import output_state
    from designer.gui.state.reconstruct_job import ReconstructJob
    from designer.sfm.settings import settings_dict

    survey = w.panels["Render"].out_dir
    job = ReconstructJob(path, survey)
    job.compare_dir.mkdir(parents=True)
    write_distances_ply(job.distances_ply, [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]], [0.01, 0.02])
    if with_settings:
        processing = w.document.project.processing or m.Processing()
        (job.out_dir / "summary.json").write_text(json.dumps(
            {"mode": job.mode, "settings": settings_dict(processing)}))
    output_state.record_reconstruction_inputs(survey, job.out_dir,
                                              output_state.manifest_digests(survey))


def reopen_reconstructed(qtbot, w, path) -> None:
    """Open ``path`` again and wait until the Results panel reads "reconstructed"."""
    assert w.open_project(path)
    wait_idle(qtbot, w)
    results = w.panels["Results"]
    wait_state(qtbot, w, lambda: results.out_of_date.text().startswith("reconstructed"))
