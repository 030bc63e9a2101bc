"""Responsiveness of the designer window (``designer bench gui``).

The case: a 1 km × 1 km procedural terrain at UTM coordinates with a 1 m grid
(1001 × 1001 = 1,002,001 vertices), a Phantom 4 Pro flying a terrain-following grid at
100 m above ground with 85 % / 75 % overlap (about 2,160 camera stations, each drawn
as a frustum, a ground footprint and part of a flight line). Measured: the time from a
flight-parameter edit (the height above ground, as a person types it into the Flight
panel) to the first frame showing the new stations — the edit goes through the undo
stack, the document event, the stations job in a worker thread and the view update.

The height field keeps every vertex for ray casts, picking and footprints. On a
software OpenGL (Mesa llvmpipe under Xvfb, as in CI) the 3D view draws every 4th node
(251 × 251) and skips FXAA, as every pixel costs CPU there; on a GPU it draws up to 1024
nodes per side with FXAA. Either way the terrain is lit by a colour per vertex (the
project's sun and sky, computed with the terrain in a worker thread), not per pixel.
The frame time of the full-resolution terrain with FXAA is measured too. ``scale``
shrinks the area's side by √scale (tests run it small).

``images=N`` (``designer bench gui --images N``) measures a survey instead (issue 53, at
survey size): the ``survey-block`` template (720 images) with its flight area and terrain
scaled to about N images, written to a file and opened as File → Open does. Measured: the
opening (file read to the last background job), the flight-height edit → frame median
and worst, the longest the event loop went without running (a freeze; none may pass 5 s),
and whether the window's render estimate and void figures are ``designer plan``'s.
"""

from __future__ import annotations

import math
import statistics
import tempfile
import time
from pathlib import Path

from designer.bench.table import Column, text_table

#: edits timed (each alternates the flight height, so every one changes the stations)
EDITS = 7


def _project(side_m: float):
    from designer.gui.state import camera_presets
    from designer.project import model as m

    E0, N0 = 500000.0, 5000000.0
    extent = m.Extent(E0, N0, E0 + side_m, N0 + side_m)
    cam = camera_presets.preset("p4p").camera()
    scene = m.Scene(
        terrain=m.Terrain(extent, m.ProceduralTerrain(seed=4, grid_spacing_m=1.0,
                                                      roughness=0.4, min_height_m=250.0,
                                                      max_height_m=340.0)),
        texture=m.Texture(m.ProceduralTexture("grass", 1, 0.05), repeat_X=20, repeat_Y=20,
                          interpolation="linear"),
        lighting=m.Lighting(m.Sun(135.0, 50.0)))
    area = ((E0, N0), (E0 + side_m, N0), (E0 + side_m, N0 + side_m), (E0, N0 + side_m))
    plan = m.FlightPlan(camera=cam.id, image_prefix="IMG_", area=area, altitude_agl_m=100.0,
                        front_overlap_percent=85.0, side_overlap_percent=75.0,
                        terrain_following=True)
    return m.Project(name="GUI benchmark", crs="EPSG:32632", origin=m.Origin(E0, N0, 0.0),
                     scene=scene, cameras=(cam,), trajectory=m.Trajectory(flight_plan=plan))


def run(repeats: int = 3, scale: float = 1.0, images: int | None = None) -> list[dict]:
    """Time flight-parameter edits → updated frames (``repeats`` is ignored: EDITS edits).
    With ``images``: a survey of about that many images (see the module doc)."""
    from designer.gui.xvfb import ensure_display, stop_xvfb

    xvfb = ensure_display()
    try:
        if images is not None:
            from designer.bench.gui_survey import run_survey

            return run_survey(images)
        return _run(scale)
    finally:
        if xvfb is not None:
            from PySide6.QtWidgets import QApplication

            if QApplication.instance() is not None:
                QApplication.instance().shutdown()
            stop_xvfb(xvfb)


def _run(scale: float) -> list[dict]:
    from PySide6.QtCore import QSettings

    from designer.gui.app import application, wait_idle
    from designer.gui.qt.main_window import MainWindow
    from designer.gui.state import edits

    app = application()
    side = round(1000.0 * math.sqrt(scale))
    tmp = Path(tempfile.mkdtemp(prefix="designer-bench-gui-"))
    window = MainWindow(QSettings(str(tmp / "settings.ini"), QSettings.Format.IniFormat))
    window.resize(1600, 1000)
    window.show()
    t0 = time.perf_counter()
    window.document.reset(_project(side), None, tmp)
    wait_idle(window, 600)
    load_s = time.perf_counter() - t0
    sync, view = window.sync, window.view
    n_vertices = sync.terrain.n_vertices
    shown = len(sync.terrain.display.points_world)

    times, computes = [], []
    for k in range(EDITS):
        altitude = 100.0 + 0.5 * (k + 1) * (-1) ** k
        new = edits.set_flight(window.document.project, altitude_agl_m=altitude)
        total, compute = _time_edit(window, new, altitude)
        times.append(total)
        computes.append(compute)
    n_stations = sync.stations.n_images

    # One frame, as drawn, and with the terrain at full resolution for comparison.
    frame_s = _frame_seconds(app, view)
    from designer.gui.state.derived import display_irradiance
    from designer.gui.state.view_geometry import terrain_display

    t = sync.terrain
    full = terrain_display(t.heightfield, None, t.tiles, max_nodes_per_side=10**6)
    light = display_irradiance(window.document.project.scene.lighting, full, t.heightfield,
                               t.raycaster)
    if view.software_gl:
        view.plotter.enable_anti_aliasing("fxaa")  # as on a GPU: full mesh and FXAA
    view.show_terrain(full.points_world, full.faces, full.uv, sync.texture_rgb,
                      irradiance=light)
    full_frame_s = _frame_seconds(app, view)
    window.close_without_prompt()

    label = f"{n_vertices:,} vertices, {n_stations:,} frusta"
    return [
        {"step": "open: terrain, texture, stations (threads)", "case": label,
         "ms": 1000 * load_s},
        {"step": "edit -> stations recomputed (median)", "case": label,
         "ms": 1000 * statistics.median(computes)},
        {"step": "edit -> updated frame (median)", "case": label,
         "ms": 1000 * statistics.median(times)},
        {"step": "edit -> updated frame (worst)", "case": label, "ms": 1000 * max(times)},
        {"step": f"one frame, terrain drawn at {shown:,} vertices", "case": label,
         "ms": 1000 * frame_s},
        {"step": "one frame, full-resolution terrain + FXAA", "case": label,
         "ms": 1000 * full_frame_s},
    ]


def _time_edit(window, new, altitude: float) -> tuple[float, float]:
    """Seconds from the edit to (the first frame showing the new stations, new stations)."""
    from designer.bench.gui_survey import time_flight_edit

    marks = time_flight_edit(window, new, altitude)
    return marks["frame"], marks["stations"]


def _frame_seconds(app, view, n: int = 5) -> float:
    best = math.inf
    view.render_now()
    for k in range(n):
        view.plotter.camera.azimuth = view.plotter.camera.azimuth + (-1) ** k
        t0 = time.perf_counter()
        view.render_now()
        app.processEvents()
        best = min(best, time.perf_counter() - t0)
    return best


def format_table(rows: list[dict]) -> str:
    if rows and "value" in rows[0]:
        from designer.bench.gui_survey import format_survey_table

        return format_survey_table(rows)
    return text_table(
        [Column("step", "<46", "step"), Column("ms", ">8.0f", "ms")], rows,
        f"({rows[0]['case']}; {EDITS} flight-height edits; 1600 x 1000 window; OpenGL as "
        "available, Mesa llvmpipe under Xvfb here)", rule_width=56)
