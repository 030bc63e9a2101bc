"""What the GCP-count example study costs (``designer bench study``).

Runs ``resources/studies/gcp-count.xml`` (written from the template into a temporary
folder) with 2 local workers, cold (empty output folder) and then resumed (everything
cached), and prints wall seconds with the number of runs, renders, reconstructions and
cache hits. ``--scale`` below 1 keeps fewer replicates (at least 1) for a quick check.

``image_size="example"`` (``designer bench study --image-size example``) flies the
study's base survey with the example survey's camera (resources/examples/survey: a
1-inch 20 MP camera, 8.8 mm, rendered at 1368 × 912 px) instead of the small 640 × 480
camera; the scene, the flight plan and the GCPs stay the study's.

``template="example-processing"`` (``designer bench study --template
example-processing``) runs the example-size study instead: the example survey (60
images at 1368 × 912 px), calibration fixed/radial × GCP mode similarity/bundle, five
marking-error replicates — 20 runs, one render. It runs once, cold, and prints one line
per run with the CPU seconds of each stage (process CPU time: render, features,
matching, SfM, the rest of the reconstruction, comparison; "-" where the run took the
stage's result from the study's cache) and, last, the whole command's wall seconds.
"""

from __future__ import annotations

import dataclasses
import os
import tempfile
import time
from pathlib import Path

from designer.bench.table import Column, text_table

WORKERS = 2


def example_camera_base(base_path: Path) -> None:
    """Rewrite the study's base project with the example survey's camera at the example's
    rendered image size (its resolution scale applied to the image size)."""
    from designer.project import load_project, write_project

    root = Path(__file__).resolve().parents[2]
    example = load_project(root / "resources" / "examples" / "survey" / "survey.xml")
    base = load_project(base_path)
    camera = example.cameras[0]
    scale = example.render.resolution_scale
    camera = dataclasses.replace(camera, id=base.cameras[0].id,
                                 image_width_px=round(camera.image_width_px * scale),
                                 image_height_px=round(camera.image_height_px * scale))
    write_project(dataclasses.replace(base, cameras=(camera,)), base_path)


#: the templates ``designer bench study --template`` runs
TEMPLATES = ("gcp-count", "example-processing")


def run(repeats: int = 1, scale: float = 1.0, image_size: str = "small",
        template: str = "gcp-count") -> list[dict]:
    if template == "example-processing":
        return run_stages(template, scale)
    from designer.study.design import plan_study
    from designer.study.run import run_study
    from designer.study.templates import write_template
    from designer.study.xml import read_study

    rows = []
    with tempfile.TemporaryDirectory(prefix="designer-bench-study-") as tmp:
        study_path, base_path = write_template("gcp-count", Path(tmp) / "gcp-count.xml")
        if image_size == "example":
            example_camera_base(base_path)
        study = read_study(study_path)
        count = max(1, round(study.replicates.count * scale))
        study = dataclasses.replace(study, replicates=dataclasses.replace(
            study.replicates, count=count))
        plan = plan_study(study)
        out = Path(tmp) / "out"
        for label, resume in (("cold", False), ("resumed (all cached)", True)):
            t0 = time.perf_counter()
            report = run_study(plan, out, workers=WORKERS, resume=resume)
            seconds = time.perf_counter() - t0
            c = report.counts
            first = report.rows[0]
            rows.append({"run": label, "wall_s": seconds, "runs": c["runs"],
                         "images": first.get("images"), "size": image_size,
                         "variants": c["variants"], "renders": c["renders_this_session"],
                         "reconstructions": c["reconstructions_this_session"],
                         "image_sets": c["renders"], "cache_hits": c["cache_hits"],
                         "failed": c["failed"], "cores": os.cpu_count(),
                         "load": os.getloadavg()[0]})
    return rows


def format_table(rows: list[dict]) -> str:
    if rows and "label" in rows[0]:
        return format_stage_table(rows)
    return text_table(
        [Column("study gcp-count, 2 workers", "28s", "run"), Column("size", ">7s", "size"),
         Column("images", "6d", lambda r: r["images"] or 0), Column("wall s", "8.1f", "wall_s"),
         *(Column(title, spec, key) for title, spec, key in (
             ("runs", "5d", "runs"), ("variants", "8d", "variants"),
             ("renders", "8d", "renders"), ("reconstr.", "9d", "reconstructions"),
             ("image sets", "10d", "image_sets"), ("cache hits", "10d", "cache_hits"),
             ("failed", "6d", "failed"), ("load", "5.1f", "load")))], rows)


#: the per-run stage columns of results.csv: (table heading, column)
STAGES = (("render", "render_cpu_s"), ("features", "features_cpu_s"),
          ("matching", "matching_cpu_s"), ("SfM", "sfm_cpu_s"),
          ("adjust+rest", None), ("compare", "compare_cpu_s"))


def run_stages(template: str, scale: float = 1.0) -> list[dict]:
    """One cold run of the study ``template`` with 2 local workers: a row per run with
    its stages' CPU seconds, then a row for the whole command (wall seconds)."""
    from designer.study.design import plan_study
    from designer.study.labels import variant_labels
    from designer.study.run import run_study
    from designer.study.templates import write_template
    from designer.study.xml import read_study

    rows = []
    with tempfile.TemporaryDirectory(prefix="designer-bench-study-") as tmp:
        study_path, _ = write_template(template, Path(tmp) / f"{template}.xml")
        study = read_study(study_path)
        count = max(1, round(study.replicates.count * scale))
        study = dataclasses.replace(study, replicates=dataclasses.replace(
            study.replicates, count=count))
        plan = plan_study(study)
        t0 = time.perf_counter()
        report = run_study(plan, Path(tmp) / "out", workers=WORKERS)
        wall = time.perf_counter() - t0
        factors = [f.name for f in plan.study.factors]
        labels = variant_labels(report.rows, factors, plan.study.design)
        for row in report.rows:
            label = labels.get(int(row["variant"]), "")
            out = {"run": row["run"], "label": f"{label} (r{row['replicate']})",
                   "status": row.get("status")}
            for name, column in STAGES:
                if column is not None:
                    out[name] = row.get(column)
            if str(row.get("render_reused")).lower() == "true":
                out["render"] = None  # the image set another run rendered
            spent = row.get("reconstruct_cpu_spent_s")
            steps = sum(out[k] or 0.0 for k in ("features", "matching", "SfM"))
            out["adjust+rest"] = None if spent is None else spent - steps
            out["check_rmse_z_m"] = row.get("check_rmse_z_m")
            rows.append(out)
        rows.append({"run": f"whole command ({len(report.rows)} runs, {WORKERS} workers)",
                     "wall_s": wall, "failed": report.counts["failed"],
                     "cores": os.cpu_count(), "load": os.getloadavg()[0]})
    return rows


def _cell(v) -> str:
    return f"{v:11.1f}" if isinstance(v, float) else f"{'-':>11s}"



def format_stage_table(rows: list[dict]) -> str:
    head = f"{'run':9s} {'variant':34s} " + " ".join(f"{n:>11s}" for n, _ in STAGES) \
        + f" {'check Z m':>10s} {'status':>6s}"
    lines = ["CPU seconds of each stage per run ('-': taken from the study's cache)",
             head, "-" * len(head)]
    totals = {n: 0.0 for n, _ in STAGES}
    for r in rows:
        if "wall_s" in r:
            continue
        for n, _ in STAGES:
            totals[n] += r.get(n) or 0.0
        z = r.get("check_rmse_z_m")
        lines.append(f"{r['run']:9s} {r['label'][:34]:34s} "
                     + " ".join(_cell(r.get(n)) for n, _ in STAGES)
                     + (f" {z:10.4f}" if isinstance(z, float) else f" {'-':>10s}")
                     + f" {r['status'] or '-':>6s}")
    lines.append("-" * len(head))
    lines.append(f"{'sum':9s} {'':34s} " + " ".join(_cell(totals[n]) for n, _ in STAGES))
    for r in rows:
        if "wall_s" in r:
            lines.append(f"{r['run']}: {r['wall_s']:.1f} s wall ({r['wall_s'] / 60:.1f} min), "
                         f"failed {r['failed']}, {r['cores']} cores, load {r['load']:.1f}")
    return "\n".join(lines)
