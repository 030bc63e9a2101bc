"""``designer warmup``: check the compiled kernels and build matplotlib's font cache once,
right after installation (``make setup`` runs it); compile the render path's numba
kernels (texture bake, camera effects: :mod:`designer.render.warmup`).

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
            "comparison runs as fast as later ones; compile the render path's kernels; "
            "render four frames of the example survey to measure this machine's render "
            "speed, which every render time estimate uses (about 15 s on 2 cores)."),
    )
    parser.add_argument("--no-probe", action="store_true",
                        help="skip the probe render (the estimates stay uncalibrated until "
                             "a first render)")
    parser.set_defaults(func=run)


def run(args) -> int:
    t0 = time.perf_counter()
    from designer.evaluate.kernels import warm_up

    warm_up()
    from designer.render.warmup import warm_up as warm_up_render

    warm_up_render()
    t1 = time.perf_counter()
    import matplotlib.font_manager  # noqa: F401  (builds the font cache on first import)

    t2 = time.perf_counter()
    print(f"compiled kernels ready in {t1 - t0:.1f} s; matplotlib fonts {t2 - t1:.1f} s",
          flush=True)
    if not getattr(args, "no_probe", False):
        from designer.render.probe import probe_render_speed
        from designer.render_time.model import cache_dir

        speed = probe_render_speed()
        print(f"render speed measured in {time.perf_counter() - t2:.1f} s "
              f"({speed.images} frames of the example survey): "
              f"{speed.terrain_cpu_s_per_mp_sample:.3f} CPU-s per megapixel-sample on the "
              f"terrain, {speed.background_cpu_s_per_mp_sample:.3f} on the background; "
              f"stored in {cache_dir()}")
    return 0
