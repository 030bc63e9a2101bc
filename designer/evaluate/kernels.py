"""Check the comparison's compiled kernels on a tiny mesh (``designer warmup``).

The kernels are C (``designer/evaluate/csrc``), compiled by ``pip install`` into the
extension module ``designer.evaluate._ckernels``: nothing is compiled or cached at run
time, so the first comparison after installation is as fast as later ones.
:func:`warm_up` runs each of them on a tiny mesh and cloud, with the argument types a
comparison uses — a smoke test of the installation that ``make setup`` runs.
"""

from __future__ import annotations

import numpy as np


def warm_up() -> None:
    """Run every kernel :func:`~.compare.compare_cloud` uses once, on a tiny terrain."""
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
