"""The example survey, end to end: every stage that exists, in order, with timings.

Stages: write the example project → check it → plan it (maps) → render every image
with its ground truth → report (Markdown with figures and the timing of each stage).
"""

from __future__ import annotations

import json
import time
from collections.abc import Callable
from pathlib import Path

from designer.atomic import write_text_atomic


def run_demo(
    output: Path,
    log: Callable[[str], None] = print,
    quality: str | None = None,
    frames: str | None = None,
) -> Path:
    """Run the demo into ``output``; returns the path of the report."""
    from designer.project import load_project, template, write_project
    from designer.render.pipeline import render_project
    from designer.survey.maps import write_coverage_map, write_gsd_map
    from designer.survey.plan_report import format_plan, plan_project, plan_summary

    output = Path(output)
    output.mkdir(parents=True, exist_ok=True)
    timings: dict[str, float] = {}

    def stage(name: str):
        log(f"== {name}")
        return _Timer(timings, name)

    with stage("write the example project"):
        tpl = template("survey")
        project_path = output / "survey.xml"
        write_project(tpl.project, project_path)
    with stage("check"):
        project = load_project(project_path)
        log(f"{project_path}: valid")
    with stage("plan"):
        plan = plan_project(project, output)
        log(format_plan(plan, str(project_path)))
        import numpy as np

        area = np.array(project.trajectory.flight_plan.area)
        xy = np.array([s.C_world[:2] for s in plan.stations])
        write_coverage_map(output / "plan-coverage.png", plan.analysis.coverage, area=area,
                           stations_xy=xy)
        write_gsd_map(output / "plan-gsd.png", plan.analysis.coverage, area=area,
                      stations_xy=xy)
    with stage("render"):
        summary = render_project(project_path, output / "images", quality=quality,
                                 frames=frames, resume=True,
                                 progress=_frame_logger(log, len(plan.stations)))
        log(f"{len(summary.report.rendered)} images rendered, "
            f"{len(summary.report.skipped)} already complete")
    report = output / "report.md"
    write_text_atomic(report, _report_text(project, plan_summary(plan), summary, timings))
    write_text_atomic(output / "timings.json", json.dumps(timings, indent=1))
    for name, seconds in timings.items():
        log(f"{name:<28} {seconds:8.1f} s")
    return report


class _Timer:
    def __init__(self, timings: dict[str, float], name: str) -> None:
        self.timings, self.name = timings, name

    def __enter__(self):
        self.t0 = time.perf_counter()
        return self

    def __exit__(self, *exc) -> None:
        self.timings[self.name] = time.perf_counter() - self.t0


def _frame_logger(log, total: int):
    done = [0]

    def progress(event: dict) -> None:
        if event["event"] in ("frame_done", "frame_skipped"):
            done[0] += 1
            if done[0] % 10 == 0 or done[0] == total:
                log(f"  {done[0]}/{total} images")

    return progress


def _report_text(project, plan: dict, summary, timings: dict[str, float]) -> str:
    first = summary.prepared.poses[0].image_name
    lines = [
        f"# {project.name}",
        "",
        project.description or "",
        "",
        "## Plan",
        "",
        f"* images: {plan['n_images']}",
        f"* GSD over the terrain (min / mean / max): "
        f"{100 * plan['gsd_terrain_m']['min']:.2f} / {100 * plan['gsd_terrain_m']['mean']:.2f}"
        f" / {100 * plan['gsd_terrain_m']['max']:.2f} cm",
        f"* front / side overlap (median): {100 * plan['front_overlap_median']:.1f} % / "
        f"{100 * plan['side_overlap_median']:.1f} %",
        "",
        "![coverage](plan-coverage.png) ![GSD](plan-gsd.png)",
        "",
        "## A rendered image",
        "",
        f"![{first}](images/{first})",
        "",
        "## GCPs (images that see each target unoccluded)",
        "",
        "| GCP | role | images |",
        "|---|---|---|",
    ]
    lines += [f"| {g['id']} | {g['role']} | {g['images']} |" for g in plan.get("gcps", [])]
    lines += ["", "## Timings", "", "| stage | seconds |", "|---|---|"]
    lines += [f"| {name} | {seconds:.1f} |" for name, seconds in timings.items()]
    lines += ["", "Ground truth: `images/ground-truth/`; manifest: `images/manifest.json`.", ""]
    return "\n".join(lines)
