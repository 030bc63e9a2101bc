"""``designer study run``: plan every run, render each image set once, process each
distinct processing once, on local worker processes or a Dask cluster; resumable.

Output folder::

    DIR/study.json                the study's plan: runs, their levels and seeds
    DIR/runs/RUN/project.xml      the run's project (valid and runnable on its own)
    DIR/runs/RUN/survey/          images/ (links into the render cache), ground-truth/
    DIR/runs/RUN/run.json         its hashes, GSD and image count
    DIR/runs/RUN/result.json      its results row, written when it is finished
    DIR/cache/renders/HASH/       one render per distinct image set
    DIR/cache/processing/HASH/    one reconstruction + comparison per distinct processing
    DIR/cache/features/           features and matches, shared by runs of the same images
    DIR/cache/step-cpu/GROUP/     what computing them (and SfM models) cost in CPU seconds
    DIR/results.csv, summary.json, report.html, report.md

A run with a ``result.json`` is finished (``ok`` or ``failed: reason``) and is not redone
by ``--resume``, which continues a killed study, re-rendering only unfinished images;
``--resume --retry-failed`` also redoes the failed runs: their failed render or
reconstruction is done again (a render keeps its finished, up-to-date images).
"""

from __future__ import annotations

import json
import shutil
import sys
import time
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from pathlib import Path

from designer.atomic import write_text_atomic
from designer.errors import DesignerError
from designer.study import stages
from designer.study.cost import REUSABLE_STEPS, STEP_CPU_DIR
from designer.study.design import Plan, Run

Progress = Callable[[dict], None]


@dataclass
class StudyRunReport:
    out_dir: Path
    rows: list[dict]
    counts: dict = field(default_factory=dict)
    seconds: float = 0.0
    #: what of the report could not be made (a figure, a table), one line each
    report_problems: list[str] = field(default_factory=list)


def _stop_signals() -> set:
    import signal

    return {getattr(signal, n) for n in ("SIGINT", "SIGTERM", "SIGHUP") if hasattr(signal, n)}


_STOP_SIGNALS = _stop_signals()


def _worker_start(parent_pid: int) -> None:
    """A pool worker's start: the stop signals the parent held while starting it are
    this process's again, and it dies with its parent."""
    import signal

    from designer.lifetime import die_with_parent

    signal.pthread_sigmask(signal.SIG_UNBLOCK, _STOP_SIGNALS)
    die_with_parent(parent_pid)


class _Local:
    """Worker processes on this machine (spawned: no state shared with the caller)."""

    def __init__(self, workers: int) -> None:
        import multiprocessing
        import os
        from concurrent.futures import ProcessPoolExecutor

        # each worker dies with this process, even killed (no orphan keeps rendering)
        self.pool = ProcessPoolExecutor(max_workers=workers,
                                        mp_context=multiprocessing.get_context("spawn"),
                                        initializer=_worker_start, initargs=(os.getpid(),))
        # start every worker now, before any stage runs: a worker started later, while a
        # stop signal ends this process, would fail half-started with a traceback
        for future in [self.submit(os.getpid) for _ in range(workers)]:
            future.result()

    def submit(self, fn, *args, priority: int = 0):
        # a submit may start a worker process: a stop signal arriving while it is being
        # handed its start-up data would leave it half-started (a traceback on its closed
        # pipe), so the signals wait until the worker has its data
        import signal

        held = signal.pthread_sigmask(signal.SIG_BLOCK, _STOP_SIGNALS)
        try:
            return self.pool.submit(fn, *args)
        finally:
            signal.pthread_sigmask(signal.SIG_SETMASK, held)

    def wait_first(self, futures):
        from concurrent.futures import FIRST_COMPLETED, wait

        return wait(futures, return_when=FIRST_COMPLETED).done

    def close(self, cancel: bool = False) -> None:
        if cancel:
            # stop the workers now, one still starting included: the pool's own shutdown
            # would wait for the running stages, or leave a starting worker to fail on
            # its closed pipe with a traceback
            for process in list(getattr(self.pool, "_processes", {}).values()):
                if process.is_alive():
                    process.terminate()
        self.pool.shutdown(wait=not cancel, cancel_futures=cancel)


class _Dask:
    """An existing dask.distributed cluster; renders are submitted with the top priority."""

    def __init__(self, scheduler: str) -> None:
        try:
            from distributed import Client
        except ImportError:
            raise DesignerError("--scheduler needs dask.distributed: pip install "
                                "'designer[cluster]'") from None
        try:
            self.client = Client(scheduler, timeout="10s")
        except (OSError, TimeoutError) as error:
            raise DesignerError(f"--scheduler {scheduler}: cannot connect ({error}); start "
                                "it with 'dask scheduler' and 'dask worker'") from None

    def submit(self, fn, *args, priority: int = 0):
        return self.client.submit(fn, *args, pure=False, priority=priority)

    def wait_first(self, futures):
        from distributed import wait

        return wait(list(futures), return_when="FIRST_COMPLETED").done

    def close(self, cancel: bool = False) -> None:
        self.client.close()


def _ground_truth_formats(run: Run) -> Run:
    outputs = replace(run.project.outputs, ground_truth=("colmap", "opk", "gcp"))
    return replace(run, project=replace(run.project, outputs=outputs))


def _plan_runs(plan: Plan, out: Path, progress: Progress) -> dict[str, dict]:
    """run.json of every run (written now, or kept from an earlier run of the study)."""
    infos = {}
    planned: dict[str, tuple[Path, dict]] = {}  # images_key → the first run with them
    for k, run in enumerate(plan.runs):
        run = _ground_truth_formats(run)
        run_dir = out / "runs" / run.run_id
        project = stages.rebase_files(run.project, plan.base_dir, run_dir)
        key = stages.images_key(project)
        info_path = run_dir / "run.json"
        if info_path.is_file():
            info = json.loads(info_path.read_text())
            # planned by this version (an earlier one did not keep the ground truth's digest)
            if info.get("project_repr") == repr(project) and "ground_truth_digest" in info:
                infos[run.run_id] = info
                planned.setdefault(key, (run_dir, info))
                continue
        info = stages.plan_run(project, run_dir, planned.get(key))
        planned.setdefault(key, (run_dir, info))
        info.update({"run": run.run_id, "variant": run.variant, "replicate": run.replicate,
                     "levels": run.levels, "seeds": run.seeds, "project_repr": repr(project)})
        write_text_atomic(info_path, json.dumps(info, indent=1))
        infos[run.run_id] = info
        progress({"event": "planned", "run": run.run_id, "done": k + 1,
                  "total": len(plan.runs)})
    return infos


def _failed(path: Path) -> bool:
    """A result (result.json or a stage's done.json) that records a failure."""
    try:
        return json.loads(path.read_text()).get("status", "ok") != "ok"
    except (OSError, ValueError, AttributeError):
        return False


def _forget_failures(out: Path, infos: dict[str, dict]) -> None:
    """Make every failed run unfinished again, with the failed stages it depends on: the
    run's result.json and a failed render's or reconstruction's done.json are removed
    (a render's images stay: the render resumes)."""
    for rid, info in infos.items():
        result = out / "runs" / rid / "result.json"
        if not _failed(result):
            continue
        result.unlink()
        for stage in (out / "cache" / "renders" / info["image_hash"],
                      out / "cache" / "processing" / info["processing_hash"]):
            if _failed(stage / stages.DONE):
                (stage / stages.DONE).unlink()


def _check_folder(out: Path, plan: Plan, resume: bool) -> None:
    marker = out / "study.json"
    if marker.is_file():
        recorded = json.loads(marker.read_text())
        if not resume:
            raise DesignerError(
                f"{out} holds the results of study '{recorded.get('name')}'; continue it "
                "with --resume, or give another output folder")
        if recorded.get("name") != plan.study.name:
            raise DesignerError(
                f"{out} holds study '{recorded.get('name')}', not '{plan.study.name}'; give "
                "another output folder")
    elif out.exists() and any(out.iterdir()) and not resume:
        raise DesignerError(f"{out} is not empty; give a new or empty output folder")


def run_study(plan: Plan, out_dir: Path, *, workers: int = 1, scheduler: str | None = None,
              resume: bool = False, progress: Progress | None = None,
              render_workers: int = 1, retry_failed: bool = False) -> StudyRunReport:
    """Run every run of ``plan`` into ``out_dir``; results, summary and report written."""
    from designer.study.results import write_results

    progress = progress or (lambda _event: None)
    # absolute: every path a task carries derives from it, and a cluster worker resolves
    # a relative one in its own working directory
    out = Path(out_dir).resolve()
    _check_folder(out, plan, resume)
    if scheduler:  # an unreachable cluster is an error before anything is written
        _Dask(scheduler).close()
    out.mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    write_text_atomic(out / "study.json", json.dumps({
        "name": plan.study.name, "study": str(plan.study.source or ""),
        "design": plan.study.design, "variants": plan.n_variants,
        "replicates": plan.study.replicates.count,
        "factors": {f.name: list(f.values) for f in plan.study.factors},
        "runs": [r.run_id for r in plan.runs]}, indent=1))
    infos = _plan_runs(plan, out, progress)
    if retry_failed:
        _forget_failures(out, infos)
    finished = {rid for rid in infos if (out / "runs" / rid / "result.json").is_file()}
    counts = _execute(out, infos, finished, workers, scheduler, progress, render_workers)
    rows = [json.loads((out / "runs" / r.run_id / "result.json").read_text())
            for r in plan.runs]
    counts.update({"variants": plan.n_variants, "runs": len(rows),
                   "failed": sum(r["status"] != "ok" for r in rows)})
    report = StudyRunReport(out, rows, counts, time.perf_counter() - t0)
    report.report_problems = write_results(plan, report)
    return report


def _execute(out: Path, infos: dict[str, dict], finished: set[str], workers: int,
             scheduler: str | None, progress: Progress, render_workers: int) -> dict:
    renders = out / "cache" / "renders"
    processing = out / "cache" / "processing"
    by_image: dict[str, list[str]] = {}
    by_proc: dict[str, list[str]] = {}
    for rid, info in infos.items():
        by_image.setdefault(info["image_hash"], []).append(rid)
        by_proc.setdefault(info["processing_hash"], []).append(rid)
    # image sets that differ only in their camera effects share one Cycles render: the
    # first of each raw group renders and keeps its raw images, the others are effect
    # passes over them
    by_raw: dict[str, list[str]] = {}
    for h, rids in by_image.items():
        by_raw.setdefault(infos[rids[0]].get("raw_hash") or h, []).append(h)
    raw_of = {h: r for r, hs in by_raw.items() for h in hs}
    raw_cache = out / "cache" / "raw"
    counts = {"renders": len(by_image), "reconstructions": len(by_proc),
              "raw_renders": len(by_raw), "effect_passes": len(by_image) - len(by_raw),
              "renders_this_session": 0, "reconstructions_this_session": 0,
              "raw_renders_this_session": 0, "effect_passes_this_session": 0}
    counts["cache_hits"] = (len(infos) - len(by_image)) + (len(infos) - len(by_proc))
    todo = [rid for rid in infos if rid not in finished]
    if not todo:
        return counts
    executor = _Dask(scheduler) if scheduler else _Local(max(1, workers))
    pending: dict = {}
    done_renders: dict[str, dict] = {}
    submitted_proc: set[str] = set()
    total, n_done = len(infos), len(finished)

    def render_result(h: str) -> dict | None:
        path = renders / h / stages.DONE
        return json.loads(path.read_text()) if path.is_file() else None

    def needed(h: str) -> bool:
        return not all(r in finished for r in by_image[h])

    def submit_render(h: str) -> None:
        """A Cycles render of image set ``h`` (keeping its raw renders when other image
        sets of its raw group need them), or an effect pass when its group's first
        image set has rendered them."""
        group = by_raw[raw_of[h]]
        raw_dir = raw_cache / raw_of[h]
        project = out / "runs" / by_image[h][0] / "project.xml"
        owner = render_result(group[0]) if h != group[0] else None
        if owner is not None and owner.get("status") == "ok" and raw_dir.is_dir():
            future = executor.submit(stages.render_stage, str(project), str(renders / h),
                                     render_workers, None, str(raw_dir), priority=10)
            counts["effect_passes_this_session"] += 1
        else:
            keep = str(raw_dir) if h == group[0] and any(needed(o) for o in group[1:]) \
                else None
            future = executor.submit(stages.render_stage, str(project), str(renders / h),
                                     render_workers, keep, None, priority=10)
            counts["raw_renders_this_session"] += 1
        pending[future] = ("render", h)
        counts["renders_this_session"] += 1
        progress({"event": "render_started", "image_set": h, "runs": len(by_image[h])})

    def rendered(h: str, result: dict) -> None:
        done_renders[h] = result
        submit_processing(h)
        group = by_raw[raw_of[h]]
        if h == group[0]:  # the raw renders are there: the group's effect passes
            for other in group[1:]:
                if needed(other) and other not in done_renders and \
                        other not in waiting_on_raw_done:
                    waiting_on_raw_done.add(other)
                    done = render_result(other)
                    if done is not None:
                        rendered(other, done)
                    else:
                        submit_render(other)

    waiting_on_raw_done: set[str] = set()

    def submit_processing(h: str) -> None:
        for rid in models_first(by_image[h], infos):
            p = infos[rid]["processing_hash"]
            if rid in finished or p in submitted_proc:
                continue
            submitted_proc.add(p)
            result = json.loads((processing / p / stages.DONE).read_text()) \
                if (processing / p / stages.DONE).is_file() else None
            if result is not None or done_renders[h]["status"] != "ok":
                finish_processing(p, result or {"status": done_renders[h]["status"]})
                continue
            first = out / "runs" / by_proc[p][0]
            stages.link_images(renders / h, first / "survey", infos[rid]["images"])
            future = executor.submit(stages.process_stage, str(first / "survey"),
                                     str(first / "project.xml"), str(processing / p),
                                     str(out / "cache" / "features"),
                                     {step: str(out / STEP_CPU_DIR / infos[rid][group])
                                      for step, _, group in REUSABLE_STEPS},
                                     priority=0)
            pending[future] = ("process", p)
            counts["reconstructions_this_session"] += 1

    def finish_processing(p: str, result: dict) -> None:
        nonlocal n_done
        for rid in by_proc[p]:
            if rid in finished:
                continue
            info = infos[rid]
            h = info["image_hash"]
            row = _row(info, done_renders.get(h) or {}, result, owner=by_proc[p][0] == rid,
                       render_owner=by_image[h][0] == rid, proc_dir=processing / p)
            row.update(render_runs=len(by_image[h]), processing_runs=len(by_proc[p]))
            write_text_atomic(out / "runs" / rid / "result.json", json.dumps(row, indent=1))
            finished.add(rid)
            n_done += 1
            progress({"event": "run_done", "run": rid, "status": row["status"],
                      "done": n_done, "total": total})

    try:
        for group in by_raw.values():
            owner = group[0]
            if not any(needed(h) for h in group):
                continue
            result = render_result(owner)
            if result is not None:
                rendered(owner, result)
            else:
                submit_render(owner)
        while pending:
            for future in executor.wait_first(pending):
                kind, key = pending.pop(future)
                try:
                    result = future.result()
                except Exception as error:  # a crashed worker process: record, go on
                    result = {"status": f"failed: {kind} worker: {error}"[:300]}
                if kind == "render":
                    progress({"event": "render_done", "image_set": key,
                              "seconds": result.get("render_s"),
                              "kind": result.get("kind", "cycles")})
                    rendered(key, result)
                else:
                    finish_processing(key, result)
    except BaseException:
        executor.close(cancel=True)
        raise
    executor.close()
    return counts


def _row(info: dict, render: dict, result: dict, owner: bool, render_owner: bool,
         proc_dir: Path) -> dict:
    row = {"run": info["run"], "variant": info["variant"], "replicate": info["replicate"]}
    row.update({f"factor:{k}": v for k, v in info["levels"].items()})
    row.update({f"seed:{k}": v for k, v in info["seeds"].items()})
    row.update({"images": len(info["images"]), "gsd_m": info["gsd_m"],
                "flight_min": info.get("flight_min"),
                "flight_min_source": info.get("flight_min_source"),
                "gcps": info.get("gcps"), "control_gcps": info.get("control_gcps"),
                "image_hash": info["image_hash"], "processing_hash": info["processing_hash"],
                "features_group": info.get("features_group"),
                "sfm_group": info.get("sfm_group"),
                "render_s": render.get("render_s"), "render_cpu_s": render.get("render_cpu_s"),
                "render_cycles_cpu_s": render.get("render_cycles_cpu_s"),
                "render_reused": not render_owner, "processing_reused": not owner})
    # the images rendered stay the run's count (the reconstruction reports those it read)
    row.update({k: v for k, v in result.items() if k not in ("status", "images")})
    if row.get("error_map"):
        row["error_map"] = str(proc_dir / row["error_map"])
    row["status"] = result.get("status", "failed: unknown")
    return row


def remove_partial(out: Path) -> None:
    """Remove unfinished stage folders (no done.json) of a study folder."""
    for kind in ("renders", "processing"):
        for folder in (out / "cache" / kind).glob("*"):
            if not (folder / stages.DONE).is_file():
                shutil.rmtree(folder, ignore_errors=True)


def print_progress(mode: str) -> Progress:
    def as_json(event: dict) -> None:
        print(json.dumps(event), flush=True)

    def as_bar(event: dict) -> None:
        if event.get("event") == "run_done":
            n, total = event["done"], event["total"]
            filled = int(30 * n / max(total, 1))
            sys.stderr.write(f"\r[{'#' * filled}{'.' * (30 - filled)}] {n}/{total} runs "
                             f"({event['run']}: {event['status'][:40]})")
            if n == total:
                sys.stderr.write("\n")
            sys.stderr.flush()
        elif event.get("event") == "planned":
            sys.stderr.write(f"\rplanning {event['done']}/{event['total']} runs")
            sys.stderr.flush()

    return {"json": as_json, "bar": as_bar}.get(mode, lambda _event: None)


def models_first(rids: list[str], infos: dict[str, dict]) -> list[str]:
    """``rids`` with the first run of each SfM model first, then the second of each, …
    (otherwise in their order): distinct models (another calibration or mapper) are found
    side by side by the workers, rather than one worker finding a model while the other
    waits for the same model for the next run."""
    nth_in_model: dict[str, int] = {}
    runs_of: dict[str, int] = {}
    for rid in rids:
        model = infos[rid].get("sfm_group") or rid
        nth_in_model[rid] = runs_of.get(model, 0)
        runs_of[model] = nth_in_model[rid] + 1
    return sorted(rids, key=nth_in_model.__getitem__)  # a stable sort
