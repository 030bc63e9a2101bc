"""``designer study``: run many virtual surveys that vary named parameters.

``designer study new FILE --template NAME`` writes an example study and its base project;
``designer study check FILE`` validates a study and lists its runs;
``designer study factors`` lists the parameters a study can vary;
``designer study run STUDY.xml -o DIR`` runs it (see designer.study.run).
"""

from __future__ import annotations

import sys
from pathlib import Path

#: ``designer study run``'s exit status when it finished but some runs failed (every
#: result is written; bad input is 2, an interruption 130)
RUNS_FAILED_EXIT = 3

TEMPLATES = ("gcp-count", "flight-geometry", "doming", "block-size", "altitude", "rig-obliques",
             "rolling-shutter", "example-processing", "tiny")


def register(subparsers) -> None:
    parser = subparsers.add_parser(
        "study", help="vary parameters across many virtual surveys, with replicates",
        description="Studies: a base project, factors (named parameters and their levels), "
                    "a design and replicates; run renders each distinct image set once and "
                    "writes results.csv, summary.json and report.html.")
    sub = parser.add_subparsers(dest="study_command", metavar="SUBCOMMAND", required=True)
    new = sub.add_parser("new", help="write an example study and its base project")
    new.add_argument("file", type=Path)
    new.add_argument("--template", choices=TEMPLATES, default="gcp-count")
    new.set_defaults(func=run_new)
    check = sub.add_parser("check", help="validate a study and list its runs")
    check.add_argument("study", type=Path)
    check.set_defaults(func=run_check)
    factors = sub.add_parser("factors", help="list the parameters a study can vary")
    factors.set_defaults(func=run_factors)
    run = sub.add_parser("run", help="run a study into an output folder")
    run.add_argument("study", type=Path, help="study XML file")
    run.add_argument("-o", "--output", type=Path, required=True, help="output folder")
    run.add_argument("--workers", type=int, default=1,
                     help="local worker processes (renders and reconstructions in parallel)")
    run.add_argument("--scheduler", metavar="tcp://HOST:PORT",
                     help="run the stages on this existing Dask cluster")
    run.add_argument("--resume", action="store_true",
                     help="continue a study in DIR: finished runs are kept, not redone")
    run.add_argument("--retry-failed", action="store_true",
                     help="with --resume: also redo the runs that failed (their failed "
                          "render or reconstruction; a render keeps its finished images)")
    run.add_argument("--progress", choices=["bar", "json", "none"], default="bar")
    run.set_defaults(func=run_run, interrupted_hint="the finished runs are kept; run the "
                     "same command with --resume to do the rest")


def run_new(args) -> int:
    from designer.errors import DesignerError
    from designer.study.templates import write_template

    if args.file.exists():
        raise DesignerError(f"{args.file} exists; give a new file name")
    for path in write_template(args.template, args.file):
        print(f"wrote {path}")
    return 0


def run_check(args) -> int:
    from designer.study.design import plan_study
    from designer.study.xml import read_study

    plan = plan_study(read_study(args.study))
    print(f"{args.study}: study '{plan.study.name}', {plan.study.design}, {plan.n_variants} "
          f"variants x {plan.study.replicates.count} replicates = {len(plan.runs)} runs")
    return 0


def run_factors(args) -> int:
    from designer.study.factors import DRAWS, FACTORS

    for f in FACTORS.values():
        print(f"{f.name:26s} {f.stage:10s} {f.doc}")
    print("\nreplicate draws (<replicates vary=...>):")
    for name, (doc, _) in DRAWS.items():
        print(f"  {name:24s} {doc}")
    return 0


def run_run(args) -> int:
    from designer.errors import DesignerError
    from designer.study.design import plan_study
    from designer.study.run import print_progress, run_study
    from designer.study.xml import read_study

    if args.workers < 1:
        raise DesignerError(f"--workers {args.workers}: give 1 or more")
    if args.retry_failed and not args.resume:
        raise DesignerError("--retry-failed redoes the failed runs of a study folder; give "
                            "it with --resume")
    plan = plan_study(read_study(args.study))
    report = run_study(plan, args.output, workers=args.workers, scheduler=args.scheduler,
                       resume=args.resume, progress=print_progress(args.progress),
                       retry_failed=args.retry_failed)
    c = report.counts
    print(f"{args.output}: {c['runs']} runs of {c['variants']} variants; renders "
          f"{c['renders']} (distinct image sets), reconstructions {c['reconstructions']}, "
          f"cache hits {c['cache_hits']}, failed {c['failed']}; this session rendered "
          f"{c['renders_this_session']} and reconstructed {c['reconstructions_this_session']}"
          f"; {report.seconds:.0f} s")
    written = ["results.csv", "summary.json"] + \
        (["report.html"] if (args.output / "report.html").is_file() else [])
    print("wrote " + ", ".join(str(args.output / name) for name in written))
    for problem in report.report_problems:  # the runs are what the exit status says
        print(f"designer: {problem}", file=sys.stderr)
    failed = [(run.run_id, row["status"]) for run, row in zip(plan.runs, report.rows,
                                                               strict=True)
              if row["status"] != "ok"]
    if failed:  # the last line, for scripts and schedulers: the status says it too
        run_id, status = failed[0]
        reason = status.removeprefix("failed: ")
        print(f"designer: {len(failed)} of {len(report.rows)} runs failed (first: {run_id}: "
              f"{reason}); their results say why, the others are complete; --resume "
              "--retry-failed redoes the failed ones",
              file=sys.stderr)
        return RUNS_FAILED_EXIT
    return 0
