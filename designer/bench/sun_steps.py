"""Light maps over a flight (``designer bench sun-steps``): the cost of baking one light
map per sun, and the error other choices would bring.

On the example survey's terrain (100 × 100 m of hills, 512 × 512 texel light map) under
the sun of a flight on 21 June at 47.37° N 8.54° E — at 09:30 UTC (sun high, the hills
cast no shadow) and at 04:45 UTC (sun low, long moving shadows) — designer bakes one
exact light map per photo's sun. Two cheaper choices are compared against the exact
bake at the worst moment of each step Δt:

* nearest: bake at the middle of each step, use it for the whole step (the worst image
  is Δt/2 away from its bake);
* interpolate: bake at the step ends and blend the two maps linearly (worst in the
  middle: two half shadows instead of one moved shadow).

Errors are in light units (1 = flat ground in full sun) over all texels: the largest
and the share of texels off by more than one 8-bit grey level of that unit (1/255).
"""

from __future__ import annotations

import datetime as _dt
import time

import numpy as np

from designer.bench.table import Column, text_table
from designer.project import template
from designer.scene.build import build_scene
from designer.scene.lighting import bake_lightmap
from designer.scene.sun_over_time import Site, sun_at

TAKEOFFS = (_dt.datetime(2026, 6, 21, 9, 30, tzinfo=_dt.UTC),
            _dt.datetime(2026, 6, 21, 4, 45, tzinfo=_dt.UTC))
SITE = Site(47.37, 8.54)
STEPS_S = (60, 300, 600)


def run(repeats: int = 1, scale: float = 1.0) -> list[dict]:
    from tempfile import TemporaryDirectory

    tpl = template("survey")
    with TemporaryDirectory() as tmp:
        scene = build_scene(tpl.project, tmp)
    hf = scene.heightfield
    size = (max(2, round(512 * scale)),) * 2

    def bake(takeoff, t_s: float) -> tuple[np.ndarray, float]:
        az, el = sun_at(takeoff + _dt.timedelta(seconds=t_s), SITE)
        best = float("inf")
        for _ in range(max(1, repeats)):
            t0 = time.perf_counter()
            light = bake_lightmap(hf, az, el, scene.sun_strength, scene.sky_strength, size)
            best = min(best, time.perf_counter() - t0)
        return light, best

    rows = []
    for takeoff, step in ((t, s) for t in TAKEOFFS for s in STEPS_S):
        exact, seconds = bake(takeoff, step / 2)
        start, _ = bake(takeoff, 0.0)
        end, _ = bake(takeoff, float(step))
        az0, el0 = sun_at(takeoff, SITE)
        az1, _ = sun_at(takeoff + _dt.timedelta(seconds=step), SITE)
        for method, approx in (("nearest", start), ("interpolate", 0.5 * (start + end))):
            error = np.abs(approx - exact)
            rows.append({"utc": takeoff.strftime("%H:%M"), "elevation_deg": el0,
                         "step_s": step, "sun_moves_deg": abs(az1 - az0), "method": method,
                         "max_error": float(error.max()),
                         "share_over_1_255": float(np.mean(error > 1 / 255)),
                         "bake_s": seconds, "texels": f"{size[0]}x{size[1]}"})
    return rows


def format_table(rows: list[dict]) -> str:
    return text_table(
        [Column("UTC", ">5", "utc"),
         Column("sun el", ">6", lambda r: f"{r['elevation_deg']:>5.1f}°"),
         Column("step s", ">6", "step_s"),
         Column("sun moves", ">9", lambda r: f"{r['sun_moves_deg']:>8.2f}°"),
         Column("method", "<11", "method"), Column("max error", ">9.3f", "max_error"),
         Column("texels > 1/255", ">14", lambda r: f"{100 * r['share_over_1_255']:>13.2f}%"),
         Column("bake s", ">7.2f", "bake_s"), Column("light map", ">9", "texels")], rows,
        "error at the worst moment of a step against the exact bake, light units (1 = flat "
        "ground in full sun); nearest: a bake Δt/2 away; interpolate: the blend of the bakes "
        "at both ends; bake s: one exact light map")
