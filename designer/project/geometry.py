"""Plane geometry for the flight-plan area: signed area and simple-polygon test (X/Y, m)."""

from __future__ import annotations

import itertools
from collections.abc import Sequence


def polygon_area(vertices: Sequence[tuple[float, float]]) -> float:
    """Signed area (m²) by the shoelace formula; positive when counter-clockwise.

    Computed relative to the first vertex so UTM-sized coordinates lose no precision.
    """
    if len(vertices) < 3:
        return 0.0
    x0, y0 = vertices[0]
    total = 0.0
    for (xa, ya), (xb, yb) in itertools.pairwise(vertices[1:]):
        total += (xa - x0) * (yb - y0) - (xb - x0) * (ya - y0)
    return total / 2.0


def polygon_is_degenerate(vertices: Sequence[tuple[float, float]], tol_m2: float = 1e-6) -> bool:
    """True if every vertex lies on one line (within ``tol_m2`` of doubled triangle area)."""
    if len(vertices) < 3:
        return True
    x0, y0 = vertices[0]
    pts = [(x - x0, y - y0) for x, y in vertices]
    far = max(pts, key=lambda p: p[0] * p[0] + p[1] * p[1])
    return all(abs(_orient((0.0, 0.0), far, p)) <= tol_m2 * max(1.0, abs(far[0]) + abs(far[1]))
               for p in pts)


def _orient(a, b, c) -> float:
    return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])


def _on_segment(a, b, p) -> bool:
    return (min(a[0], b[0]) <= p[0] <= max(a[0], b[0])
            and min(a[1], b[1]) <= p[1] <= max(a[1], b[1]))


def _segments_touch(a, b, c, d) -> bool:
    o1, o2, o3, o4 = _orient(a, b, c), _orient(a, b, d), _orient(c, d, a), _orient(c, d, b)
    if ((o1 > 0 > o2) or (o1 < 0 < o2)) and ((o3 > 0 > o4) or (o3 < 0 < o4)):
        return True
    return ((o1 == 0 and _on_segment(a, b, c)) or (o2 == 0 and _on_segment(a, b, d))
            or (o3 == 0 and _on_segment(c, d, a)) or (o4 == 0 and _on_segment(c, d, b)))


def polygon_self_intersection(
    vertices: Sequence[tuple[float, float]],
) -> tuple[int, int] | None:
    """Indices (i, j) of the first two non-adjacent edges that touch, or None if simple.

    Edge i runs from vertex i to vertex i + 1 (the last edge closes the ring). O(n²):
    flight areas have tens of vertices.
    """
    n = len(vertices)
    x0, y0 = vertices[0] if n else (0.0, 0.0)
    pts = [(x - x0, y - y0) for x, y in vertices]
    for i in range(n):
        a, b = pts[i], pts[(i + 1) % n]
        for j in range(i + 1, n):
            if j == i + 1 or (i == 0 and j == n - 1):
                continue  # adjacent edges share a vertex
            if _segments_touch(a, b, pts[j], pts[(j + 1) % n]):
                return i, j
    return None


def point_in_polygon(x: float, y: float, vertices: Sequence[tuple[float, float]]) -> bool:
    """True if (x, y) lies inside the polygon ``vertices`` (even-odd rule; either
    orientation; relative to the first vertex for UTM-sized coordinates)."""
    if len(vertices) < 3:
        return False
    x0, y0 = vertices[0]
    px, py = x - x0, y - y0
    pts = [(vx - x0, vy - y0) for vx, vy in vertices]
    inside = False
    for (xa, ya), (xb, yb) in zip(pts, pts[1:] + pts[:1], strict=True):
        if (ya > py) != (yb > py) and px < xa + (py - ya) * (xb - xa) / (yb - ya):
            inside = not inside
    return inside


def rectangle_corner_error_deg(vertices: Sequence[tuple[float, float]]) -> float:
    """The largest departure (deg) of a corner of the quadrilateral ``vertices`` from a
    right angle; infinite unless there are exactly four vertices."""
    import math

    if len(vertices) != 4:
        return math.inf
    worst = 0.0
    for i in range(4):
        (xa, ya), (xb, yb), (xc, yc) = vertices[i - 1], vertices[i], vertices[(i + 1) % 4]
        u, v = (xa - xb, ya - yb), (xc - xb, yc - yb)
        nu, nv = math.hypot(*u), math.hypot(*v)
        if nu == 0 or nv == 0:
            return math.inf
        cos = max(-1.0, min(1.0, (u[0] * v[0] + u[1] * v[1]) / (nu * nv)))
        worst = max(worst, abs(math.degrees(math.acos(cos)) - 90.0))
    return worst
