"""Dense matching speed and accuracy against image size (``designer bench dense``).

The example survey (``designer new --template survey``: 60 images, 1368 × 912 px at
draft quality, GSD 5.5 cm) is rendered and triangulated with its known poses
(``designer reconstruct --mode known-poses``) once, in a folder kept between runs
(``bench-dense/`` in the current folder; delete it to start again). Then the dense cloud
is computed with the longer image side limited to each size in SIZES_PX (None = the
full rendered size), cropped to the modelled terrain, and compared with the true mesh.

Per row: fused points, wall-clock and CPU seconds (this process, all its threads: the
machine's other load disturbs it less) per stage, points per wall second, and the
median / 90 % quantile of |signed distance| to the true mesh in metres and GSD. The
machine's load average is printed with the table: on a shared machine wall-clock times
are upper bounds.
"""

from __future__ import annotations

import json
import os
import shutil
import time
from pathlib import Path

import numpy as np

OUT_DIR = Path("bench-dense")
SIZES_PX = (684, 912, None)
GSD_M = 0.0548  # 50 m above the terrain, 13.2 mm / 1368 px sensor, 8.8 mm lens


def _survey(folder: Path) -> tuple[Path, Path, Path, np.ndarray]:
    """(images, local sparse model, project, origin): rendered and triangulated once."""
    from designer.project.new import write_template
    from designer.render.pipeline import render_project
    from designer.sfm.dense import write_local_model
    from designer.sfm.reconstruct import reconstruct

    project = folder / "example.xml"
    images = folder / "survey"
    recon = folder / "known-poses"
    if not (recon / "model").is_dir():
        folder.mkdir(parents=True, exist_ok=True)
        if not project.is_file():
            write_template(project, "survey", force=True)
        render_project(project, images, quality="draft", resume=True)
        reconstruct(images, recon, mode="known-poses", log=lambda m: None)
    local = folder / "sparse-local"
    shutil.rmtree(local, ignore_errors=True)
    origin = write_local_model(recon / "model", local)
    return images, local, project, origin


def run(repeats: int = 1, scale: float = 1.0, out_dir: Path | None = None) -> list[dict]:
    from designer.core.layout import images_dir
    from designer.evaluate.compare import reference_mesh
    from designer.evaluate.distance import signed_distances
    from designer.sfm.dense import dense_cloud

    folder = Path(out_dir or OUT_DIR)
    images, model, project, origin = _survey(folder)
    mesh = reference_mesh(project)
    lo, hi = mesh.vertices.min(axis=0) - [0, 0, 100], mesh.vertices.max(axis=0) + [0, 0, 100]
    rows = []
    for size in SIZES_PX:
        best = None
        for _ in range(max(1, repeats)):
            work = folder / f"dense-{size or 'full'}"
            shutil.rmtree(work, ignore_errors=True)
            wall, cpu = time.perf_counter(), time.process_time()
            cloud = dense_cloud(images_dir(images), model, work, origin_world=origin,
                                max_image_size_px=size, bounds_world=(lo, hi),
                                log=lambda m: None)
            wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
            if best is None or wall < best[0]:
                best = (wall, cpu, cloud)
        wall, cpu, cloud = best
        d = np.abs(signed_distances(cloud.points_world, (mesh.vertices, mesh.faces)))
        rows.append({"size_px": size or 1368, "points": len(cloud), "wall_s": wall,
                     "cpu_s": cpu, "stages": cloud.stage_seconds,
                     "median_abs_m": float(np.median(d)),
                     "q90_abs_m": float(np.quantile(d, 0.9))})
    (folder / "bench-dense.json").write_text(json.dumps(rows, indent=1))
    return rows


def format_table(rows: list[dict]) -> str:
    head = (f"{'longer side':>11} {'points':>9} {'wall s':>7} {'CPU s':>6} {'pts/s':>7} "
            f"{'undist':>6} {'pairs':>5} {'depth':>6} {'fusion':>6} "
            f"{'med |d|':>8} {'GSD':>5} {'q90 |d|':>8}")
    lines = [f"dense cloud of the example survey (60 images), GSD {GSD_M} m; "
             f"load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores", head]
    for r in rows:
        s = r["stages"]
        lines.append(
            f"{r['size_px']:>9}px {r['points']:>9} {r['wall_s']:>7.1f} {r['cpu_s']:>6.1f} "
            f"{r['points'] / r['wall_s']:>7.0f} {s['undistort_s']:>6.1f} {s['pairs_s']:>5.1f} "
            f"{s['depth_maps_s']:>6.1f} {s['fusion_s']:>6.1f} {r['median_abs_m']:>8.4f} "
            f"{r['median_abs_m'] / GSD_M:>5.2f} {r['q90_abs_m']:>8.4f}")
    lines.append("stage columns are wall-clock seconds; |d|: distance to the true mesh (m)")
    return "\n".join(lines)
