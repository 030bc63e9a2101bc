"""What the GCP-count example study costs (``designer bench study``).

Runs ``resources/studies/gcp-count.xml`` (written from the template into a temporary
folder) with 2 local workers, cold (empty output folder) and then resumed (everything
cached), and prints wall seconds with the number of runs, renders, reconstructions and
cache hits. ``--scale`` below 1 keeps fewer replicates (at least 1) for a quick check.

``image_size="example"`` (``designer bench study --image-size example``) flies the
study's base survey with the example survey's camera (resources/examples/survey: a
1-inch 20 MP camera, 8.8 mm, rendered at 1368 × 912 px) instead of the small 640 × 480
camera; the scene, the flight plan and the GCPs stay the study's.
"""

from __future__ import annotations

import dataclasses
import os
import tempfile
import time
from pathlib import Path

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


def run(repeats: int = 1, scale: float = 1.0, image_size: str = "small") -> list[dict]:
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
    head = (f"{'study gcp-count, 2 workers':28s} {'size':>7s} {'images':>6s} {'wall s':>8s} "
            f"{'runs':>5s} {'variants':>8s} "
            f"{'renders':>8s} {'reconstr.':>9s} {'image sets':>10s} {'cache hits':>10s} "
            f"{'failed':>6s} {'load':>5s}")
    lines = [head, "-" * len(head)]
    for r in rows:
        lines.append(f"{r['run']:28s} {r['size']:>7s} {r['images'] or 0:6d} {r['wall_s']:8.1f} "
                     f"{r['runs']:5d} {r['variants']:8d} "
                     f"{r['renders']:8d} {r['reconstructions']:9d} {r['image_sets']:10d} "
                     f"{r['cache_hits']:10d} {r['failed']:6d} {r['load']:5.1f}")
    return "\n".join(lines)
