"""Render throughput on the example survey (``designer bench render``).

Three figures for the same frames and settings:
* designer: one long-lived worker process per two cores, the scene built once;
* bare Cycles: the time spent inside Blender's render call for those frames (what the
  renderer alone costs); designer's overhead ratio is wall time / this;
* naive: a fresh Blender process per image (import bpy, build the scene, render).

The example's ground has a non-repeating texture variation (docs/world.md); a row with
the plain tiled texture (``texture tiled``) gives its render-time cost. A last row
renders the survey preset with a sun over time (a time line at 8 m/s, the sun
computed for each photo): its job bakes one light map per photo (``prepare s/img``) and
the worker swaps the terrain's light map and the targets' colours before each frame.

The "+movers" row renders the survey preset with a time line, the static sun and 20
moving objects (10 cars, 10 people) crossing the site: the worker poses them before each
frame; its ``prepare s/img`` includes writing their ground truth (a mask per image and
the positions table).
The "+houses" row renders the survey preset with the static sun and 11 buildings (10 m ×
8 m; gable, hip and flat roofs, 6 m walls) on a 4 × 4 grid over the flown area, the spots
near a GCP left empty: its ``prepare s/img`` includes building them and writing their
ground truth (a mask per image and buildings.ply); its ``wall s/img`` over the plain
survey row's is their render cost.
The "+plants" row renders the survey preset with a time line, the static sun and
vegetation over the whole site — grass tufts (1 per m²), shrubs (0.05 per m²) and trees
(0.004 per m²), about 10,500 plants swaying in a 5° wind: the worker instances one mesh
per kind and turns every plant before each frame; its ``prepare s/img`` includes placing
the plants and writing their ground truth (a mask per image and the plant table). The
table ends with its cost relative to the plain survey row.
The row "clouds" has the same time line, the static sun and drifting cloud shadows: one
light map per photo, the direct sun dimmed by the clouds at the photo's time.
The row "rig x5" flies the example's grid with a nadir + four 45° oblique rig of its
camera (docs/world.md): five images per station, each through its camera's lens warp and
effects; ``s/station`` is what one station of the flight costs (wall s/img × images per
station, 1 for the other rows).
The rows "pinhole" and "rolling" fly the same time line with the camera's lens distortion
removed (a rolling shutter is rendered for a pinhole camera only): "pinhole" with a global
shutter, "rolling" with a rolling shutter read out over 30 ms (Cycles' rolling shutter, the
camera keyed along the leg); their ratio is the rolling shutter's cost.
"""

from __future__ import annotations

import tempfile
import time
from collections.abc import Callable
from dataclasses import replace
from pathlib import Path

import numpy as np

from designer.project import load_project, template, write_project
from designer.project import model as m
from designer.render.job import prepare_job
from designer.render.runner import render_frames
from designer.render_time.stages import STAGE_COLUMNS, mean_stages


def _example(folder: Path) -> Path:
    tpl = template("survey")
    path = folder / "survey.xml"
    write_project(tpl.project, path)
    return path


def _with_movers(project: m.Project) -> m.Project:
    """``project`` with a time line (static sun) and 10 cars and 10 people driving and
    walking across its extent."""
    e = project.scene.terrain.extent
    cx, cy = (e.min_X + e.max_X) / 2, (e.min_Y + e.max_Y) / 2
    w, h = e.max_X - e.min_X, e.max_Y - e.min_Y
    movers = []
    for k in range(20):
        y = cy + (k / 19 - 0.5) * 0.8 * h
        a, b = (cx - 0.4 * w, y), (cx + 0.4 * w, y + 0.1 * h)
        path = tuple(m.PathPoint(*p) for p in ((a, b) if k % 2 else (b, a)))
        movers.append(m.MovingObject(f"m{k}", path, 8.0 if k < 10 else 1.4,
                                     shape="car" if k < 10 else "person", loop=True))
    return replace(project, scene=replace(project.scene, moving_objects=tuple(movers)),
                   trajectory=replace(project.trajectory, time_line=m.TimeLine(
                       "2026-06-21T06:30:00Z", 8.0, 10.0)))


#: the oblique rig of the "rig x5" row: (suffix, ω, φ, κ) deg
RIG_MOUNTS = (("_N", 0.0, 0.0, 0.0), ("_F", 45.0, 0.0, 0.0), ("_B", -45.0, 0.0, 180.0),
              ("_L", 0.0, 45.0, 0.0), ("_R", 0.0, -45.0, 0.0))


def _with_rig(project: m.Project) -> m.Project:
    """``project``'s flight flown by a nadir + four 45° oblique rig of its first camera."""
    camera = project.cameras[0].id
    rig = m.Rig("penta", tuple(m.Mount(camera, s, o, p, k) for s, o, p, k in RIG_MOUNTS))
    plan = replace(project.trajectory.flight_plan, camera=rig.name)
    return replace(project, trajectory=replace(project.trajectory, rigs=(rig,),
                                               flight_plan=plan))


#: the bench's rolling-shutter readout (s), a typical consumer drone camera's
ROLLING_READOUT_S = 0.03


def _pinhole(project: m.Project, readout_s: float = 0.0) -> m.Project:
    """``project`` on a time line with its camera's distortion removed and, when
    ``readout_s``, a rolling shutter."""
    rolling = m.RollingShutter(readout_s) if readout_s else None
    cameras = tuple(replace(c, distortion=None, rolling_shutter=rolling)
                    for c in project.cameras)
    return replace(project, cameras=cameras, trajectory=replace(
        project.trajectory, time_line=m.TimeLine("2026-06-21T06:30:00Z", 8.0, 10.0)))


def _with_houses(project: m.Project) -> m.Project:
    """``project`` with buildings on a 4 × 4 grid over the central 70 % of its extent,
    roofs gable, hip and flat in turn, none within 2 m of a GCP."""
    from designer.project.geometry import point_in_polygon

    e = project.scene.terrain.extent
    cx, cy = (e.min_X + e.max_X) / 2, (e.min_Y + e.max_Y) / 2
    w, h = e.max_X - e.min_X, e.max_Y - e.min_Y
    houses = []
    for i in range(4):
        for j in range(4):
            x, y = cx + (i / 3 - 0.5) * 0.7 * w, cy + (j / 3 - 0.5) * 0.7 * h + 6.0
            corners = ((x - 5, y - 4), (x + 5, y - 4), (x + 5, y + 4), (x - 5, y + 4))
            margin = ((x - 7, y - 6), (x + 7, y - 6), (x + 7, y + 6), (x - 7, y + 6))
            if any(point_in_polygon(t.true.X, t.true.Y, margin) for t in project.targets):
                continue
            roof = ("gable", "hip", "flat")[len(houses) % 3]
            houses.append(m.Building(f"h{i}{j}", tuple(m.PathPoint(*c) for c in corners),
                                     roof, 6.0, None if roof == "flat" else 9.0))
    return replace(project, scene=replace(project.scene, buildings=tuple(houses)))


def _with_plants(project: m.Project) -> m.Project:
    """``project`` with a time line (static sun) and grass, shrubs and trees over its
    whole extent, swaying in a 5° wind."""
    veg = m.Vegetation((m.PlantGroup(1.0, "grass-tuft", height_sd_m=0.05),
                        m.PlantGroup(0.05, "shrub", height_sd_m=0.2),
                        m.PlantGroup(0.004, "tree", height_sd_m=1.5)), seed=1,
                       wind=m.Wind(5.0, 4.0, 90.0))
    return replace(project, scene=replace(project.scene, vegetation=veg),
                   trajectory=replace(project.trajectory, time_line=m.TimeLine(
                       "2026-06-21T06:30:00Z", 8.0, 10.0)))


def run(repeats: int = 1, scale: float = 1.0, variants: bool = False,
        on_row: Callable[[dict], None] | None = None) -> list[dict]:
    """The example survey as ``designer demo`` renders it, stage by stage, beside the same
    frames without the texture bake and in bare Cycles; with ``variants`` also the rows
    of the world's elements (module docstring). ``on_row`` gets each row as it is
    measured."""
    rows = demo_rows(repeats, scale, on_row)
    if variants:
        for row in variant_rows(scale):
            rows.append(row)
            if on_row is not None:
                on_row(row)
    return rows


#: frames of the demo rows at --scale 1, spread evenly over the flight
DEMO_FRAMES = 12


def demo_frames(n_images: int, scale: float) -> list[int]:
    """``DEMO_FRAMES`` × scale frames spread evenly over a flight of ``n_images``: edge
    and centre frames (an image partly off the terrain renders faster) in their share;
    at least one (the first)."""
    n = max(1, min(n_images, round(DEMO_FRAMES * scale)))
    if n == 1:
        return [0]
    return sorted({round(float(k)) for k in np.linspace(0, n_images - 1, n)})


def demo_rows(repeats: int = 1, scale: float = 1.0,
              on_row: Callable[[dict], None] | None = None) -> list[dict]:
    """Four rows over the same frames of the example survey: ``demo`` (as ``designer
    demo`` renders it, the project's workers: the texture bake, the camera effects, the
    files), ``node graph`` (the same without the bake: Cycles evaluates the texture
    variation's five lookups and the light map per sample), ``bare Cycles`` (the demo's
    scene rendered in Cycles only: no file, no effects) and ``2 workers`` (the demo with
    two worker processes of one thread each). The best of ``repeats`` runs each."""
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        project_path = _example(tmp)
        project = load_project(project_path)
        for name, bake, bare, workers in (
                ("demo", True, False, project.render.workers),
                ("node graph", False, False, project.render.workers),
                ("bare Cycles", True, True, project.render.workers),
                ("2 workers", True, False, 2)):
            out = tmp / name.replace(" ", "-")
            t0 = time.perf_counter()
            prepared = prepare_job(project, project_path.parent, out, bake_texture=bake)
            prepare_s = time.perf_counter() - t0
            frames = demo_frames(len(prepared.job.frames), scale)
            n = len(frames)
            W, H = prepared.interior.image_size_px
            best = None
            runs = max(1, repeats)
            for k in range(runs):
                report = render_frames(prepared.job_path, frames, workers=workers, bare=bare)
                row = {"row": name, "image": f"{W}x{H}", "frames": n,
                       "samples": prepared.job.render.samples,
                       "workers": len(report.peak_rss_mb),
                       "prepare_s": prepare_s,
                       "wall_per_image_s": report.wall_seconds / n,
                       "scene_build_s": max(report.scene_seconds or [0.0]),
                       "stages_per_image_s": mean_stages(report.stages.values()),
                       "peak_rss_mb_per_worker": max(report.peak_rss_mb or [0.0])}
                if on_row is not None:  # every run as it ends: a cut-short run keeps it
                    on_row({**row, "run": f"{k + 1}/{runs}"})
                if best is None or row["wall_per_image_s"] < best["wall_per_image_s"]:
                    best = row
            rows.append(best)
    return rows


def variant_rows(scale: float = 1.0) -> list[dict]:
    """The rows of the world's elements (module docstring), as before the stage table."""
    n_frames = max(2, round(20 * scale))
    n_naive = max(1, round(5 * scale))
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        project_path = _example(tmp)
        project = load_project(project_path)
        timed = replace(project, scene=replace(project.scene, lighting=replace(
            project.scene.lighting, sun=m.SunOverTime(47.37, 8.54))),
            trajectory=replace(project.trajectory, time_line=m.TimeLine(
                "2026-06-21T06:30:00Z", 8.0, 10.0)))
        cloudy = replace(project, scene=replace(project.scene, lighting=replace(
            project.scene.lighting, clouds=m.CloudShadows(0.3, 40.0, 5.0, 0.6, 5.0, 90.0, 0))),
            trajectory=timed.trajectory)
        tiled = replace(project, scene=replace(project.scene, texture=replace(
            project.scene.texture, variation=None)))
        texture = "varied" if project.scene.texture.variation is not None else "tiled"
        for quality, sun, kind, proj in (("draft", "static", texture, project),
                                         ("survey", "static", texture, project),
                                         ("survey", "static", "tiled", tiled),
                                         ("survey", "over time", texture, timed),
                                         ("survey", "+movers", texture, _with_movers(project)),
                                         ("survey", "+houses", texture, _with_houses(project)),
                                         ("survey", "+plants", texture, _with_plants(project)),
                                         ("survey", "clouds", texture, cloudy),
                                         ("survey", "pinhole", texture, _pinhole(project)),
                                         ("survey", "rolling", texture,
                                          _pinhole(project, ROLLING_READOUT_S)),
                                         ("survey", "rig x5", texture, _with_rig(project))):
            out = tmp / f"out-{quality}-{sun.replace(' ', '-').replace('+', '')}-{kind}"
            naive = sun == "static" and proj is project
            t_prepare = time.perf_counter()
            prepared = prepare_job(proj, project_path.parent, out, quality)
            if proj.scene.moving_objects:
                from designer.render.job import JOB_DIR
                from designer.render.moving_truth import write_moving_truth

                write_moving_truth(out / JOB_DIR / "truth", prepared.interior, prepared.poses,
                                   prepared.moving_poses, prepared.moving_meshes)
            if prepared.buildings:
                from designer.render.building_truth import write_building_truth
                from designer.render.job import JOB_DIR

                write_building_truth(out / JOB_DIR / "truth", prepared.interior,
                                     prepared.poses, prepared.buildings)
            if proj.scene.vegetation is not None:
                from designer.render.job import JOB_DIR
                from designer.render.vegetation_truth import write_vegetation_truth

                write_vegetation_truth(out / JOB_DIR / "truth", prepared.interior,
                                       prepared.poses, [t.time_s for t in prepared.times],
                                       list(prepared.plants), proj.scene.vegetation.wind)
            prepare = time.perf_counter() - t_prepare
            frames = list(range(n_frames))
            report = render_frames(prepared.job_path, frames)
            bare = sum(report.rendered.values()) / max(1, len(report.peak_rss_mb))
            t0 = time.perf_counter()
            for i in range(n_naive if naive else 0):
                render_frames(prepared.job_path, [i], workers=1)
            naive_per_image = (time.perf_counter() - t0) / n_naive if naive else float("nan")
            W, H = prepared.interior.image_size_px
            per_image = report.wall_seconds / n_frames
            rows.append({
                "quality": quality, "sun": sun, "texture": kind, "image": f"{W}x{H}",
                "plants": sum(len(g) for g in prepared.plants),
                "frames": n_frames,
                "prepare_per_image_s": prepare / len(prepared.job.frames),
                "workers": len(report.peak_rss_mb),
                "wall_per_image_s": per_image,
                "bare_cycles_per_image_s": bare / n_frames,
                "overhead_ratio": report.wall_seconds / bare if bare else float("nan"),
                "naive_per_image_s": naive_per_image,
                "speedup_vs_naive": naive_per_image / per_image,
                "peak_rss_mb_per_worker": max(report.peak_rss_mb or [0.0]),
                "images_per_station": len(proj.trajectory.rigs[0].mounts)
                if proj.trajectory.rigs else 1,
            })
    return rows


def format_table(rows: list[dict]) -> str:
    """The stage table of the demo rows (the best of the repeats), then (with
    ``--variants``) the variants' table."""
    demo = [r for r in rows if "stages_per_image_s" in r]
    others = [r for r in rows if "stages_per_image_s" not in r]
    parts = []
    if demo:
        parts.append(format_demo_table(demo))
    if others:
        parts.append(format_variant_table(others))
    return "\n\n".join(parts)


def demo_header() -> str:
    head = (f"{'row':<12} {'image':>9} {'spp':>4} {'frames':>6} {'workers':>7} "
            f"{'prepare s':>9} {'wall s/img':>10} "
            + " ".join(f"{c:>8}" for c in STAGE_COLUMNS.values()))
    return head + "\n" + "-" * len(head)


def format_demo_row(r: dict) -> str:
    stages = r["stages_per_image_s"]
    cells = " ".join(_or_dash(stages.get(k, float("nan")), 8, ".2f") for k in STAGE_COLUMNS)
    return (f"{r['row']:<12} {r['image']:>9} {r['samples']:>4} {r['frames']:>6} "
            f"{r['workers']:>7} {r['prepare_s']:>9.1f} {r['wall_per_image_s']:>10.2f} {cells}")


def format_demo_table(rows: list[dict]) -> str:
    lines = [demo_header()] + [format_demo_row(r) for r in rows]
    by = {r["row"]: r for r in rows}
    wall = {name: r["wall_per_image_s"] for name, r in by.items()}
    if "demo" in wall and "bare Cycles" in wall:
        lines.append(f"demo wall / bare Cycles wall: {wall['demo'] / wall['bare Cycles']:.2f}")
    if "demo" in wall and "node graph" in wall:
        lines.append(f"node graph / demo (the texture bake's speed-up): "
                     f"{wall['node graph'] / wall['demo']:.2f}")
    lines.append("wall s/img: the whole run of the workers (process start, scene build, every "
                 "frame) / images; the stage columns: mean seconds per image inside one worker "
                 "(the workers run side by side); prepare s: building the job (scene, bake, "
                 "warp) once")
    return "\n".join(lines)


def format_variant_table(rows: list[dict]) -> str:
    head = (f"{'quality':<8} {'sun':<9} {'texture':<7} {'prepare s/img':>13} {'image':>10} "
            f"{'frames':>6} "
            f"{'workers':>7} {'wall s/img':>10} "
            f"{'Cycles s/img':>12} {'overhead':>8} {'naive s/img':>11} {'speed-up':>8} "
            f"{'peak MB/worker':>14} {'s/station':>9}")
    lines = [head, "-" * len(head)]
    for r in rows:
        lines.append(
            f"{r['quality']:<8} {r['sun']:<9} {r.get('texture', '–'):<7} "
            f"{r['prepare_per_image_s']:>13.2f} "
            f"{r['image']:>10} {r['frames']:>6} {r['workers']:>7} "
            f"{r['wall_per_image_s']:>10.2f} {r['bare_cycles_per_image_s']:>12.2f} "
            f"{r['overhead_ratio']:>8.3f} {_or_dash(r['naive_per_image_s'], 11, '.2f')} "
            f"{_or_dash(r['speedup_vs_naive'], 7, '.1f')}x "
            f"{r['peak_rss_mb_per_worker']:>14.0f} "
            f"{r['wall_per_image_s'] * r.get('images_per_station', 1):>9.2f}")
    plain = next((r for r in rows if (r["quality"], r["sun"], r.get("texture")) ==
                  ("survey", "static", rows[0].get("texture"))), None)
    for r in rows:
        if r["sun"] == "+plants" and plain is not None:
            lines.append(
                f"+plants ({r.get('plants', 0):,} plants) vs the plain survey row: wall "
                f"{r['wall_per_image_s'] / plain['wall_per_image_s']:.2f}x, Cycles "
                f"{r['bare_cycles_per_image_s'] / plain['bare_cycles_per_image_s']:.2f}x, "
                f"peak memory {r['peak_rss_mb_per_worker'] - plain['peak_rss_mb_per_worker']:+.0f}"
                " MB per worker")
    lines.append("wall: designer's local runner incl. process start and scene build; Cycles: "
                 "time inside the render call per worker; naive: a new Blender process per "
                 "image; prepare: building the job (scene, light maps) per image of the flight")
    return "\n".join(lines)


def _or_dash(value: float, width: int, spec: str) -> str:
    """``value`` formatted, or a dash where it was not measured (NaN)."""
    return f"{'–':>{width}}" if value != value else f"{value:>{width}{spec}}"


def live_header() -> str:
    """The header of the rows ``designer bench`` prints as they are measured."""
    return "measured rows (the full table follows at the end):"


def format_row(row: dict) -> str:
    """One measured row on one line (demo rows in the stage table's format, each run of
    a row with its number)."""
    if "stages_per_image_s" in row:
        return format_demo_row(row) + (f"   run {row['run']}" if "run" in row else "")
    return (f"{row['quality']} {row['sun']} {row.get('texture', '')}: "
            f"wall {row['wall_per_image_s']:.2f} s/img, Cycles "
            f"{row['bare_cycles_per_image_s']:.2f} s/img")
