"""``designer demo``: the example survey end to end, headless."""

from __future__ import annotations

import argparse
import time
from pathlib import Path


def register(subparsers) -> None:
    parser = subparsers.add_parser(
        "demo", help="run the bundled example survey end to end (headless)",
        description=("Write the example survey, check it, plan it, render it with its ground "
                     "truth, and write a report with figures and timings. Re-running "
                     "resumes: finished images are kept."),
    )
    parser.add_argument("-o", "--output", type=Path, default=Path("demo-output"),
                        help="output folder (default: demo-output)")
    parser.add_argument("--quality", choices=["draft", "survey", "metrology"], default=None,
                        help="render quality (default: the example project's)")
    # A frame subset, for quick tests of the demo itself.
    parser.add_argument("--frames", default=None, help=argparse.SUPPRESS)
    parser.set_defaults(func=run, interrupted_hint="the finished images are kept; run the "
                        "same command again to continue (the render resumes)")


def run(args) -> int:
    from designer.demo import run_demo

    t0 = time.perf_counter()
    report = run_demo(args.output, log=print, quality=args.quality, frames=args.frames)
    print(f"demo finished in {time.perf_counter() - t0:.1f} s; report: {report}")
    return 0
