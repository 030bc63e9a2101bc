"""``designer demo``: the example survey end to end, headless.

The demo grows with the product: each stage that exists runs, in order, and writes
its results under the output folder.
"""

from __future__ import annotations

import time
from pathlib import Path


def register(subparsers) -> None:
    parser = subparsers.add_parser(
        "demo", help="run the bundled example survey end to end (headless)",
        description="Run the bundled example survey end to end, headless, and write a report.",
    )
    parser.add_argument("-o", "--output", type=Path, default=Path("demo-output"),
                        help="output folder (default: demo-output)")
    parser.set_defaults(func=run)


def run(args) -> int:
    from designer.demo import run_demo

    t0 = time.perf_counter()
    report = run_demo(args.output, log=print)
    print(f"demo finished in {time.perf_counter() - t0:.1f} s; report: {report}")
    return 0
