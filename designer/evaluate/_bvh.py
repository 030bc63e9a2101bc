"""Bounding-volume hierarchy over triangles and exact nearest-triangle queries.

Local coordinates (world − a mesh origin), float64, metres. The hierarchy is built over
triangles sorted by the Morton code of their centroids (one grid scale for all axes);
a node splits its range where the highest differing Morton bit changes (Karras 2012),
or in the middle when all codes are equal. Queries descend nearest child first and
prune every box (and every triangle's own box) not closer than the best distance so
far, so the result is the exact nearest triangle; the closest point on a triangle
follows Ericson (2005, §5.1.5). Points are processed in Morton order, in blocks run in
parallel; within a block each point starts from the previous point's triangle as an
upper bound. The loops are C (``csrc/bvh.c``, ``csrc/closest.h``); these functions
check and allocate.
"""

from __future__ import annotations

import numpy as np

from designer.evaluate._native import ckernels, f8, i8, threads


def centroid_codes(local, faces, lo, scale) -> np.ndarray:
    """Morton codes (M,) of the centroids of triangles ``faces`` over vertices ``local``."""
    local, faces = f8(local).reshape(-1, 3), i8(faces).reshape(-1, 3)
    out = np.empty(len(faces), dtype=np.uint64)
    ckernels().centroid_codes(local, len(local), faces, len(faces), f8(lo), f8(scale), out,
                              threads())
    return out


def radix_argsort(codes) -> np.ndarray:
    """Stable argsort (N,) int64 of uint64 ``codes`` (LSD radix, 16-bit digits)."""
    codes = np.ascontiguousarray(codes, dtype=np.uint64)
    order = np.empty(len(codes), dtype=np.int64)
    ckernels().radix_argsort(codes, len(codes), order)
    return order


def build_bvh(codes, tri) -> tuple[np.ndarray, np.ndarray]:
    """Nodes of a BVH over triangles ``tri`` (M, 9) sorted by Morton ``codes`` (M,).

    Returns ``box`` (K, 6) = (x, y, z) min then max of each node, and ``link`` (K, 2):
    an inner node has link = (first child, 0) with its two children stored side by side;
    a leaf has link = (first triangle, number of triangles). Node 0 is the root.
    """
    codes = np.ascontiguousarray(codes, dtype=np.uint64)
    tri = f8(tri).reshape(-1, 9)
    cap = max(1, 2 * len(tri) - 1)
    box = np.empty((cap, 6))
    link = np.empty((cap, 2), dtype=np.int64)
    n_nodes = ckernels().build_bvh(codes, tri, len(tri), box, link)
    # views: the rows past n_nodes were never written, so they cost no memory
    return box[:n_nodes], link[:n_nodes]


def query(points_world, origin_world, lo, scale, tri, box, link, limit_d2, normals_face,
          neighbours, crowded, normals_vert, corner_vertex, dist: np.ndarray,
          nearest: np.ndarray | None = None) -> None:
    """Write the signed distance of each world point (N, 3) into ``dist`` (N,) float64
    and, when given, its nearest triangle in BVH order into ``nearest`` (N,) int64.

    Points are made local (− ``origin_world``) and ordered along the Morton curve of the
    grid ``lo``, ``scale`` inside the kernel (no copy of the cloud). ``limit_d2`` bounds
    the search: points farther than sqrt(limit_d2) get NaN and triangle −1.
    """
    points = f8(points_world).reshape(-1, 3)
    crowded = f8(crowded).reshape(-1, 3)
    normals_vert = f8(normals_vert).reshape(-1, 3)
    n, m, k = len(points), len(tri), len(box)
    ckernels().query(points, n, f8(origin_world), f8(lo), f8(scale), f8(tri), m, f8(box),
                     i8(link), k, f8(normals_face), i8(neighbours), crowded, len(crowded),
                     normals_vert, len(normals_vert), i8(corner_vertex), float(limit_d2), dist,
                     nearest, threads())
