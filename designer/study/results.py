"""The study's tables: ``results.csv`` (one row per run, tidy), ``results.parquet`` (when
pyarrow is installed) and ``summary.json`` (every metric by factor level: mean and 95 %
interval over replicates, and the counts of variants, renders, reconstructions, cache
hits and failed runs).

Units: metres (``_m``), pixels (``_px``), ground sample distances (``_gsd``: the metre
value divided by the run's mean GSD), seconds (``_s``), minutes (``_min``).

Cost in a surveyor's units (:mod:`designer.study.cost`): ``flight_min``, ``images``,
``gcps`` (targets surveyed) and ``control_gcps``; CPU seconds of the render
(``render_cpu_s``), the reconstruction (``reconstruct_cpu_s``, on its own) and the
comparison (``compare_cpu_s``). Wall seconds: ``total_s`` is what the run costs on its
own (its render, reconstruction and comparison, even where the study shared them with
other runs); ``amortised_s`` is its share within the study (a render shared by
``render_runs`` runs counts 1/render_runs); ``cpu_s`` and ``cpu_amortised_s`` are the
same two for CPU seconds.
"""

from __future__ import annotations

import csv
import io
import json
from pathlib import Path

from designer.atomic import write_text_atomic
from designer.study.cost import (
    STEP_CPU_DIR,
    accuracy_metric,
    add_reused_cpu,
    recorded_step_cpu,
)
from designer.study.levels import factor_levels, interval95, level_rows

#: accuracy and cost columns of results.csv (a study's <metrics> name some of them)
METRIC_COLUMNS = (
    "registered", "images", "gsd_m",
    "check_rmse_x_m", "check_rmse_y_m", "check_rmse_z_m", "check_rmse_xy_m",
    "check_rmse_xyz_m", "check_rmse_x_gsd", "check_rmse_y_gsd", "check_rmse_z_gsd",
    "control_rmse_x_m", "control_rmse_y_m", "control_rmse_z_m", "control_rmse_xyz_m",
    "cloud_median_m", "cloud_nmad_m", "cloud_mean_m", "cloud_rmse_m",
    "dtm_cloud_median_m", "dtm_cloud_nmad_m", "dtm_cloud_mean_m", "dtm_cloud_rmse_m",
    "dome_amplitude_m", "dome_amplitude_gsd", "sparse_dome_gsd", "focal_error_px", "k1_error",
    "k1_error_beyond_focal", "render_s", "reconstruct_s",
    "compare_s", "total_s", "amortised_s",
    "flight_min", "gcps", "control_gcps", "render_cpu_s", "reconstruct_cpu_s",
    "compare_cpu_s", "cpu_s", "cpu_amortised_s",
)

_FIRST = ("run", "variant", "replicate")
_LAST = ("images", "gsd_m", "flight_min", "flight_min_source", "gcps", "control_gcps",
         "render_s", "reconstruct_s", "compare_s", "total_s", "amortised_s",
         "render_cpu_s", "render_cycles_cpu_s", "reconstruct_cpu_s",
         "reconstruct_cpu_spent_s", "features_cpu_s", "matching_cpu_s", "sfm_cpu_s",
         "compare_cpu_s",
         "cpu_s", "cpu_amortised_s", "render_runs", "processing_runs",
         "registered", "check_n", "check_rmse_x_m", "check_rmse_y_m", "check_rmse_z_m",
         "check_rmse_xy_m", "check_rmse_xyz_m", "check_rmse_x_gsd", "check_rmse_y_gsd",
         "check_rmse_z_gsd", "control_n", "control_rmse_x_m", "control_rmse_y_m",
         "control_rmse_z_m", "control_rmse_xyz_m", "cloud_median_m", "cloud_nmad_m",
         "cloud_mean_m", "cloud_rmse_m", "dtm_cloud_median_m", "dtm_cloud_nmad_m",
         "dtm_cloud_mean_m", "dtm_cloud_rmse_m", "dome_amplitude_m", "dome_amplitude_gsd",
         "sparse_dome_gsd", "focal_error_px", "k1_error", "k1_error_beyond_focal",
         "render_reused", "processing_reused", "features_reused", "matches_reused",
         "sfm_reused", "image_hash", "processing_hash", "features_group", "sfm_group",
         "error_map", "status")


def complete_row(row: dict) -> dict:
    """Add the derived columns: RMSE in GSD units, the wall and CPU seconds of the run on
    its own and its share (``reconstruct_cpu_s`` first: :func:`add_reused_cpu`)."""
    gsd = row.get("gsd_m")
    for axis in ("x", "y", "z"):
        v = row.get(f"check_rmse_{axis}_m")
        row[f"check_rmse_{axis}_gsd"] = v / gsd if v is not None and gsd else None
    row["total_s"] = sum(row.get(k) or 0.0 for k in ("render_s", "reconstruct_s", "compare_s"))
    # what the run cost within the study: shared renders and processing divided among
    # the runs that share them
    row["amortised_s"] = (row.get("render_s") or 0.0) / max(1, row.get("render_runs") or 1) \
        + sum(row.get(k) or 0.0 for k in ("reconstruct_s", "compare_s")) \
        / max(1, row.get("processing_runs") or 1)
    cpu = [row.get(k) for k in ("render_cpu_s", "reconstruct_cpu_s", "compare_cpu_s")]
    row["cpu_s"] = sum(v or 0.0 for v in cpu) if any(v is not None for v in cpu) else None
    row["cpu_amortised_s"] = None if row["cpu_s"] is None else \
        (row.get("render_cpu_s") or 0.0) / max(1, row.get("render_runs") or 1) \
        + sum(row.get(k) or 0.0 for k in ("reconstruct_cpu_spent_s", "compare_cpu_s")) \
        / max(1, row.get("processing_runs") or 1)
    return row


def columns(rows: list[dict]) -> list[str]:
    keys = {k for r in rows for k in r}
    middle = sorted(k for k in keys if k.startswith(("factor:", "seed:")))
    return list(_FIRST) + middle + [k for k in _LAST]


def rows_csv(rows: list[dict]) -> str:
    cols = columns(rows)
    buffer = io.StringIO()
    writer = csv.DictWriter(buffer, cols, extrasaction="ignore", lineterminator="\n")
    writer.writeheader()
    for r in rows:
        writer.writerow({k: _cell(r.get(k)) for k in cols})
    return buffer.getvalue()


def _cell(v):
    if v is None:
        return ""
    if isinstance(v, float):
        return f"{v:.6g}"
    return v


def summarise(plan, rows: list[dict], counts: dict) -> dict:
    ok = [r for r in rows if r["status"] == "ok"]
    by_factor = {}
    for f in plan.study.factors:
        levels = []
        for level in factor_levels(plan, rows, f.name):
            selected = level_rows(plan, rows, f.name, level)
            good = [r for r in selected if r["status"] == "ok"]
            levels.append({"level": level, "runs": len(selected), "failed":
                           len(selected) - len(good), "metrics": {
                               c: interval95([r.get(c) for r in good]) for c in METRIC_COLUMNS}})
        by_factor[f.name] = {"stage": _stage(f.name), "levels": levels}
    return {"study": plan.study.name, "design": plan.study.design,
            "replicates": plan.study.replicates.count,
            "vary": list(plan.study.replicates.vary), "metrics": list(plan.study.metrics),
            "variants": counts.get("variants"), "runs": len(rows),
            "renders": counts.get("renders"), "reconstructions": counts.get("reconstructions"),
            "cache_hits": counts.get("cache_hits"), "failed": counts.get("failed"),
            "renders_this_session": counts.get("renders_this_session"),
            "reconstructions_this_session": counts.get("reconstructions_this_session"),
            # of the renders: Cycles renders, and effect passes over their kept raw
            # images (image sets that differ only in their camera effects)
            "raw_renders": counts.get("raw_renders"),
            "effect_passes": counts.get("effect_passes"),
            "raw_renders_this_session": counts.get("raw_renders_this_session"),
            "effect_passes_this_session": counts.get("effect_passes_this_session"),
            "ok": len(ok), "factors": by_factor, "cost": cost_summary(plan, rows),
            "rows": rows}


def cost_summary(plan, rows: list[dict]) -> dict:
    """The study's cost axis, its accuracy metric and each variant's point on them:
    mean and replicate range of both, its label, whether it is on the front."""
    from designer.study.cost_figure import analyse

    a = analyse(plan, rows, accuracy_metric(plan.study.metrics))
    cost = a["cost"]
    return {"axis": cost.name, "column": cost.column, "label": cost.label,
            "metric": a["metric"], "front_drawn": a["drawn"], "rule": a["rule"],
            "variants": [{"variant": p.variant, "label": p.label, "runs": p.runs,
                          "cost": vars(p.cost), "error": vars(p.error),
                          "front": p in a["front"]} for p in a["points"]]}


def _stage(name: str) -> str:
    from designer.study.factors import FACTORS

    return FACTORS[name].stage


def write_results(plan, report) -> list[str]:
    """results.csv (+ .parquet), summary.json, report.html and report.md in the folder;
    what of the report could not be made, one line each (empty when all of it is
    written). The report never fails the results: they are written before it, and a
    report that cannot be written is one of those lines."""
    out = Path(report.out_dir)
    rows = [complete_row(r) for r in add_reused_cpu([dict(r) for r in report.rows],
                                                    recorded_step_cpu(out / STEP_CPU_DIR))]
    write_text_atomic(out / "results.csv", rows_csv(rows))
    _parquet(rows, out / "results.parquet")
    summary = summarise(plan, rows, report.counts)
    summary["wall_s"] = report.seconds
    write_text_atomic(out / "summary.json", json.dumps(summary, indent=1) + "\n")
    from designer.study.report import one_line, write_report

    try:
        problems = write_report(plan, rows, summary, out)["problems"]
    except Exception as error:  # a bug in the report: the finished runs stand
        for stale in ("report.md", "report.html"):  # an earlier session's, not these runs'
            (out / stale).unlink(missing_ok=True)
        return [f"report: report.md and report.html not written: {one_line(error)}; "
                "results.csv and summary.json are"]
    return [f"report: {p}; the rest of the report is written" for p in problems]


def _parquet(rows: list[dict], path: Path) -> None:
    try:
        import pyarrow as pa
        import pyarrow.parquet as pq
    except ImportError:
        return
    from designer.atomic import atomic_path

    cols = columns(rows)
    table = pa.table({c: [_cell(r.get(c)) if isinstance(r.get(c), str) else r.get(c)
                          for r in rows] for c in cols})
    with atomic_path(path) as tmp:
        pq.write_table(table, tmp)
