"""Compile or load the compiled distance and gridding kernels ahead of use.

The kernels are numba functions cached on disk (``cache=True``): the first call after
installation compiles them (about 25 s on 2 cores) and stores machine code in the
``__pycache__`` folders beside the sources, or — where those are read-only — in the
user's cache (``~/.cache/numba``), or in ``$NUMBA_CACHE_DIR`` when set. Every later
process loads them from there (about 0.5 s for the set used by a comparison).

:func:`warm_up` runs the comparison's kernels on a tiny mesh and cloud, with the
argument types a comparison uses, so they are compiled (``designer warmup``, run by
``make setup``) or loaded into this process. :func:`load_in_background` does that in a
thread, while the caller reads its input files.
"""

from __future__ import annotations

import threading

import numpy as np


def warm_up() -> None:
    """Compile (or load from the cache) every kernel :func:`~.compare.compare_cloud` uses."""
    from designer.evaluate.distance import build_mesh_index, signed_distances
    from designer.evaluate.maps import grid_errors

    # a 4 × 4-node terrain at UTM-sized coordinates: open borders (welding is tried),
    # faces, edges and corners nearest to some of the points
    n = 4
    yy, xx = np.mgrid[0:n, 0:n].astype(np.float64)
    vertices = np.column_stack([xx.ravel() + 500000.0, yy.ravel() + 5000000.0,
                                np.sin(xx + yy).ravel() + 100.0])
    sw = (np.arange(n - 1)[:, None] * n + np.arange(n - 1)[None, :]).ravel()
    faces = np.vstack([np.column_stack([sw, sw + 1, sw + n + 1]),
                       np.column_stack([sw, sw + n + 1, sw + n])])
    index = build_mesh_index((vertices, faces))
    rng = np.random.default_rng(0)
    points = vertices[rng.integers(0, len(vertices), 64)] + rng.normal(0.0, 0.5, (64, 3))
    d = signed_distances(points, index)
    signed_distances(points, index, max_distance=0.25, return_faces=True)
    grid_errors(points[:, :2], d)


class _Loader(threading.Thread):
    def __init__(self) -> None:
        super().__init__(name="designer-kernel-loader", daemon=True)
        self.error: BaseException | None = None
        #: set when loading has ended (also on failure)
        self.done = threading.Event()

    def run(self) -> None:
        try:
            warm_up()
        except BaseException as exc:  # reported by join()
            self.error = exc
        finally:
            self.done.set()

    def join(self, timeout: float | None = None) -> None:
        """Wait for the kernels; re-raise what loading them raised."""
        super().join(timeout)
        if self.error is not None:
            raise self.error


def load_in_background() -> _Loader:
    """Start :func:`warm_up` in a thread; ``join()`` the returned thread before use."""
    loader = _Loader()
    loader.start()
    return loader
