"""Bounding-volume hierarchy over triangles and exact nearest-triangle queries (numba).

Local coordinates (world − a mesh origin), float64, metres. The hierarchy is built over
triangles sorted by the Morton code of their centroids (one grid scale for all axes);
a node splits its range where the highest differing Morton bit changes (Karras 2012),
or in the middle when all codes are equal. Queries descend nearest child first and
prune every box (and every triangle's own box) not closer than the best distance so
far, so the result is the exact nearest triangle. Points are processed in Morton
order, in blocks run in parallel; within a block each point starts from the previous
point's triangle as an upper bound.
"""

from __future__ import annotations

import numpy as np
from numba import njit, prange

from designer.evaluate._closest import EDGE0, FACE, VERT0, closest_point

LEAF_SIZE = 8
_STACK = 256  # deeper than any tree built here: <= 63 bit splits + log2(M) middle splits
_BLOCK = 512  # points per parallel work item; consecutive points warm-start each other


@njit(cache=True, nogil=True)
def _split(codes, start, end):
    first, last = codes[start], codes[end - 1]
    if first == last:
        return (start + end) >> 1
    diff = first ^ last
    bit = np.uint64(63)
    while (diff >> bit) == np.uint64(0):
        bit -= np.uint64(1)
    # first index in [start, end) whose code has that bit set (codes are sorted)
    lo, hi = start, end - 1
    while lo < hi:
        mid = (lo + hi) >> 1
        if (codes[mid] >> bit) & np.uint64(1):
            hi = mid
        else:
            lo = mid + 1
    return lo


@njit(cache=True, nogil=True)
def build_bvh(codes, tri):
    """Nodes of a BVH over triangles ``tri`` (M, 9) sorted by Morton ``codes`` (M,).

    Returns ``box`` (K, 6) = (x, y, z) min then max of each node, and ``link`` (K, 2):
    an inner node has link = (first child, 0) with its two children stored side by side;
    a leaf has link = (first triangle, number of triangles). Node 0 is the root and
    parents precede their children, so boxes are computed in one backward pass.
    """
    m = codes.shape[0]
    cap = max(1, 2 * m - 1)
    link = np.zeros((cap, 2), dtype=np.int64)
    is_leaf = np.zeros(cap, dtype=np.bool_)
    span = np.empty((cap, 2), dtype=np.int64)  # (start, count) of every node
    stack = np.empty(_STACK, dtype=np.int64)
    span[0, 0], span[0, 1] = 0, m
    stack[0] = 0
    n_nodes, sp = 1, 1
    while sp > 0:
        sp -= 1
        node = stack[sp]
        s, c = span[node, 0], span[node, 1]
        if c <= LEAF_SIZE:
            is_leaf[node] = True
            link[node, 0], link[node, 1] = s, c
            continue
        cut = _split(codes, s, s + c)
        link[node, 0] = n_nodes
        span[n_nodes, 0], span[n_nodes, 1] = s, cut - s
        span[n_nodes + 1, 0], span[n_nodes + 1, 1] = cut, s + c - cut
        stack[sp], stack[sp + 1] = n_nodes, n_nodes + 1
        sp += 2
        n_nodes += 2
    box = np.empty((n_nodes, 6))
    for node in range(n_nodes - 1, -1, -1):
        if is_leaf[node]:
            for a in range(3):
                mn, mx = np.inf, -np.inf
                for t in range(span[node, 0], span[node, 0] + span[node, 1]):
                    for corner in range(3):
                        v = tri[t, 3 * corner + a]
                        mn = min(mn, v)
                        mx = max(mx, v)
                box[node, a], box[node, 3 + a] = mn, mx
        else:
            c = link[node, 0]
            for a in range(3):
                box[node, a] = min(box[c, a], box[c + 1, a])
                box[node, 3 + a] = max(box[c, 3 + a], box[c + 1, 3 + a])
    return box, link[:n_nodes].copy()


@njit(cache=True, nogil=True, parallel=True)
def morton_codes(xyz, lo, scale):
    """63-bit Morton codes (M,) of points ``xyz`` (M, 3) on a 2²¹ grid from ``lo``."""
    n = xyz.shape[0]
    out = np.empty(n, dtype=np.uint64)
    top = float((1 << 21) - 1)
    for i in prange(n):
        code = np.uint64(0)
        for a in range(3):
            q = (xyz[i, a] - lo[a]) * scale[a]
            q = min(top, max(0.0, q))
            v = np.uint64(q)
            # spread the 21 bits of v three apart
            v = (v | (v << np.uint64(32))) & np.uint64(0x1F00000000FFFF)
            v = (v | (v << np.uint64(16))) & np.uint64(0x1F0000FF0000FF)
            v = (v | (v << np.uint64(8))) & np.uint64(0x100F00F00F00F00F)
            v = (v | (v << np.uint64(4))) & np.uint64(0x10C30C30C30C30C3)
            v = (v | (v << np.uint64(2))) & np.uint64(0x1249249249249249)
            code |= v << np.uint64(a)
        out[i] = code
    return out


@njit(cache=True, nogil=True, parallel=True)
def centroid_codes(local, faces, lo, scale):
    """Morton codes (M,) of the centroids of triangles ``faces`` over vertices ``local``."""
    m = faces.shape[0]
    centroid = np.empty((m, 3))
    for f in prange(m):
        for a in range(3):
            centroid[f, a] = (local[faces[f, 0], a] + local[faces[f, 1], a]
                              + local[faces[f, 2], a]) / 3.0
    return morton_codes(centroid, lo, scale)


@njit(cache=True, nogil=True)
def radix_argsort(codes):
    """Stable argsort of uint64 ``codes`` (LSD radix, 16-bit digits; passes over digits
    that are equal for every code are skipped) — a few times faster than np.argsort."""
    n = codes.shape[0]
    order = np.arange(n)
    tmp = np.empty(n, dtype=np.int64)
    count = np.empty((1 << 16) + 1, dtype=np.int64)
    for shift in range(0, 64, 16):
        s = np.uint64(shift)
        count[:] = 0
        for i in range(n):
            count[((codes[i] >> s) & np.uint64(0xFFFF)) + 1] += 1
        if count.max() == n:
            continue  # this digit is the same for every code
        for d in range(1 << 16):
            count[d + 1] += count[d]
        for i in range(n):
            j = order[i]
            digit = (codes[j] >> s) & np.uint64(0xFFFF)
            tmp[count[digit]] = j
            count[digit] += 1
        order, tmp = tmp, order
    return order


# --------------------------------------------------------------------------- queries
@njit(cache=True, inline="always")
def _box_d2(px, py, pz, box, node):
    dx = max(box[node, 0] - px, 0.0, px - box[node, 3])
    dy = max(box[node, 1] - py, 0.0, py - box[node, 4])
    dz = max(box[node, 2] - pz, 0.0, pz - box[node, 5])
    return dx * dx + dy * dy + dz * dz


@njit(cache=True, inline="always")
def _tri_box_d2(px, py, pz, t):
    dx = max(min(t[0], t[3], t[6]) - px, 0.0, px - max(t[0], t[3], t[6]))
    dy = max(min(t[1], t[4], t[7]) - py, 0.0, py - max(t[1], t[4], t[7]))
    dz = max(min(t[2], t[5], t[8]) - pz, 0.0, pz - max(t[2], t[5], t[8]))
    return dx * dx + dy * dy + dz * dz


@njit(cache=True, nogil=True)
def _nearest(px, py, pz, tri, box, link, best, best_t, stack, stack_d):
    """Index of the triangle nearest to p among those closer than sqrt(best) (or best_t)."""
    stack[0] = 0
    stack_d[0] = _box_d2(px, py, pz, box, 0)
    sp = 1
    while sp > 0:
        sp -= 1
        if stack_d[sp] >= best:
            continue
        node = stack[sp]
        first, n_tri = link[node, 0], link[node, 1]
        if n_tri > 0:
            for t in range(first, first + n_tri):
                if _tri_box_d2(px, py, pz, tri[t]) >= best:
                    continue  # cheaper than the exact test, and rejects most of a leaf
                d2 = closest_point(px, py, pz, tri[t])[0]
                if d2 < best:
                    best, best_t = d2, t
            continue
        near, far = first, first + 1
        d_near = _box_d2(px, py, pz, box, near)
        d_far = _box_d2(px, py, pz, box, far)
        if d_near > d_far:  # push the farther child first: the nearer one is searched next
            near, far, d_near, d_far = far, near, d_far, d_near
        if d_far < best:
            stack[sp], stack_d[sp] = far, d_far
            sp += 1
        if d_near < best:
            stack[sp], stack_d[sp] = near, d_near
            sp += 1
    return best_t


@njit(cache=True, nogil=True, parallel=True)
def query(points, tri, box, link, limit_d2, normals_face, neighbours, crowded, normals_vert,
          corner_vertex):
    """Signed distance (N,) and nearest triangle (N,) of each local point (N, 3).

    Triangles and their pseudo-normals are in BVH order. ``limit_d2`` bounds the
    search: points farther than sqrt(limit_d2) get NaN and triangle −1.
    """
    n = points.shape[0]
    dist = np.empty(n)
    nearest = np.empty(n, dtype=np.int64)
    n_blocks = (n + _BLOCK - 1) // _BLOCK
    for b in prange(n_blocks):
        stack = np.empty(_STACK, dtype=np.int64)
        stack_d = np.empty(_STACK)
        warm = -1
        for i in range(b * _BLOCK, min(n, (b + 1) * _BLOCK)):
            px, py, pz = points[i, 0], points[i, 1], points[i, 2]
            best = limit_d2
            if warm >= 0:  # the previous point's triangle bounds this one's distance
                best = min(best, closest_point(px, py, pz, tri[warm])[0])
            t = _nearest(px, py, pz, tri, box, link, np.nextafter(best, np.inf),
                         warm if best < limit_d2 else -1, stack, stack_d)
            nearest[i] = t
            if t < 0:
                dist[i] = np.nan
                continue
            warm = t
            dist[i] = _signed(px, py, pz, tri[t], t, normals_face, neighbours, crowded,
                              normals_vert, corner_vertex)
    return dist, nearest


@njit(cache=True, nogil=True)
def _signed(px, py, pz, tri_t, t, normals_face, neighbours, crowded, normals_vert,
            corner_vertex):
    d2, qx, qy, qz, feat = closest_point(px, py, pz, tri_t)
    if feat == FACE:
        # exact form in the face's Voronoi region: distance along the unit normal
        return ((px - tri_t[0]) * normals_face[t, 0] + (py - tri_t[1]) * normals_face[t, 1]
                + (pz - tri_t[2]) * normals_face[t, 2])
    if feat >= VERT0:
        v = corner_vertex[t, feat - VERT0]
        nx, ny, nz = normals_vert[v, 0], normals_vert[v, 1], normals_vert[v, 2]
    else:
        g = neighbours[t, feat - EDGE0]
        nx, ny, nz = normals_face[t, 0], normals_face[t, 1], normals_face[t, 2]
        if g >= 0:
            nx, ny, nz = nx + normals_face[g, 0], ny + normals_face[g, 1], nz + normals_face[g, 2]
        elif g <= -2:
            nx, ny, nz = crowded[-2 - g, 0], crowded[-2 - g, 1], crowded[-2 - g, 2]
    d = np.sqrt(d2)
    s = (px - qx) * nx + (py - qy) * ny + (pz - qz) * nz
    return -d if s < 0.0 else d
