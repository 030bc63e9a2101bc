"""What a rolling shutter costs Cycles: the example survey with a global and with a
rolling shutter, rendered in turns so both see the same machine load.

    python scripts/rolling-shutter-cost.py [ROUNDS]

Both are the ``pinhole`` and ``rolling`` rows of ``designer bench render`` (the example
survey at 1368 x 912 px, survey quality, its lens distortion removed, a time line at
8 m/s; the rolling one read out over 30 ms). Each round renders two frames of one, then
the same two frames of the other, in a new worker each; printed: the median CPU seconds
(all Cycles threads) and wall seconds inside the render call per image, and the ratio of
the CPU medians. CPU time is compared because a shared machine's load moves the wall
time by tens of per cent between rows of one bench run.

Used for the figures of docs/world.md, "Rolling shutter".
"""

from __future__ import annotations

import statistics
import sys
import tempfile
from pathlib import Path

from designer.bench.render import ROLLING_READOUT_S, _example, _pinhole
from designer.project import load_project
from designer.render.job import prepare_job
from designer.render.runner import render_frames


def main(rounds: int = 3) -> None:
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        project = load_project(_example(tmp))
        jobs = {name: prepare_job(p, tmp, tmp / name, "survey").job_path
                for name, p in (("pinhole", _pinhole(project)),
                                ("rolling", _pinhole(project, ROLLING_READOUT_S)))}
        cpu: dict[str, list[float]] = {name: [] for name in jobs}
        wall: dict[str, list[float]] = {name: [] for name in jobs}
        for k in range(rounds):
            for name, job in jobs.items():
                def record(event, name=name):
                    if event.get("event") == "frame_done":
                        cpu[name].append(event["render_cpu_seconds"])
                        wall[name].append(event["render_seconds"])

                render_frames(job, [2 * k, 2 * k + 1], workers=1, progress=record)
        for name in jobs:
            print(f"{name}: CPU {statistics.median(cpu[name]):.2f} s/img, wall "
                  f"{statistics.median(wall[name]):.2f} s/img (medians of "
                  f"{len(cpu[name])}: CPU {[round(c, 1) for c in cpu[name]]})")
        ratio = statistics.median(cpu["rolling"]) / statistics.median(cpu["pinhole"])
        print(f"rolling / pinhole CPU: {ratio:.3f}")


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 3)
