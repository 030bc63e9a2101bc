"""Seconds of the rolling-shutter adjustment, before and after vectorising it (``designer
bench rolling-adjustment``).

The same input for both: a synthetic rolling-shutter block the size of the example
survey's adjustment (designer.bench.synthetic_rolling.EXAMPLE_SIZE: 60 images of a 5-strip
grid, about 17,000 tie points and 114,000 observations, 20 ms readout at 8 m/s), with
camera-position priors (σ 2 cm / 3 cm) and the true interior orientation (``fixed``).
Each solver adjusts its own copy of the block: the per-observation Ceres problem
(designer.bench.rolling_reference, a Python cost per observation, as designer did before)
and the vectorised Schur Levenberg–Marquardt (designer.sfm.rolling_adjustment). Rows:
wall-clock and CPU seconds of this process (best of the repeats), steps, and the largest
differences between the two solutions (velocities, points, per-observation errors).
``scale`` shrinks the block (strips, photos per strip and points) for tests.
"""

from __future__ import annotations

import os
import time
from dataclasses import replace

import numpy as np


def _spec(scale: float):
    from designer.bench.synthetic_rolling import EXAMPLE_SIZE

    if scale >= 1.0:
        return EXAMPLE_SIZE
    return replace(EXAMPLE_SIZE, strips=max(2, round(EXAMPLE_SIZE.strips * scale ** 0.5)),
                   per_strip=max(4, round(EXAMPLE_SIZE.per_strip * scale ** 0.5)),
                   points=max(300, round(EXAMPLE_SIZE.points * scale)))


def run(repeats: int = 3, scale: float = 1.0) -> list[dict]:
    """One row per solver (module docstring), the reference first."""
    from designer.bench.rolling_reference import adjust_rolling_ceres
    from designer.bench.synthetic_rolling import block_counts, copy_of, rolling_block
    from designer.sfm.adjustment import MIN_GCP_SIGMA_M, MIN_MARKING_SIGMA_PX, PositionPriors
    from designer.sfm.rolling_adjustment import adjust_rolling

    spec = _spec(scale)
    rec, _, true_C, shutters = rolling_block(spec)
    priors = PositionPriors({n: C.copy() for n, C in true_C.items()}, 0.02, 0.03)
    size = "{} images, {} points, {} observations".format(*block_counts(rec))
    load = os.getloadavg()[0]
    rows, results = [], []
    for label, solver in (("per-observation Ceres (before)", adjust_rolling_ceres),
                          ("vectorised Schur LM (now)", adjust_rolling)):
        best_wall = best_cpu = float("inf")
        for _ in range(max(1, repeats)):
            copy = copy_of(rec)
            wall, cpu = time.perf_counter(), time.process_time()
            solution, _ = solver(copy, (), shutters, [], MIN_MARKING_SIGMA_PX, priors,
                                 MIN_GCP_SIGMA_M)
            best_wall = min(best_wall, time.perf_counter() - wall)
            best_cpu = min(best_cpu, time.process_time() - cpu)
        s = solution.summary
        results.append((copy, solution))
        rows.append({"solver": label, "block": size, "wall_s": best_wall, "cpu_s": best_cpu,
                     "steps": int(s.num_successful_steps + s.num_unsuccessful_steps),
                     "load": load})
    (ref, ref_sol), (new, new_sol) = results
    rows[1]["ratio"] = rows[0]["wall_s"] / rows[1]["wall_s"]
    rows[1]["d_velocity"] = max(float(np.abs(ref_sol.velocities[n] - new_sol.velocities[n])
                                      .max()) for n in ref_sol.velocities)
    rows[1]["d_point"] = max(float(np.abs(ref.points3D[p].xyz - new.points3D[p].xyz).max())
                             for p in ref.points3D)
    rows[1]["d_error"] = max(float(np.abs(np.sort(ref_sol.point_errors_px[p])
                                          - np.sort(new_sol.point_errors_px[p])).max())
                             for p in ref_sol.point_errors_px)
    return rows


def format_table(rows: list[dict]) -> str:
    lines = [f"block: {rows[0]['block']} (synthetic; fixed interior, position priors)",
             f"{'solver':<32} {'wall s':>8} {'CPU s':>8} {'steps':>6} {'before/now':>11}",
             "-" * 69]
    for r in rows:
        ratio = f"{r['ratio']:>11.1f}" if "ratio" in r else f"{'':>11}"
        lines.append(f"{r['solver']:<32} {r['wall_s']:>8.2f} {r['cpu_s']:>8.2f} "
                     f"{r['steps']:>6d} {ratio}")
    now = rows[-1]
    lines.append(f"largest differences now − before: velocity {now['d_velocity']:.1e} m/s, "
                 f"point {now['d_point']:.1e} m, observation error {now['d_error']:.1e} px")
    lines.append(f"(best of the repeats, this process; load average {rows[0]['load']:.1f} "
                 "at the start: on a shared machine wall-clock times are upper bounds)")
    return "\n".join(lines)
