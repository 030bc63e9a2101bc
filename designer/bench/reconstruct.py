"""Seconds per stage of ``designer reconstruct --mode free --dense cpu`` (``designer bench
reconstruct``).

The example survey (``designer new --template survey``: 60 images, 1368 × 912 px at
draft quality, GSD 5.5 cm) is rendered once into ``bench-reconstruct/survey/`` in the
current folder (kept between runs; delete it to start again), or taken from ``--survey
DIR`` (a folder ``designer render`` wrote; its manifest names the project, which gives
the true surface for the DEM of difference). Then it is processed once, free (incremental
SfM and the bundle adjustment with the project's ``<processing>``), with the dense stage
on and the longer image side for dense matching limited to DENSE_IMAGE_PX × scale.

The table has one row per stage — features, matching, mapping, adjustment, dense
(undistortion, pair choice and depth maps), fusion, rasters — with its wall-clock
seconds (and the dense matcher's CPU seconds, this process, all threads), then the
totals, the dense points and dense points per wall second of dense + fusion. The
machine's load average is printed with it: on a shared machine wall-clock times are
upper bounds.
"""

from __future__ import annotations

import dataclasses
import json
import os
import time
from pathlib import Path

OUT_DIR = Path("bench-reconstruct")
#: longer image side for dense matching at scale 1 (half the example's 1368 px)
DENSE_IMAGE_PX = 684
#: the rows of the table, in processing order
STAGES = ("features", "matching", "mapping", "adjustment", "dense", "fusion", "rasters")


def _example_survey(folder: Path) -> Path:
    """The example survey rendered at draft quality into ``folder/survey`` (resumed)."""
    from designer.project.new import write_template
    from designer.render.pipeline import render_project

    project = folder / "example.xml"
    images = folder / "survey"
    if not (images / "manifest.json").is_file() or not project.is_file():
        folder.mkdir(parents=True, exist_ok=True)
        if not project.is_file():
            write_template(project, "survey", force=True)
        render_project(project, images, quality="draft", resume=True)
    return images


def run(repeats: int = 1, scale: float = 1.0, survey: Path | None = None,
        out_dir: Path | None = None) -> list[dict]:
    """Process the survey once; one row per stage (``repeats`` is ignored: one run)."""
    from designer.sfm.reconstruct import reconstruct
    from designer.sfm.settings import resolve_processing

    folder = Path(out_dir or OUT_DIR)
    images = Path(survey) if survey is not None else _example_survey(folder)
    processing = resolve_processing(images, None)
    processing = dataclasses.replace(processing, dense="cpu")
    dense_px = max(64, round(DENSE_IMAGE_PX * scale))
    out = folder / "reconstruction"
    load_before = os.getloadavg()[0]
    wall, cpu = time.perf_counter(), time.process_time()
    result = reconstruct(images, out, mode="free", processing=processing,
                         dense_max_image_px=dense_px, log=lambda _message: None)
    wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
    s = result.summary
    t = s["stage_seconds"]
    dense = s["dense"]
    ds = dense["stage_seconds"]
    fusion_s = ds["fusion_s"]
    seconds = {"features": t["features_s"], "matching": t["matching_s"],
               "mapping": t["reconstruction_s"], "adjustment": t["adjustment_s"],
               "dense": t["dense_s"] - fusion_s, "fusion": fusion_s,
               "rasters": t["rasters_s"]}
    dense_cpu = {"dense": sum(ds[f"{k}_cpu_s"] for k in ("undistort", "pairs", "depth_maps")),
                 "fusion": ds["fusion_cpu_s"]}
    rows = [{"stage": name, "wall_s": seconds[name], "cpu_s": dense_cpu.get(name)}
            for name in STAGES]
    rows.append({"stage": "total", "wall_s": wall, "cpu_s": cpu,
                 "images": s["images"], "registered": s["registered"],
                 "tie_points": s["points"], "dense_points": dense["points"],
                 "dense_points_per_s": dense["points"] / max(t["dense_s"], 1e-9),
                 "dense_image_px": dense_px, "dome_amplitude_m": dense["dome_amplitude_m"],
                 "check_rmse_z_m": (s.get("check") or {}).get("rmse_z_m"),
                 "load_before": load_before, "load_after": os.getloadavg()[0],
                 "survey": str(images)})
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "bench-reconstruct.json").write_text(json.dumps(rows, indent=1))
    return rows


def format_table(rows: list[dict]) -> str:
    total = rows[-1]
    lines = [f"designer reconstruct --mode free --dense cpu of {total['survey']}: "
             f"{total['registered']}/{total['images']} images registered, "
             f"{total['tie_points']} tie points, dense matching at "
             f"{total['dense_image_px']} px; load average {total['load_before']:.1f} before, "
             f"{total['load_after']:.1f} after, on {os.cpu_count()} cores",
             f"{'stage':<11} {'wall s':>8} {'CPU s':>8}"]
    for r in rows:
        cpu = f"{r['cpu_s']:>8.1f}" if r["cpu_s"] is not None else f"{'':>8}"
        lines.append(f"{r['stage']:<11} {r['wall_s']:>8.1f} {cpu}")
    lines.append(f"dense points {total['dense_points']}, "
                 f"{total['dense_points_per_s']:.0f} per wall second of dense + fusion")
    lines.append("stage rows: wall-clock seconds; CPU seconds of this process (all threads) "
                 "where measured; total CPU covers every stage")
    return "\n".join(lines)
