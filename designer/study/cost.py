"""What a run costs a surveyor, in the units a surveyor pays in, and what it cost the study.

Per run (columns of results.csv):

* ``flight_min`` — minutes from the first photo to the last: the project's flight time
  line when it has one (:mod:`designer.survey.timeline`: legs at its speed, its turn
  seconds, explicit photo times), else the length of the path through the perspective
  centres in flight order at :data:`DEFAULT_SPEED_M_S` (no turn time).
  ``flight_min_source`` says which. Neither counts the climb, the transit to the first
  photo or the landing;
* ``images`` — every image rendered (a rig station gives one per mount);
* ``gcps`` — GCP targets to survey in the field: control and check targets alike;
  ``control_gcps`` — of them, the ones the processing uses as control (0 with GCP mode
  ``none``);
* CPU seconds — process CPU time (user + system, every thread; and every child process
  that ended), which load from other jobs on a shared machine barely moves, unlike wall
  seconds: see :func:`cpu_seconds` and docs/studies.md for what each column counts.

:data:`COSTS` are the cost axes a study may plot accuracy against (``<cost>``).
"""

from __future__ import annotations

import json
import resource
import statistics
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

#: ground speed (m/s) of the flight time of a project without a time line
DEFAULT_SPEED_M_S = 8.0


@dataclass(frozen=True)
class Cost:
    """A cost axis: the results.csv column, its axis label, and whether it is a count
    fixed by the project (``planned``) or measured while the study ran."""

    name: str
    column: str
    label: str
    planned: bool


#: the costs a study may plot accuracy against, by their names in ``<cost>``
COSTS: dict[str, Cost] = {c.name: c for c in (
    Cost("flight-minutes", "flight_min", "flight minutes per survey", True),
    Cost("images", "images", "images per survey", True),
    Cost("gcps", "gcps", "GCP targets surveyed (control + check)", True),
    Cost("control-gcps", "control_gcps", "control GCPs", True),
    Cost("cpu-seconds", "reconstruct_cpu_s",
         "processing CPU seconds per survey (reconstruction on its own)", False),
    Cost("wall-seconds", "total_s",
         "wall seconds per run (render + reconstruct + compare)", False),
)}
DEFAULT_COST = "flight-minutes"

#: results.csv columns that are costs, not accuracy
COST_COLUMNS = ("total_s", "amortised_s", "render_s", "reconstruct_s", "compare_s",
                "images", "flight_min", "gcps", "control_gcps", "render_cpu_s",
                "reconstruct_cpu_s", "compare_cpu_s", "cpu_s", "cpu_amortised_s")


def accuracy_metric(metrics) -> str:
    """The metric the report plots against cost: the study's first that is not a cost
    or the registered-image count."""
    metrics = list(metrics)
    return next((m for m in metrics if m != "registered" and m not in COST_COLUMNS),
                metrics[0])


def path_length_m(centres_world: np.ndarray) -> float:
    """Length (m) of the polyline through ``centres_world`` (N, 3), in their order."""
    c = np.asarray(centres_world, float).reshape(-1, 3)
    return float(np.linalg.norm(np.diff(c, axis=0), axis=1).sum()) if len(c) > 1 else 0.0


def flight_minutes(centres_world: np.ndarray, times_s: Sequence[float] | None
                   ) -> tuple[float, str]:
    """(minutes, source) of a flight: the last photo's time after the first when the
    photos have times (``times_s``, seconds after take-off), else the path through the
    perspective centres (N, 3; world m, in flight order) at :data:`DEFAULT_SPEED_M_S`."""
    if times_s is not None and len(times_s):
        return (max(times_s) - min(times_s)) / 60.0, "time line"
    return path_length_m(centres_world) / DEFAULT_SPEED_M_S / 60.0, \
        f"path at {DEFAULT_SPEED_M_S:g} m/s"


def gcp_counts(project) -> tuple[int, int]:
    """(GCP targets to survey, of them the processing's control points)."""
    from designer.project import model as m
    from designer.project.processing import control_count

    targets = project.targets
    p = project.processing or m.Processing()
    if p.gcps.mode == "none":
        return len(targets), 0
    return len(targets), control_count(p.gcps.control, targets)


def cpu_seconds() -> float:
    """CPU seconds (user + system) so far of this process — all its threads — and of its
    child processes that have ended and been waited for (e.g. Blender workers)."""
    own = resource.getrusage(resource.RUSAGE_SELF)
    children = resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime + children.ru_utime + children.ru_stime


#: the reconstruction's log line that starts a step → the step
_STEP_LINES = {"features:": "features", "matching:": "matching", "incremental SfM": "sfm",
               "global SfM": "sfm"}
#: the steps a reconstruction may take from the feature cache: the step, the row's column
#: saying it was taken, the row's column naming the runs that share it
REUSABLE_STEPS = (("features", "features_reused", "features_group"),
                  ("matching", "matches_reused", "features_group"),
                  ("sfm", "sfm_reused", "sfm_group"))
#: where a study keeps what computing features and matches cost, per group of runs that
#: share them (relative to the study folder)
STEP_CPU_DIR = Path("cache") / "step-cpu"


class StageClock:
    """CPU seconds of the steps of a reconstruction, split at its log lines: the step a
    line starts (``features: …``, ``matching: …``, ``incremental SfM``) runs until the
    next line (the SfM mapper's: until the model is georeferenced, a few cheap steps
    after it). Passed as the reconstruction's ``log``; ``on_step(step, cpu_s)`` hears
    each step as it ends (``features``, ``matching``, ``sfm``), before the
    reconstruction goes on."""

    def __init__(self, on_step=None) -> None:
        self.marks: list[tuple[str, float]] = []
        self.on_step = on_step

    def __call__(self, message: str) -> None:
        now = cpu_seconds()
        if self.marks and self.on_step is not None:
            step = self._step(self.marks[-1][0])
            if step is not None:
                self.on_step(step, now - self.marks[-1][1])
        self.marks.append((message, now))

    def _step(self, message: str) -> str | None:
        return next((s for p, s in _STEP_LINES.items() if message.startswith(p)), None)

    def step_cpu_s(self, step: str, end: float) -> float | None:
        """CPU seconds of ``step`` (``features``/``matching``/``sfm``; None: it did not run, e.g.
        its result came from the feature cache); ``end``: the CPU clock when the
        reconstruction returned."""
        for k, (message, start) in enumerate(self.marks):
            if self._step(message) == step:
                stop = self.marks[k + 1][1] if k + 1 < len(self.marks) else end
                return stop - start
        return None


def record_step_cpu(folder: Path, name: str, step: str, cpu_s: float) -> None:
    """Keep what computing ``step`` cost (``folder``: one per group of runs that share
    features and matches; ``name``: the reconstruction's), for the runs that will reuse
    it — even when the reconstruction that computed it is killed later."""
    from designer.atomic import write_text_atomic

    folder.mkdir(parents=True, exist_ok=True)
    write_text_atomic(folder / f"{name}-{step}.json", json.dumps({"cpu_s": cpu_s}))


def recorded_step_cpu(root: Path) -> dict[tuple[str, str], list[float]]:
    """Every recorded step under ``root`` (:func:`record_step_cpu`) by (group, step)."""
    out: dict[tuple[str, str], list[float]] = {}
    for path in sorted(Path(root).glob("*/*.json")) if Path(root).is_dir() else ():
        step = path.stem.rsplit("-", 1)[-1]
        try:
            out.setdefault((path.parent.name, step), []).append(
                float(json.loads(path.read_text())["cpu_s"]))
        except (OSError, ValueError, KeyError, TypeError):
            continue
    return out


def add_reused_cpu(rows: list[dict], recorded: dict | None = None) -> list[dict]:
    """Each row's ``reconstruct_cpu_s``: what its reconstruction would have cost on its
    own — the CPU it spent (``reconstruct_cpu_spent_s``) plus, for each step it took from
    the study's feature cache (features, matches, the SfM model), the CPU that computing
    it cost a reconstruction of its group (:data:`REUSABLE_STEPS`): the median of those
    ``recorded`` (:func:`recorded_step_cpu`), else of the rows that computed it. Rows are
    changed in place and returned."""
    spent: dict[tuple[str, str], list[float]] = {k: list(v) for k, v in
                                                  (recorded or {}).items()}
    if not recorded:
        for r in rows:
            for step, _, group in REUSABLE_STEPS:
                v = r.get(f"{step}_cpu_s")
                if v is not None and r.get(group):
                    spent.setdefault((r[group], step), []).append(float(v))
    for r in rows:
        own = r.get("reconstruct_cpu_spent_s")
        if own is None:
            r["reconstruct_cpu_s"] = None
            continue
        total = float(own)
        for step, flag, group in REUSABLE_STEPS:
            if _true(r.get(flag)) and r.get(f"{step}_cpu_s") is None:
                done = spent.get((r.get(group), step))
                total += statistics.median(done) if done else 0.0
        r["reconstruct_cpu_s"] = total
    return rows


def _true(v) -> bool:
    return v is True or v == "True"
