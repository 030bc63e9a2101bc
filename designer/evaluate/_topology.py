"""Mesh topology for the sign: welding, face geometry and pseudo-normals.

The sign of a distance comes from the pseudo-normal of the nearest feature (Bærentzen
& Aanæs 2005): the face normal; for an edge, the sum of the normals of the faces
sharing it (one face on a boundary); for a vertex, the angle-weighted sum of its
faces' normals. Edges are found by a counting sort of their smaller vertex id, so no
hashing of every edge is needed; only vertices on open edges are hashed, to weld
corners that were split with bit-identical coordinates. The loops are C
(``csrc/topology.c``); these functions check and allocate.
"""

from __future__ import annotations

import numpy as np

from designer.evaluate._native import ckernels, f8, i8, threads


def weld_vertices(vertices, candidates) -> np.ndarray:
    """Canonical index (N,) of each vertex: among ``candidates`` (indices), the first
    with bit-identical x, y, z; every other vertex maps to itself."""
    vertices, candidates = f8(vertices).reshape(-1, 3), i8(candidates)
    out = np.empty(len(vertices), dtype=np.int64)
    ckernels().weld_vertices(vertices, len(vertices), candidates, len(candidates), out)
    return out


def face_geometry(local, faces) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Corners (M, 9), unit normals (M, 3) (zero for degenerate faces) and the angle at
    each corner (M, 3) in radians of the triangles ``faces`` over vertices ``local``."""
    local, faces = f8(local).reshape(-1, 3), i8(faces).reshape(-1, 3)
    m = len(faces)
    tri, normal, angle = np.empty((m, 9)), np.empty((m, 3)), np.empty((m, 3))
    ckernels().face_geometry(local, len(local), faces, m, tri, normal, angle, threads())
    return tri, normal, angle


def vertex_normals(faces, normal, angle, n_vertices: int) -> np.ndarray:
    """(N, 3) pseudo-normal of each vertex: the angle-weighted sum of its faces' normals."""
    faces = i8(faces).reshape(-1, 3)
    vert = np.zeros((n_vertices, 3))
    ckernels().vertex_normals(faces, len(faces), f8(normal), f8(angle), vert, n_vertices)
    return vert


def edge_neighbours(faces, normal, n_vertices: int) -> tuple[np.ndarray, np.ndarray]:
    """The face across edge k (corners k, k + 1) of each face, (M, 3) int64: −1 on a
    boundary edge; −2 − e where three or more faces share the edge, e indexing the
    returned (E, 3) sums of their normals (the pseudo-normal of such an edge)."""
    faces = i8(faces).reshape(-1, 3)
    neighbour = np.empty((len(faces), 3), dtype=np.int64)
    sums = ckernels().edge_neighbours(faces, len(faces), n_vertices, f8(normal), neighbour,
                                      threads())
    return neighbour, np.frombuffer(sums, dtype=np.float64).reshape(-1, 3).copy()
