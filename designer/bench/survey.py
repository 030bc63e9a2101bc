"""Flight planning and coverage analysis at survey scale (``designer bench survey``).

The standard case: a 1 km × 1 km area at UTM-sized coordinates over a 1001 × 1001
(1 M vertex, 1 m) hilly terrain with about 90 m of relief, a DJI Phantom 4 Pro camera
flown with terrain following at 100 m AGL, 85 % front and 75 % side overlap (about
2,000 images), 20 GCPs. ``scale`` shrinks the area's side by √scale (the terrain
keeps its 1 m spacing) so tests can run it quickly.
"""

from __future__ import annotations

import math

import numpy as np

from designer.bench.table import Column, text_table
from designer.bench.timing import best_of
from designer.core.heightfield import Heightfield
from designer.core.interior import InteriorOrientation
from designer.core.raycast import TerrainRaycaster
from designer.survey import area as survey_area
from designer.survey import coverage, gcp_layout
from designer.survey.flight import plan_flight

ORIGIN_EN = (500000.0, 5000000.0)


def _terrain(side_m: float) -> Heightfield:
    n = round(side_m) + 1
    x = np.linspace(0.0, side_m, n)
    X, Y = np.meshgrid(x, x)
    Z = (300.0 + 30 * np.sin(X / 90) * np.cos(Y / 120) + 15 * np.sin(X / 37 + Y / 53)
         + 5 * np.cos(X / 11) * np.sin(Y / 13))
    return Heightfield(ORIGIN_EN[0], ORIGIN_EN[1], side_m / (n - 1), side_m / (n - 1), Z)


def _camera() -> InteriorOrientation:
    return InteriorOrientation(focal_length_mm=8.8, sensor_width_mm=13.2,
                               sensor_height_mm=8.8, image_width_px=5472,
                               image_height_px=3648)


def run(repeats: int = 3, scale: float = 1.0) -> list[dict]:
    """Time each step of ``designer plan`` on the standard case (best of ``repeats``)."""
    side = 1000.0 * math.sqrt(scale)
    hf = _terrain(side)
    area = survey_area.heightfield_area(hf)
    camera = _camera()
    gcp_xy = gcp_layout.random_stratified(20, area, min_spacing_m=side / 10, seed=7)
    gcp_xyz = gcp_layout.true_gcp_xyz(gcp_xy, hf)

    rows = []
    secs, plan = best_of(repeats, lambda: plan_flight(
        area, camera, altitude_agl_m=100.0, front_overlap_fraction=0.85,
        side_overlap_fraction=0.75, heightfield=hf, altitude_mode="terrain_following"))
    M = len(plan.stations)
    rows.append({"step": "flight plan", "images": M, "seconds": secs})
    secs, rc = best_of(repeats, lambda: TerrainRaycaster(hf))
    rows.append({"step": "terrain bounds (ray caster)", "images": M, "seconds": secs})
    secs, _ = best_of(repeats, lambda: coverage.analyse_stations(plan.stations, camera, rc))
    rows.append({"step": "station GSD + overlaps", "images": M, "seconds": secs})
    grid = coverage.ground_grid(hf, area)
    secs, _ = best_of(repeats, lambda: coverage.coverage_map(
        grid, plan.C_world, plan.R_cam_to_world, camera, rc))
    rows.append({"step": f"coverage map {grid.shape[1]}x{grid.shape[0]}, occlusion",
                 "images": M, "seconds": secs})
    secs, _ = best_of(repeats, lambda: coverage.gcp_visibility(
        gcp_xyz, plan.C_world, plan.R_cam_to_world, camera, rc))
    rows.append({"step": "GCP visibility (20 GCPs)", "images": M, "seconds": secs})
    secs, _ = best_of(repeats, lambda: coverage.analyse_plan(
        plan_flight(area, camera, altitude_agl_m=100.0, front_overlap_fraction=0.85,
                    side_overlap_fraction=0.75, heightfield=hf,
                    altitude_mode="terrain_following"),
        camera, hf, area, gcp_xyz=gcp_xyz))
    rows.append({"step": "total: plan + analyse_plan", "images": M, "seconds": secs})
    return rows


def format_table(rows: list[dict]) -> str:
    return text_table(
        [Column("step", "<40", "step"), Column("images", ">7d", "images"),
         Column("seconds", ">9.3f", "seconds")], rows,
        "(1 km^2, 1 M-vertex terrain at UTM coordinates; one process, numpy "
        "single-threaded; best of the repeats)")
