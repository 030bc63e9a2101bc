"""Closest point on a triangle, and which feature of it is nearest (numba).

Local coordinates (world − a mesh origin), float64, metres. Follows Ericson,
*Real-Time Collision Detection* (2005), §5.1.5, with every division guarded; triangles
too thin for a trustworthy plane (sin of the angle at the first corner below 1e-10) are
handled as their three edges. The feature — the face, edge k (corners k, k + 1) or
corner k — tells :mod:`._bvh` which pseudo-normal gives the sign.
"""

from __future__ import annotations

import numpy as np
from numba import njit

#: feature codes returned by :func:`closest_point`
FACE = 0
EDGE0, EDGE1, EDGE2 = 1, 2, 3  # edge k joins corners k and (k + 1) % 3
VERT0, VERT1, VERT2 = 4, 5, 6

_SLIVER = 1e-20


@njit(cache=True, inline="always")
def _seg_param(num: float, den: float) -> float:
    if den <= 0.0:
        return 0.0
    t = num / den
    return min(1.0, max(0.0, t))


@njit(cache=True, nogil=True)
def _closest_on_segment(px, py, pz, ax, ay, az, bx, by, bz):
    ex, ey, ez = bx - ax, by - ay, bz - az
    t = _seg_param((px - ax) * ex + (py - ay) * ey + (pz - az) * ez, ex * ex + ey * ey + ez * ez)
    qx, qy, qz = ax + t * ex, ay + t * ey, az + t * ez
    return (px - qx) ** 2 + (py - qy) ** 2 + (pz - qz) ** 2, qx, qy, qz, t


@njit(cache=True, nogil=True)
def _degenerate(px, py, pz, tri):
    """Closest point on the three edges of a (near-)degenerate triangle."""
    best, feat = np.inf, EDGE0
    bx = by = bz = 0.0
    for k in range(3):
        a, b = 3 * k, 3 * ((k + 1) % 3)
        d2, qx, qy, qz, t = _closest_on_segment(px, py, pz, tri[a], tri[a + 1], tri[a + 2],
                                                tri[b], tri[b + 1], tri[b + 2])
        if d2 < best:
            best, bx, by, bz = d2, qx, qy, qz
            feat = VERT0 + k if t == 0.0 else (VERT0 + (k + 1) % 3 if t == 1.0 else EDGE0 + k)
    return best, bx, by, bz, feat


@njit(cache=True, inline="always")
def closest_point(px, py, pz, tri):
    """(d², qx, qy, qz, feature) of the point of triangle ``tri`` (9,) nearest to p."""
    ax, ay, az = tri[0], tri[1], tri[2]
    abx, aby, abz = tri[3] - ax, tri[4] - ay, tri[5] - az
    acx, acy, acz = tri[6] - ax, tri[7] - ay, tri[8] - az
    # Ericson's region tests assume a proper triangle: send (near-)degenerate ones
    # (|ab × ac|² tiny against |ab|²·|ac|², i.e. sin of the angle at a below 1e-10) to
    # the edge-only routine.
    nx, ny, nz = aby * acz - abz * acy, abz * acx - abx * acz, abx * acy - aby * acx
    if not (nx * nx + ny * ny + nz * nz > _SLIVER * ((abx * abx + aby * aby + abz * abz)
                                                   * (acx * acx + acy * acy + acz * acz))):
        return _degenerate(px, py, pz, tri)
    apx, apy, apz = px - ax, py - ay, pz - az
    d1 = abx * apx + aby * apy + abz * apz
    d2 = acx * apx + acy * apy + acz * apz
    if d1 <= 0.0 and d2 <= 0.0:
        return apx * apx + apy * apy + apz * apz, ax, ay, az, VERT0
    bpx, bpy, bpz = px - tri[3], py - tri[4], pz - tri[5]
    d3 = abx * bpx + aby * bpy + abz * bpz
    d4 = acx * bpx + acy * bpy + acz * bpz
    if d3 >= 0.0 and d4 <= d3:
        return bpx * bpx + bpy * bpy + bpz * bpz, tri[3], tri[4], tri[5], VERT1
    vc = d1 * d4 - d3 * d2
    if vc <= 0.0 and d1 >= 0.0 and d3 <= 0.0:
        v = _seg_param(d1, d1 - d3)
        qx, qy, qz = ax + v * abx, ay + v * aby, az + v * abz
        return (px - qx) ** 2 + (py - qy) ** 2 + (pz - qz) ** 2, qx, qy, qz, EDGE0
    cpx, cpy, cpz = px - tri[6], py - tri[7], pz - tri[8]
    d5 = abx * cpx + aby * cpy + abz * cpz
    d6 = acx * cpx + acy * cpy + acz * cpz
    if d6 >= 0.0 and d5 <= d6:
        return cpx * cpx + cpy * cpy + cpz * cpz, tri[6], tri[7], tri[8], VERT2
    vb = d5 * d2 - d1 * d6
    if vb <= 0.0 and d2 >= 0.0 and d6 <= 0.0:
        w = _seg_param(d2, d2 - d6)
        qx, qy, qz = ax + w * acx, ay + w * acy, az + w * acz
        return (px - qx) ** 2 + (py - qy) ** 2 + (pz - qz) ** 2, qx, qy, qz, EDGE2
    va = d3 * d6 - d5 * d4
    if va <= 0.0 and d4 - d3 >= 0.0 and d5 - d6 >= 0.0:
        w = _seg_param(d4 - d3, (d4 - d3) + (d5 - d6))
        qx = tri[3] + w * (tri[6] - tri[3])
        qy = tri[4] + w * (tri[7] - tri[4])
        qz = tri[5] + w * (tri[8] - tri[5])
        return (px - qx) ** 2 + (py - qy) ** 2 + (pz - qz) ** 2, qx, qy, qz, EDGE1
    den = va + vb + vc  # = |ab × ac|² > 0 here
    v, w = vb / den, vc / den
    qx = ax + abx * v + acx * w
    qy = ay + aby * v + acy * w
    qz = az + abz * v + acz * w
    return (px - qx) ** 2 + (py - qy) ** 2 + (pz - qz) ** 2, qx, qy, qz, FACE
