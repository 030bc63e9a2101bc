"""Render time as the example survey's terrain grows (``designer bench render-sizes``).

The example survey (100 m terrain, 70 m flight area) and the same survey with its terrain
grown to 500 m and 1.2 km and its flight area to 350 m and 1 km — the same camera,
overlaps and texture (its 20 m tile repeated over the extent), as a researcher scales it
to a real site (issue 52). For each size and each way the renderer can draw the varied
texture — the node graph (Cycles blends the variation per sample: what a terrain too
wide for one bake got before the tiled bake) and the bake (one image up to
``MAX_BAKE_PX`` a side, tiles beyond) — one worker renders ``FRAMES`` frames in the
middle of the flight. Per row: Cycles wall and CPU seconds per image (each worker's first
frame, which builds Cycles' scene, left out), the frame set-up per image (the tiles' bake
and load), the worker's peak memory, and the render-time model's Cycles CPU seconds per
image for those frames with its ratio to the measured: the model as ``designer plan``
has it on a machine that has rendered the example and nothing else (a record fitted to
the example's baked row, in a cache folder of the run's own), so the rows of other
sizes and paths are estimated through the texture path's priors
(``designer.render_time.model.TEXTURE_PATH_CYCLES``). Every row renders in its own
worker process, one after the other in one run.
"""

from __future__ import annotations

import os
import tempfile
import time
from collections.abc import Callable
from dataclasses import replace
from pathlib import Path

import numpy as np

from designer.project import model as m
from designer.project import template, write_project
from designer.render.job import prepare_job
from designer.render.runner import render_frames
from designer.render.tiled_bake import TileGrid, swap_frames
from designer.render_time.model import (
    REFERENCE,
    fit_speed,
    frame_cpu_s,
    image_costs,
    load_speed,
    save_speed,
)
from designer.render_time.record import job_texture_path

#: (terrain side, flight area side) in metres
SIZES = ((100.0, 70.0), (500.0, 350.0), (1200.0, 1000.0))
#: frames rendered per row, in the middle of the flight (the first one builds the scene)
FRAMES = 6
#: the example's texture tile (m): kept as the terrain grows
TILE_M = 20.0


def grown_example(terrain_m: float, area_m: float,
                  image_texture: Path | None = None) -> m.Project:
    """The example survey with a ``terrain_m`` square terrain and ``area_m`` square flight
    area about the same centre, its texture tile kept at TILE_M; with ``image_texture``
    (a PNG file to write) the texture is that file, holding the example's procedural
    tile: the same texels from an image (the source given relative to the file's folder,
    where the project is to be written)."""
    project = template("survey").project
    if image_texture is not None:
        project = _with_image_texture(project, Path(image_texture))
    terrain = project.scene.terrain
    e = terrain.extent
    cx, cy = (e.min_X + e.max_X) / 2, (e.min_Y + e.max_Y) / 2
    h, a = terrain_m / 2, area_m / 2
    extent = replace(e, min_X=cx - h, max_X=cx + h, min_Y=cy - h, max_Y=cy + h)
    repeats = max(1, round(terrain_m / TILE_M))
    texture = replace(project.scene.texture, repeat_X=repeats, repeat_Y=repeats)
    scene = replace(project.scene, terrain=replace(terrain, extent=extent), texture=texture)
    plan = project.trajectory.flight_plan
    area = ((cx - a, cy - a), (cx + a, cy - a), (cx + a, cy + a), (cx - a, cy + a))
    trajectory = replace(project.trajectory, flight_plan=replace(plan, area=area))
    return replace(project, scene=scene, trajectory=trajectory)


def _with_image_texture(project: m.Project, path: Path) -> m.Project:
    import cv2

    from designer.scene.texture import procedural_texture

    texture = project.scene.texture
    src = texture.source
    side_px = round(TILE_M / src.texel_size_m)
    rgb = procedural_texture((side_px, side_px), src.seed, kind=src.pattern)
    if not cv2.imwrite(str(path), cv2.cvtColor(rgb, cv2.COLOR_RGB2BGR)):
        raise OSError(f"could not write {path}")
    texture = replace(texture, source=m.ImageTexture(file=path.name))
    return replace(project, scene=replace(project.scene, texture=texture))


def run(repeats: int = 1, scale: float = 1.0,
        on_row: Callable[[dict], None] | None = None, frames: int = FRAMES,
        node_graph: bool = True, sources: tuple[str, ...] = ("procedural",)) -> list[dict]:
    """One row per terrain size and texture path (module docstring); ``scale`` < 1 keeps
    the sizes whose terrain is at most ``scale`` × 1.2 km; ``frames`` rendered per row
    (more take in more of the frames that swap tiles: about one in 18 over a flight);
    ``node_graph`` False leaves out the node graph's rows; ``sources``: the grown
    terrains' texture sources, "procedural" (the example's) and "image" (an image file
    holding the same texels: its bake's rows only). The example's baked row comes first
    in any case: the model's one record."""
    rows = []
    cache = os.environ.get("DESIGNER_CACHE_DIR")
    with tempfile.TemporaryDirectory(prefix="designer-bench-sizes-") as tmp:
        tmp = Path(tmp)
        os.environ["DESIGNER_CACHE_DIR"] = str(tmp / "cache")
        try:
            # the example's baked row first: the model's one record
            paths = (False, True) if node_graph else (True,)
            order = [(SIZES[0], True, False)] + [(SIZES[0], False, False)] * node_graph
            for size in SIZES[1:]:
                order += [(size, bake, False) for bake in paths] * ("procedural" in sources)
                order += [(size, True, True)] * ("image" in sources)
            for (terrain_m, area_m), bake, image in order:
                if terrain_m > scale * SIZES[-1][0]:
                    continue
                name = f"{terrain_m:.0f}-{bake}-{'image' if image else 'procedural'}"
                png = tmp / f"texture-{name}.png" if image else None
                project = grown_example(terrain_m, area_m, png)
                path = tmp / f"survey-{name}.xml"
                write_project(project, path)
                row = _row(project, path, tmp / name, bake, calibrate=not rows, count=frames)
                row["terrain_m"] = terrain_m
                row["source"] = "image" if image else "procedural"
                rows.append(row)
                if on_row is not None:
                    on_row(row)
        finally:
            if cache is None:
                os.environ.pop("DESIGNER_CACHE_DIR", None)
            else:
                os.environ["DESIGNER_CACHE_DIR"] = cache
    return rows


def _row(project: m.Project, path: Path, out: Path, bake: bool, calibrate: bool,
         count: int = FRAMES) -> dict:
    """One row (module docstring); ``calibrate``: first store the model's record fitted
    to this row's frames."""
    t0 = time.perf_counter()
    prepared = prepare_job(project, path.parent, out, bake_texture=bake)
    prepare_s = time.perf_counter() - t0
    n = len(prepared.job.frames)
    mid = n // 2
    frames = list(range(max(0, mid - 1), min(n, mid - 1 + count)))
    report = render_frames(prepared.job_path, frames, workers=1)
    timed = [i for i in frames if i in report.rendered and i not in report.first_frames]
    cycles = [report.stages[i]["cycles_s"] for i in timed]
    cpu = [report.stages[i]["cycles_cpu_s"] for i in timed]
    setup = [report.stages[i].get("setup_s", 0.0) for i in timed]
    path_name = job_texture_path(prepared.job)
    swaps = float("nan")
    spec = prepared.job.tiled_texture
    if spec is not None:
        grid = TileGrid(tuple(spec.full_px), spec.core_px, spec.pad_px)
        swaps = swap_frames(grid, tuple(spec.slots), [f.texture_tiles for f in prepared.job.frames])
    poses = [prepared.poses[i] for i in timed]
    costs = image_costs(prepared.scene.heightfield,
                        np.array([p.C_world for p in poses]).reshape(-1, 3),
                        np.array([p.R_cam_to_world for p in poses]).reshape(-1, 3, 3),
                        [prepared.interior_of(p.image_name) for p in poses],
                        prepared.job.render.samples, project, path_name)
    if calibrate and costs:
        post = [report.rendered[i] - report.stages[i]["cycles_s"] for i in timed]
        save_speed(fit_speed(costs, cpu, post, prepare_s, "render", prior=REFERENCE), costs[0])
    model = [frame_cpu_s(load_speed(c), c) for c in costs]
    measured = float(np.mean(cpu)) if cpu else float("nan")
    estimate = float(np.mean(model)) if model else float("nan")
    return {"images": n, "texture": path_name, "frames": len(timed),
            "prepare_s": prepare_s,
            "cycles_s": float(np.mean(cycles)) if cycles else float("nan"),
            "cycles_cpu_s": measured,
            "setup_s": float(np.mean(setup)) if setup else float("nan"),
            "peak_rss_mb": max(report.peak_rss_mb or [float("nan")]),
            "model_cpu_s": estimate, "model_ratio": estimate / measured,
            "cpu_per_frame_s": [round(c, 2) for c in cpu],
            "flight_swaps": swaps}


def _texture(r: dict) -> str:
    return r["texture"] + (" img" if r.get("source") == "image" else "")


def format_row(r: dict) -> str:
    return (f"{r['terrain_m']:>9.0f} {r['images']:>6} {_texture(r):<10} {r['frames']:>6} "
            f"{r['prepare_s']:>9.1f} {r['cycles_s']:>8.2f} {r['cycles_cpu_s']:>8.2f} "
            f"{r['setup_s']:>7.2f} {r['peak_rss_mb']:>8.0f} {r['model_cpu_s']:>8.2f} "
            f"{r['model_ratio']:>7.2f}")


def live_header() -> str:
    return header()


def header() -> str:
    head = (f"{'terrain m':>9} {'images':>6} {'texture':<10} {'frames':>6} "
            f"{'prepare s':>9} {'Cycles s':>8} {'CPU s':>8} {'setup s':>7} {'peak MB':>8} "
            f"{'model s':>8} {'model/':>7}")
    return head + "\n" + "-" * len(head)


def format_table(rows: list[dict]) -> str:
    lines = [header()] + [format_row(r) for r in rows]
    base = next((r for r in rows if r["terrain_m"] == SIZES[0][0] and r["texture"] == "baked"),
                None)
    if base is not None:
        for r in rows:
            if r is not base:
                lines.append(f"{r['terrain_m']:.0f} m, {_texture(r)}: Cycles "
                             f"{r['cycles_s'] / base['cycles_s']:.2f}x the example's wall "
                             f"seconds, {r['cycles_cpu_s'] / base['cycles_cpu_s']:.2f}x its "
                             "CPU seconds")
    for r in rows:
        if r.get("flight_swaps") == r.get("flight_swaps"):  # not NaN: a tiled row
            lines.append(f"{r['terrain_m']:.0f} m, {_texture(r)}: {r['flight_swaps']} of the "
                         f"flight's {r['images']} frames change tile slots, rendered in order "
                         "by one worker")
    lines.append("Cycles s, CPU s, setup s: per image, each worker's first frame left out; "
                 "setup: the frame's set-up (the tiles' bake and load); peak MB: the worker's; "
                 "model s: the render-time model's Cycles CPU seconds for the same images "
                 "(this machine's records; wall = CPU / cores on an idle machine); model/: "
                 "model s / CPU s; img: the texture from an image file")
    return "\n".join(lines)
