"""Refresh the screenshots of the desktop designer in docs/images.

    .venv/bin/python scripts/gui_screenshots.py [--out docs/images]

On the example survey (``designer new --template survey``) in a 1600 × 1000 window, on
a virtual X display (Xvfb) when there is none:

* ``gui-window.png`` — the window as it opens;
* ``gui-panel-<name>.png`` — each panel (its dock), one per panel of the window (the
  Results panel with the synthetic cloud below in it; Buildings, Moving objects and
  Vegetation with a house, a car (the photos given times) and shrubs added, taken away
  after the shot);
* ``gui-coverage.png`` — the 3D view with the coverage heat map (H);
* ``gui-results-window.png`` — a synthetic cloud coloured by its signed distance to the
  true surface: 300,000 points on the terrain and targets, plus a smooth 3 cm bowl and
  1 cm noise (seeded), 25 gross outliers (up to 1.4 km below), with GCP estimates off by
  1–2 cm (drawn in the view as exaggerated error lines);
* ``gui-refused-input.png`` — the Flight panel refusing a front overlap of 150 %;
* ``gui-place-mode.png`` — the window in the place-GCPs mode (banner) with the cursor
  off the terrain (status bar);
* ``gui-out-of-date.png`` — the Render panel after a quick draft render and a terrain
  edit: what is out of date and the button that re-renders it;
* ``gui-flight-beyond.png`` — the Flight panel warning about a flight that looks far
  beyond the terrain (the same survey without surroundings, flown at 120 m);
* ``gui-site-orthophoto.png`` — the sample site (``scripts/make-sample-site.py``) made
  into a project as File ▸ Import site does, its orthophoto draped in the view;
* ``gui-import-flight.png`` — the example survey with its first 12 photos imported back
  from DJI-tagged images (File ▸ Import flight ▸ From a folder of images…);
* ``gui-study-panel.png`` — the Study panel, whole: a study of the tiny test survey
  (``designer study new --template tiny``'s base: marking error 0.2 / 2 px and sun
  elevation 40°) built in it, run from it (about a minute) and its results shown
  (``--study-only`` takes just this one).

Pictures over 300 kB are written as 256-colour PNGs. Each window runs with a designer
cache folder of its own: the render estimates shown are the reference machine's, and the
draft render calibrates neither this machine's estimates nor the later shots'.

``designer gui FILE.xml --screenshot OUT.png --panel NAME`` takes one such shot of the
whole window from the command line.
"""

from __future__ import annotations

import argparse
import dataclasses
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]


def _write_cloud(path: Path, xyz: np.ndarray) -> None:
    from plyfile import PlyData, PlyElement

    data = np.empty(len(xyz), dtype=[("x", "f8"), ("y", "f8"), ("z", "f8")])
    data["x"], data["y"], data["z"] = xyz.T
    PlyData([PlyElement.describe(data, "vertex")]).write(str(path))


def _synthetic_results(window, folder: Path) -> tuple[Path, Path]:
    """A cloud over the flight area and a GCP estimate table (seeded)."""
    rng = np.random.default_rng(7)
    hf = window.sync.terrain.heightfield
    area = np.array(window.document.project.trajectory.flight_plan.area)
    lo, hi = area.min(axis=0), area.max(axis=0)
    centre, radius = (lo + hi) / 2, 0.5 * float(np.max(hi - lo))
    xy = rng.uniform(lo - 15, hi + 15, (300_000, 2))
    r2 = np.sum((xy - centre) ** 2, axis=1) / radius**2
    # a bowl, 3 cm deep in the middle, flat beyond the radius
    dz = 0.03 * (np.minimum(r2, 1.0) - 0.5) + rng.normal(0.0, 0.01, len(xy))
    # and a few gross outliers (mismatches), one of them 1.4 km below the ground
    dz[rng.choice(len(xy), 25, replace=False)] = -rng.uniform(0.5, 1400.0, 25)
    xyz = np.column_stack([xy, hf.height_at_clamped(xy[:, 0], xy[:, 1]) + dz])
    cloud = folder / "cloud.ply"
    _write_cloud(cloud, xyz)
    targets = window.sync.targets
    rows = ["id,role,X,Y,Z"]
    for gcp_id, role, p in zip(targets.ids, targets.roles, targets.true_xyz, strict=True):
        e = rng.normal(0.0, [0.012, 0.012, 0.015])
        rows.append(f"{gcp_id},{role},{p[0] + e[0]:.4f},{p[1] + e[1]:.4f},{p[2] + e[2]:.4f}")
    residuals = folder / "gcp_residuals.csv"
    residuals.write_text("\n".join(rows) + "\n")
    return cloud, residuals


def _fresh_cache() -> None:
    """A designer cache folder of its own: the render estimates shown are the reference
    machine's (the same on every machine), and the draft render calibrates neither this
    machine's estimates nor a later shot's."""
    os.environ["DESIGNER_CACHE_DIR"] = tempfile.mkdtemp(prefix="designer-screenshots-cache-")


def take(out: Path) -> list[Path]:
    from PySide6.QtCore import QSettings

    from designer.gui.app import application, wait_idle
    from designer.gui.qt.main_window import MainWindow

    _fresh_cache()
    work = Path(tempfile.mkdtemp(prefix="designer-screenshots-"))
    project = work / "survey.xml"
    subprocess.run([sys.executable, "-m", "designer", "new", str(project), "--template",
                    "survey"], check=True, capture_output=True)
    app = application()
    window = MainWindow(QSettings(str(work / "settings.ini"), QSettings.Format.IniFormat))
    window.resize(1600, 1000)
    window.show()
    if not window.open_project(project):
        raise SystemExit(f"cannot open {project}")
    wait_idle(window)
    written = []

    def shot(name: str, widget=None) -> None:
        app.processEvents()
        wait_idle(window)
        window.save_screenshot(out / name, widget)
        written.append(out / name)

    shot("gui-window.png")
    _processing_settings(window)
    # the panels of things the example has none of: one added (and taken away again)
    adds = {"Buildings": "add_house", "Moving objects": "add_car"}
    for title, dock in window.docks.items():
        # Results: below, with a cloud in it; Study: gui-study-panel.png, with a study
        if title in ("Problems", "Results", "Study"):
            continue
        dock.show()
        dock.raise_()
        if title == "GCPs":  # show the last columns: surveyed positions, images per GCP
            bar = window.panels["GCPs"].table.horizontalScrollBar()
            bar.setValue(bar.maximum())
        panel = window.panels.get(title)
        steps = window.undo_stack.index()
        if title == "Moving objects":  # they move on the flight's time line
            window.panels["Flight"].timed.click()
        if title in adds:
            getattr(panel, adds[title]).click()
        elif title == "Vegetation":
            panel.add_buttons["shrub"].click()
        shot(f"gui-panel-{title.lower().replace(' ', '-')}.png", dock)
        if title == "GCPs":  # the later window shots show the ids and roles again
            bar.setValue(0)
        while window.undo_stack.index() > steps:
            window.undo_stack.undo()
    window.docks["Terrain"].raise_()
    window.docks["Flight"].raise_()

    window.coverage_action.setChecked(True)
    shot("gui-coverage.png", window.view)
    window.coverage_action.setChecked(False)

    # saved, the cloud is measured against the file's terrain and GCP plates, as
    # designer compare measures it
    window.file_actions.save()
    cloud, residuals = _synthetic_results(window, work)
    for layer in ("frusta", "footprints", "flight"):
        window.view.set_layer_visible(layer, False)
    results = window.panels["Results"]
    results.open_cloud(cloud)
    wait_idle(window)
    results.open_residuals(residuals)
    window.docks["Results"].raise_()
    shot("gui-panel-results.png", window.docks["Results"])
    window.docks["GCPs"].raise_()
    shot("gui-results-window.png")
    results.clear()

    # a typed value out of range: refused, red, said why
    from PySide6.QtCore import Qt
    from PySide6.QtTest import QTest
    from PySide6.QtWidgets import QDoubleSpinBox

    window.docks["Flight"].raise_()
    window.activateWindow()
    box = window.findChild(QDoubleSpinBox, "trajectory.flight_plan.front_overlap_percent")
    box.setFocus()
    box.selectAll()
    QTest.keyClicks(box.lineEdit(), "150")
    QTest.keyClick(box.lineEdit(), Qt.Key.Key_Return)
    shot("gui-refused-input.png", window.docks["Flight"])
    # the project's value typed back: the refusal leaves the panel and the status bar
    box.selectAll()
    QTest.keyClicks(box.lineEdit(), "80")
    QTest.keyClick(box.lineEdit(), Qt.Key.Key_Return)
    window.view.plotter.setFocus()

    # the place-GCPs mode, the cursor over the background
    window.panels["GCPs"].place.setChecked(True)
    window.view.ground_hovered.emit(())
    shot("gui-place-mode.png")
    window.view.interaction.set_mode("navigate")

    # the same survey without surroundings, flown high: images look beyond the terrain
    import dataclasses

    from designer.gui.state import edits

    bare = window.document.project
    bare = dataclasses.replace(bare, scene=dataclasses.replace(bare.scene, terrain=(
        dataclasses.replace(bare.scene.terrain, surroundings="none"))))
    window.editor.edit(edits.set_flight(bare, altitude_agl_m=120.0), "Flight height")
    shot("gui-flight-beyond.png", window.docks["Flight"])
    window.undo_stack.undo()
    _render_then_edit(window, project)
    shot("gui-out-of-date.png", window.docks["Render"])
    window.close_without_prompt()
    return written + take_site(out) + take_import_flight(out) + take_study(out)


def take_site(out: Path) -> list[Path]:
    """The sample site (scripts/make-sample-site.py's DEM and orthophoto) imported as
    File → Import site does, the Flight panel in front."""
    from PySide6.QtCore import QSettings

    from designer.gui.app import application, wait_idle
    from designer.gui.qt.main_window import MainWindow
    from designer.scene.sample_site import write_sample_site

    _fresh_cache()
    work = Path(tempfile.mkdtemp(prefix="designer-screenshots-site-"))
    files = write_sample_site(work, geographic=False)
    app = application()
    window = MainWindow(QSettings(str(work / "settings.ini"), QSettings.Format.IniFormat))
    window.resize(1600, 1000)
    window.show()
    if not window.site_flight_actions.make_site_project(files["dem"], files["orthophoto"],
                                                        work / "site.xml"):
        raise SystemExit("cannot make the sample site's project")
    window.docks["Terrain"].raise_()
    window.docks["Flight"].raise_()
    _until(lambda: window.sync.plan is not None and not window.tasks.busy,
           "the site's flight figures")
    app.processEvents()
    wait_idle(window)
    path = out / "gui-site-orthophoto.png"
    window.save_screenshot(path)
    window.close_without_prompt()
    return [path]


def take_import_flight(out: Path) -> list[Path]:
    """The example survey with its first 12 planned photos imported back as DJI-tagged
    images (File → Import flight → From a folder of images…)."""
    import shutil

    from PySide6.QtCore import QSettings

    from designer.gui.app import application, wait_idle
    from designer.gui.qt.main_window import MainWindow

    sys.path.insert(0, str(ROOT))  # the tests' writer of DJI-tagged images
    from designer.project import load_project
    from tests.flight.helpers import true_poses, write_dji_image

    _fresh_cache()
    work = Path(tempfile.mkdtemp(prefix="designer-screenshots-flown-"))
    example = ROOT / "resources" / "examples" / "survey"
    shutil.copytree(example, work / "survey")
    project = load_project(work / "survey" / "survey.xml")
    (work / "flown").mkdir()
    for k, pose in enumerate(true_poses(project, work / "survey")[:12]):
        write_dji_image(work / "flown" / f"DJI_{k + 1:04d}.JPG", pose, project.crs)
    app = application()
    window = MainWindow(QSettings(str(work / "settings.ini"), QSettings.Format.IniFormat))
    window.resize(1600, 1000)
    window.show()
    if not window.open_project(work / "survey" / "survey.xml"):
        raise SystemExit("cannot open the example survey")
    wait_idle(window)
    if not window.site_flight_actions.import_flight(work / "flown"):
        raise SystemExit("cannot import the flown images")
    window.docks["Terrain"].raise_()
    window.docks["Flight"].raise_()
    _until(lambda: window.sync.plan is not None and not window.tasks.busy,
           "the imported flight's figures")
    app.processEvents()
    wait_idle(window)
    path = out / "gui-import-flight.png"
    window.save_screenshot(path)
    window.close_without_prompt()
    return [path]


def _until(condition, what: str, timeout_s: float = 900.0) -> None:
    import time

    from PySide6.QtWidgets import QApplication

    deadline = time.monotonic() + timeout_s
    while not condition():
        QApplication.instance().processEvents()
        time.sleep(0.05)
        if time.monotonic() > deadline:
            raise SystemExit(f"{what} did not happen in {timeout_s:.0f} s")


def take_study(out: Path) -> list[Path]:
    """The Study panel with a tiny study built, run and its results shown."""
    from PySide6.QtCore import QSettings

    from designer.gui.app import application, wait_idle
    from designer.gui.qt.main_window import MainWindow
    from designer.study.templates import write_template

    _fresh_cache()
    work = Path(tempfile.mkdtemp(prefix="designer-screenshots-study-"))
    write_template("tiny", work / "tiny.xml")
    app = application()
    window = MainWindow(QSettings(str(work / "settings.ini"), QSettings.Format.IniFormat))
    window.resize(1600, 1000)
    window.show()
    if not window.open_project(work / "tiny-base.xml"):
        raise SystemExit("cannot open the tiny study's base project")
    wait_idle(window)
    panel = window.panels["Study"]
    window.docks["Study"].raise_()
    panel.name.setText("marks-and-sun")
    panel.add_factor("marking-sigma-px", "0.2 2")
    panel.add_factor("sun-elevation-deg", "40")
    panel.vary["marking-error"].setChecked(True)
    if not panel.save_study(work / "marks-and-sun.xml"):
        raise SystemExit(f"cannot save the study: {panel.errors.text()}")
    _until(lambda: panel.plan is not None and not window.tasks.busy, "the study check")
    panel.run_box.workers.setValue(2)
    _until(lambda: panel.plan is not None and not window.tasks.busy, "the study check")
    panel.run_box.run()
    _until(lambda: not panel.run_box.process.running, "the study run")
    panel.results.select_figure("marking-sigma-px: check-point RMSE Z (m)")
    app.processEvents()
    wait_idle(window)
    inner = panel.body.parentWidget()
    inner.adjustSize()
    app.processEvents()
    path = out / "gui-study-panel.png"
    inner.grab().save(str(path))
    window.close_without_prompt()
    return [path]


def _processing_settings(window) -> None:
    """Processing as a survey with RTK positions and a dense cloud would set it."""
    from designer.project import model as m

    processing = m.Processing(
        calibration=m.Calibration("radial", m.PreCalibrationError(5.0, 2.0, 0.01, seed=1)),
        gcps=m.GcpProcessing("bundle", 0.5, 2), position_prior=m.PositionPrior("rtk"),
        matching=m.Matching(8192, "footprint", 3), dense="cpu")
    window.editor.edit(dataclasses.replace(window.document.project, processing=processing),
                       "processing settings")


def _render_then_edit(window, project: Path, timeout_s: float = 600.0) -> None:
    """A quick draft render of part of the survey, then the terrain made higher in the
    window: the Render panel says what is out of date."""
    import time

    from designer.gui.state import edits
    from designer.project import model as m

    p = window.document.project
    E0, N0 = p.origin.E0, p.origin.N0
    p = edits.set_flight(p, area=((E0 - 15, N0 - 15), (E0 + 15, N0 - 15), (E0 + 15, N0 + 15),
                                  (E0 - 15, N0 + 15)))
    p = edits.replace_path(p, "render", m.Render(preset="draft", resolution_scale=0.0625,
                                                 workers=2))
    window.editor.edit(p, "a quick draft render")
    if not window.file_actions.save_to(project):
        problems = [window.problems.item(i).text() for i in range(window.problems.count())]
        raise SystemExit(f"cannot save {project}: {problems}")
    render = window.panels["Render"]
    render.start()
    deadline = time.monotonic() + timeout_s
    from PySide6.QtWidgets import QApplication

    app = QApplication.instance()
    while render.process.running:
        app.processEvents()
        time.sleep(0.05)
        if time.monotonic() > deadline:
            raise SystemExit("the draft render did not finish")
    window.editor.edit(edits.replace_path(window.document.project,
                                          "scene.terrain.source.max_height_m", 14.0),
                       "Terrain highest height")
    window.docks["Render"].raise_()
    while not (render.out_of_date.stale and not window.stale_watch.pending
               and not window.tasks.busy):
        app.processEvents()
        time.sleep(0.05)
        if time.monotonic() > deadline:
            raise SystemExit("the out-of-date state did not appear")


def _compact(path: Path, limit_bytes: int = 300_000) -> None:
    """Rewrite a picture of more than ``limit_bytes`` as a 256-colour PNG (octree: the
    small red and blue GCP marks keep their colours), the others optimised losslessly."""
    from PIL import Image

    image = Image.open(path)
    image.load()
    if path.stat().st_size > limit_bytes:
        image = image.convert("RGB").quantize(colors=256, method=Image.Quantize.FASTOCTREE,
                                              kmeans=2)
    image.save(path, "PNG", optimize=True)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=ROOT / "docs" / "images")
    parser.add_argument("--study-only", action="store_true",
                        help="take only gui-study-panel.png")
    args = parser.parse_args()
    from designer.gui.xvfb import ensure_display, stop_xvfb

    xvfb = ensure_display()
    try:
        for path in (take_study if args.study_only else take)(args.out):
            _compact(path)
            print(path)
    finally:
        if xvfb is not None:
            from PySide6.QtWidgets import QApplication

            if QApplication.instance() is not None:
                QApplication.instance().shutdown()
            stop_xvfb(xvfb)
    return 0


if __name__ == "__main__":
    sys.exit(main())
