"""``designer warmup``: check the compiled kernels and build matplotlib's font cache once,
right after installation (``make setup`` runs it).

The comparison's kernels are C, compiled by ``pip install``; this runs each of them on a
tiny mesh, so a broken build shows at installation, not in a user's first comparison.
matplotlib builds its font cache on its first import; doing that here keeps it out of
the first ``designer compare``.
"""

from __future__ import annotations

import time


def register(subparsers) -> None:
    parser = subparsers.add_parser(
        "warmup", help="check the compiled kernels after installation (make setup runs it)",
        description=(
            "Run the point-cloud comparison's compiled kernels once on a tiny mesh (a check "
            "of the installation) and build matplotlib's font cache, so that the first "
            "comparison runs as fast as later ones."),
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
