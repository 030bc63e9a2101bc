"""Mesh topology for the sign: welding, face geometry and pseudo-normals (numba).

The sign of a distance comes from the pseudo-normal of the nearest feature (Bærentzen
& Aanæs 2005): the face normal; for an edge, the sum of the normals of the faces
sharing it (one face on a boundary); for a vertex, the angle-weighted sum of its
faces' normals. Edges are found by a counting sort of their smaller vertex id, so no
hashing of every edge is needed; only vertices on open edges are hashed, to weld
corners that were split with bit-identical coordinates.
"""

from __future__ import annotations

import numpy as np
from numba import njit, prange


@njit(cache=True, inline="always")
def _mix(h):
    # splitmix64's finaliser: every input bit reaches the low bits the table index uses
    # (coordinates on a grid have mantissas ending in many zero bits)
    h ^= h >> np.uint64(30)
    h *= np.uint64(0xBF58476D1CE4E5B9)
    h ^= h >> np.uint64(27)
    h *= np.uint64(0x94D049BB133111EB)
    h ^= h >> np.uint64(31)
    return h


@njit(cache=True, nogil=True)
def _hash3(a, b, c):
    h = _mix(np.uint64(a))
    h = _mix(h ^ np.uint64(b))
    return _mix(h ^ np.uint64(c))


@njit(cache=True, nogil=True)
def weld_vertices(vertices, candidates):
    """Canonical index (N,) of each vertex: among ``candidates`` (indices), the first
    with bit-identical x, y, z; every other vertex maps to itself."""
    n = vertices.shape[0]
    out = np.arange(n)
    m = candidates.shape[0]
    bits = vertices.view(np.int64)
    size = 1
    while size < 2 * m:
        size <<= 1
    mask = np.uint64(size - 1)
    table = np.full(size, -1, dtype=np.int64)
    for c in range(m):
        i = candidates[c]
        slot = _hash3(bits[i, 0], bits[i, 1], bits[i, 2]) & mask
        while True:
            j = table[slot]
            if j < 0:
                table[slot] = i
                break
            if bits[j, 0] == bits[i, 0] and bits[j, 1] == bits[i, 1] and bits[j, 2] == bits[i, 2]:
                out[i] = j
                break
            slot = (slot + np.uint64(1)) & mask
    return out


@njit(cache=True, nogil=True, parallel=True)
def face_geometry(local, faces):
    """Corners (M, 9), unit normals (M, 3) (zero for degenerate faces) and the angle at
    each corner (M, 3) in radians of the triangles ``faces`` over vertices ``local``."""
    m = faces.shape[0]
    tri = np.empty((m, 9))
    normal = np.zeros((m, 3))
    angle = np.zeros((m, 3))
    for f in prange(m):
        for c in range(3):
            for a in range(3):
                tri[f, 3 * c + a] = local[faces[f, c], a]
        e1x, e1y, e1z = tri[f, 3] - tri[f, 0], tri[f, 4] - tri[f, 1], tri[f, 5] - tri[f, 2]
        e2x, e2y, e2z = tri[f, 6] - tri[f, 0], tri[f, 7] - tri[f, 1], tri[f, 8] - tri[f, 2]
        nx, ny, nz = e1y * e2z - e1z * e2y, e1z * e2x - e1x * e2z, e1x * e2y - e1y * e2x
        length = np.sqrt(nx * nx + ny * ny + nz * nz)
        if length > 0.0:
            normal[f, 0], normal[f, 1], normal[f, 2] = nx / length, ny / length, nz / length
        for c in range(3):
            i, j, k = 3 * c, 3 * ((c + 1) % 3), 3 * ((c + 2) % 3)
            ux, uy = tri[f, j] - tri[f, i], tri[f, j + 1] - tri[f, i + 1]
            uz = tri[f, j + 2] - tri[f, i + 2]
            vx, vy = tri[f, k] - tri[f, i], tri[f, k + 1] - tri[f, i + 1]
            vz = tri[f, k + 2] - tri[f, i + 2]
            cx, cy, cz = uy * vz - uz * vy, uz * vx - ux * vz, ux * vy - uy * vx
            angle[f, c] = np.arctan2(np.sqrt(cx * cx + cy * cy + cz * cz),
                                     ux * vx + uy * vy + uz * vz)
    return tri, normal, angle


@njit(cache=True, nogil=True)
def vertex_normals(faces, normal, angle, n_vertices):
    """(N, 3) pseudo-normal of each vertex: the angle-weighted sum of its faces' normals."""
    vert = np.zeros((n_vertices, 3))
    for f in range(faces.shape[0]):
        for c in range(3):
            v = faces[f, c]
            for a in range(3):
                vert[v, a] += angle[f, c] * normal[f, a]
    return vert


@njit(cache=True, nogil=True)
def edge_neighbours(faces, normal, n_vertices):
    """The face across edge k (corners k, k + 1) of each face, (M, 3) int64: −1 on a
    boundary edge; −2 − e where three or more faces share the edge, e indexing the
    returned (E, 3) sums of their normals (the pseudo-normal of such an edge)."""
    m = faces.shape[0]
    # edges grouped by their smaller vertex (a counting sort), then matched in-bucket
    first = np.zeros(n_vertices + 1, dtype=np.int64)
    for f in range(m):
        for k in range(3):
            first[min(faces[f, k], faces[f, (k + 1) % 3]) + 1] += 1
    for v in range(n_vertices):
        first[v + 1] += first[v]
    fill = first[:-1].copy()
    slot_other = np.empty(3 * m, dtype=np.int64)
    slot_edge = np.empty(3 * m, dtype=np.int64)  # 3·face + k of the first face seen
    slot_count = np.zeros(3 * m, dtype=np.int64)
    slot_of = np.empty((m, 3), dtype=np.int64)
    neighbour = np.full((m, 3), -1, dtype=np.int64)
    crowded = 0
    for f in range(m):
        for k in range(3):
            a, b = faces[f, k], faces[f, (k + 1) % 3]
            if a > b:
                a, b = b, a
            s = first[a]
            while s < fill[a] and slot_other[s] != b:
                s += 1
            if s == fill[a]:
                slot_other[s] = b
                slot_edge[s] = 3 * f + k
                fill[a] += 1
            elif slot_count[s] == 1:
                g = slot_edge[s]
                neighbour[f, k] = g // 3
                neighbour[g // 3, g % 3] = f
            slot_count[s] += 1
            if slot_count[s] == 3:
                crowded += 1
            slot_of[f, k] = s
    sums = np.zeros((crowded, 3))
    if crowded:
        index = np.full(3 * m, -1, dtype=np.int64)
        e = 0
        for f in range(m):
            for k in range(3):
                s = slot_of[f, k]
                if slot_count[s] < 3:
                    continue
                if index[s] < 0:
                    index[s] = e
                    e += 1
                for c in range(3):
                    sums[index[s], c] += normal[f, c]
                neighbour[f, k] = -2 - index[s]
    return neighbour, sums
