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
    import shutil

    if shutil.which("colmap") is not None:
        cli = colmap_cli_seconds(images, out, processing.matching.max_features)
        for name in ("features", "matching", "mapping"):
            rows[STAGES.index(name)]["colmap_cli_s"] = cli[name]
        rows[-1]["colmap_cli_registered"] = cli["registered"]
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "bench-reconstruct.json").write_text(json.dumps(rows, indent=1))
    return rows


def colmap_cli_seconds(survey: Path, recon: Path, max_features: int) -> dict:
    """Wall seconds of COLMAP's command line (whole processes) doing the steps designer
    did in ``recon``: SIFT on the CPU with the same camera model, start values and
    feature count; matching the same pairs (recon/pairs.txt); incremental mapping with
    designer's mapper options (4° initial triangulation angle, 50 initial inliers,
    distortion held in the mapper's adjustments)."""
    import shutil
    import sqlite3
    import subprocess

    import numpy as np

    from designer.core.layout import images_dir

    work = recon.parent / "colmap-cli"
    shutil.rmtree(work, ignore_errors=True)
    (work / "sparse").mkdir(parents=True)
    with sqlite3.connect(recon / "database.db") as db:
        model, blob = db.execute("SELECT model, params FROM cameras LIMIT 1").fetchone()
    names = {0: "SIMPLE_PINHOLE", 1: "PINHOLE", 2: "SIMPLE_RADIAL", 4: "OPENCV",
             5: "OPENCV_FISHEYE", 6: "FULL_OPENCV"}
    params = ",".join(repr(float(v)) for v in np.frombuffer(blob, np.float64))
    db = str(work / "db.db")
    image_path = str(images_dir(survey))
    steps = {
        "features": ["feature_extractor", "--database_path", db, "--image_path", image_path,
                     "--ImageReader.single_camera", "1", "--ImageReader.camera_model",
                     names[model], "--ImageReader.camera_params", params,
                     "--SiftExtraction.use_gpu", "0",
                     "--SiftExtraction.max_num_features", str(max_features)],
        "matching": ["matches_importer", "--database_path", db, "--match_list_path",
                     str(recon / "pairs.txt"), "--match_type", "pairs",
                     "--SiftMatching.use_gpu", "0"],
        "mapping": ["mapper", "--database_path", db, "--image_path", image_path,
                    "--output_path", str(work / "sparse"),
                    "--Mapper.init_min_tri_angle", "4", "--Mapper.init_min_num_inliers", "50",
                    "--Mapper.ba_refine_extra_params", "0"],
    }
    seconds: dict = {}
    for name, args in steps.items():
        t0 = time.perf_counter()
        subprocess.run(["colmap", *args], check=True, capture_output=True)
        seconds[name] = time.perf_counter() - t0
    registered = 0
    for model in sorted((work / "sparse").iterdir()):  # as text, read without pycolmap
        subprocess.run(["colmap", "model_converter", "--input_path", str(model),
                        "--output_path", str(model), "--output_type", "TXT"], check=True,
                       capture_output=True)
        lines = [x for x in (model / "images.txt").read_text().splitlines()
                 if not x.startswith("#")]
        registered = max(registered, len(lines) // 2)
    seconds["registered"] = registered
    return seconds


def format_table(rows: list[dict]) -> str:
    total = rows[-1]
    lines = [f"designer reconstruct --mode free --dense cpu of {total['survey']}: "
             f"{total['registered']}/{total['images']} images registered, "
             f"{total['tie_points']} tie points, dense matching at "
             f"{total['dense_image_px']} px; load average {total['load_before']:.1f} before, "
             f"{total['load_after']:.1f} after, on {os.cpu_count()} cores",
             f"{'stage':<11} {'wall s':>8} {'CPU s':>8} {'colmap CLI s':>12}"]
    for r in rows:
        cpu = f"{r['cpu_s']:>8.1f}" if r["cpu_s"] is not None else f"{'':>8}"
        cli = f"{r['colmap_cli_s']:>12.1f}" if r.get("colmap_cli_s") is not None else ""
        lines.append(f"{r['stage']:<11} {r['wall_s']:>8.1f} {cpu} {cli}")
    lines.append(f"dense points {total['dense_points']}, "
                 f"{total['dense_points_per_s']:.0f} per wall second of dense + fusion")
    lines.append("stage rows: wall-clock seconds; CPU seconds of this process (all threads) "
                 "where measured; total CPU covers every stage; colmap CLI: COLMAP's command "
                 "line (whole processes, same images, camera start values, features, pairs "
                 "and mapper options), run after designer"
                 + (f", {total['colmap_cli_registered']} images registered"
                    if "colmap_cli_registered" in total else ""))
    return "\n".join(lines)
