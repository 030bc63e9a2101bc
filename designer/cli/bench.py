"""``designer bench NAME``: run a benchmark and print its table of measured figures."""

from __future__ import annotations

import argparse
import importlib

BENCHMARKS = {
    "core": "designer.bench.core",
    "scene": "designer.bench.scene",
    "project-io": "designer.bench.project_io",
    "survey": "designer.bench.survey",
    "render": "designer.bench.render",
    "compare": "designer.bench.compare",
    "gui": "designer.bench.gui",
    "accuracy": "designer.bench.accuracy",
    "effects": "designer.bench.effects",
    "dense": "designer.bench.dense",
    "study": "designer.bench.study",
}


def register(subparsers) -> None:
    parser = subparsers.add_parser(
        "bench", help="run a benchmark and print a table of measured figures",
        description="Run a benchmark and print a table of measured figures.",
    )
    parser.add_argument("name", choices=sorted(BENCHMARKS), help="which benchmark")
    parser.add_argument("--repeats", type=int, default=3, help="repeats; the best is kept")
    parser.add_argument("--scale", type=float, default=1.0, help=argparse.SUPPRESS)
    parser.set_defaults(func=run)


def run(args) -> int:
    module = importlib.import_module(BENCHMARKS[args.name])
    rows = module.run(repeats=args.repeats, scale=args.scale)
    print(module.format_table(rows))
    return 0
