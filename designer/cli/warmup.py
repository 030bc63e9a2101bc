"""``designer warmup``: compile the numba kernels once, right after installation.

numba compiles a kernel on its first call and caches the machine code on disk; without
this step the first ``designer compare`` (or the GUI's first Reconstruct) would spend
about 25 s compiling. ``make setup`` runs it after ``pip install``. It also builds
matplotlib's font cache, which the first figure would otherwise build.
"""

from __future__ import annotations

import time


def register(subparsers) -> None:
    parser = subparsers.add_parser(
        "warmup", help="compile the numba kernels once after installation (make setup runs it)",
        description=(
            "Compile the numba kernels of the point-cloud comparison and cache them on disk "
            "(beside the sources, or in ~/.cache/numba when those are read-only, or in "
            "$NUMBA_CACHE_DIR), and build matplotlib's font cache, so that the first "
            "comparison runs as fast as later ones. Run again after upgrading numba."),
    )
    parser.set_defaults(func=run)


def run(args) -> int:
    t0 = time.perf_counter()
    from designer.evaluate.kernels import warm_up

    warm_up()
    t1 = time.perf_counter()
    import matplotlib.font_manager  # noqa: F401  (builds the font cache on first import)

    t2 = time.perf_counter()
    print(f"compiled kernels ready in {t1 - t0:.1f} s; matplotlib fonts {t2 - t1:.1f} s")
    return 0
