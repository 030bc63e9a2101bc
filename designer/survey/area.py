"""Survey areas: simple polygons in the world XY plane, and the operations used on them.

An *area* is a (K, 2) array of vertices, X = easting and Y = northing in metres (world
frame), K ≥ 3, in either winding order, simple (no two edges cross). A repeated first
vertex at the end is dropped. UTM-sized coordinates are fine: every function here
subtracts the first vertex before doing arithmetic, so nothing is lost to float64.

Use :func:`rectangle` or :func:`heightfield_area` for axis-aligned rectangles.
"""

from __future__ import annotations

import numpy as np

from designer.core.heightfield import Heightfield
from designer.errors import DesignerError, ParameterError
from designer.project.validate_shared import plain_number


def rectangle(x_min_m: float, y_min_m: float, x_max_m: float, y_max_m: float) -> np.ndarray:
    """The axis-aligned rectangle [x_min, x_max] × [y_min, y_max] as a (4, 2) area (CCW)."""
    if not (x_max_m > x_min_m and y_max_m > y_min_m):
        raise DesignerError(
            f"rectangle needs x_min < x_max and y_min < y_max, got x {x_min_m}..{x_max_m}, "
            f"y {y_min_m}..{y_max_m}")
    return as_polygon([[x_min_m, y_min_m], [x_max_m, y_min_m],
                       [x_max_m, y_max_m], [x_min_m, y_max_m]])


def heightfield_area(heightfield: Heightfield) -> np.ndarray:
    """The whole extent of a height field as a (4, 2) area."""
    x0, x1, y0, y1 = heightfield.extent_m
    return rectangle(x0, y0, x1, y1)


def as_polygon(area) -> np.ndarray:
    """Validate an area and return it as a read-only float64 (K, 2) array.

    Raises DesignerError for fewer than 3 distinct vertices, non-finite values, zero
    area or crossing edges.
    """
    poly = np.array(area, dtype=float)
    if poly.ndim != 2 or poly.shape[1] != 2:
        raise DesignerError(f"an area must be a list of (x, y) vertices, got shape {poly.shape}")
    if not np.all(np.isfinite(poly)):
        raise DesignerError("an area has a non-finite vertex coordinate")
    if len(poly) > 1 and np.array_equal(poly[0], poly[-1]):
        poly = poly[:-1]
    keep = np.any(poly != np.roll(poly, 1, axis=0), axis=1)  # drop repeated vertices
    poly = poly[keep] if len(poly) > 1 else poly
    if len(poly) < 3:
        raise DesignerError(f"an area needs at least 3 distinct vertices, got {len(poly)}")
    local = poly - poly[0]
    crossing = _first_crossing(local)
    if crossing is not None:
        i, j = crossing
        n = len(poly)  # vertices numbered from 1, as a table's rows and the XML's order
        raise DesignerError(
            f"an area's edges cross (vertex {i + 1} to vertex {(i + 1) % n + 1} meets vertex "
            f"{j + 1} to vertex {(j + 1) % n + 1}); give the vertices in order around the "
            "boundary")
    if abs(_signed_area(local)) <= 1e-12 * float(np.ptp(local, axis=0).max()) ** 2:
        raise DesignerError("an area has zero size (its vertices are collinear)")
    poly.flags.writeable = False
    return poly


def polygon_area_m2(area) -> float:
    """Area enclosed by the polygon (m², positive)."""
    poly = as_polygon(area)
    return abs(_signed_area(poly - poly[0]))


def polygon_centroid(area) -> np.ndarray:
    """Centroid (2,) of the enclosed region (world XY, metres)."""
    poly = as_polygon(area)
    p = poly - poly[0]
    q = np.roll(p, -1, axis=0)
    cross = p[:, 0] * q[:, 1] - q[:, 0] * p[:, 1]
    a = cross.sum() / 2.0
    c = ((p + q) * cross[:, None]).sum(axis=0) / (6.0 * a)
    return poly[0] + c


def contains(area, xy_m) -> np.ndarray:
    """True where points (N, 2) lie inside the polygon or on its boundary (even–odd rule)."""
    poly = as_polygon(area)
    p = np.asarray(xy_m, dtype=float).reshape(-1, 2) - poly[0]
    v = poly - poly[0]
    inside = np.zeros(len(p), dtype=bool)
    x, y = p[:, 0], p[:, 1]
    for a, b in zip(v, np.roll(v, -1, axis=0), strict=True):
        straddles = (a[1] > y) != (b[1] > y)
        with np.errstate(divide="ignore", invalid="ignore"):
            x_cross = a[0] + (y - a[1]) * (b[0] - a[0]) / (b[1] - a[1])
        inside ^= straddles & (x < x_cross)
    # the boundary's distance only where the crossings say outside: over a terrain's
    # nodes (millions, most inside the area) it was 90 % of the stations job
    outside = np.flatnonzero(~inside)
    if len(outside):
        inside[outside] = distance_to_boundary_m(poly, p[outside] + poly[0]) <= 1e-9
    return inside


def contains_grid(area, x_m, y_m) -> np.ndarray:
    """:func:`contains` of the grid's nodes (x_m[j], y_m[i]) as an (ny, nx) array: the same
    answers (the same arithmetic), with each edge's crossing found once per row instead
    of once per node (over a 5,000-image block's terrain, 4 M nodes)."""
    poly = as_polygon(area)
    v = poly - poly[0]
    x = np.asarray(x_m, dtype=float).ravel() - poly[0][0]
    y = np.asarray(y_m, dtype=float).ravel() - poly[0][1]
    inside = np.zeros((len(y), len(x)), dtype=bool)
    for a, b in zip(v, np.roll(v, -1, axis=0), strict=True):
        rows = np.flatnonzero((a[1] > y) != (b[1] > y))
        x_cross = a[0] + (y[rows] - a[1]) * (b[0] - a[0]) / (b[1] - a[1])
        inside[rows] ^= x[None, :] < x_cross[:, None]
    i, j = np.nonzero(~inside)
    if len(i):
        p = np.column_stack([x[j], y[i]])
        inside[i, j] = distance_to_boundary_m(poly, p + poly[0]) <= 1e-9
    return inside


def distance_to_boundary_m(area, xy_m) -> np.ndarray:
    """Distance (N,) in metres from points (N, 2) to the nearest polygon edge."""
    poly = as_polygon(area)
    p = np.asarray(xy_m, dtype=float).reshape(-1, 2) - poly[0]
    v = poly - poly[0]
    best = np.full(len(p), np.inf)
    for a, b in zip(v, np.roll(v, -1, axis=0), strict=True):
        ab = b - a
        t = np.clip(((p - a) @ ab) / float(ab @ ab), 0.0, 1.0)
        d = np.hypot(*(p - a - t[:, None] * ab).T)
        np.minimum(best, d, out=best)
    return best


def inset(area, margin_m: float) -> np.ndarray:
    """The polygon moved inwards by ``margin_m`` ≥ 0 (each edge offset, mitred corners).

    Raises DesignerError when the margin is too large for the area (the result would
    collapse, turn inside out, or come closer than the margin to another edge).
    """
    poly = as_polygon(area)
    if not margin_m >= 0:
        raise ParameterError(f"margin_m = {margin_m} must be >= 0 m", name="margin_m",
                             value=margin_m, unit="m", must="at least 0 m")
    if margin_m == 0:
        return poly
    origin = poly[0]
    v = poly - origin
    if _signed_area(v) < 0:
        v = v[::-1]
    edge = np.roll(v, -1, axis=0) - v
    normal = np.column_stack([-edge[:, 1], edge[:, 0]]) / np.hypot(*edge.T)[:, None]
    start = v + margin_m * normal  # offset edge k: start[k] + s·edge[k]
    prev = np.roll(np.arange(len(v)), 1)
    # vertex k = intersection of offset edges k-1 and k
    d1, d2 = edge[prev], edge
    p1, p2 = start[prev], start
    denom = d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]
    with np.errstate(divide="ignore", invalid="ignore"):
        s = ((p2 - p1)[:, 0] * d2[:, 1] - (p2 - p1)[:, 1] * d2[:, 0]) / denom
    out = np.where(np.abs(denom)[:, None] > 1e-12, p1 + s[:, None] * d1, p2)
    ok = (
        np.all(np.isfinite(out))
        and _signed_area(out) > 0
        and _first_crossing(out) is None
        and np.all(distance_to_boundary_m(v, out) >= margin_m * (1 - 1e-9))
        and np.all(contains(v, out))
    )
    if not ok:
        raise DesignerError(
            f"a margin of {plain_number(margin_m)} m leaves nothing of this area; use a "
            "smaller margin")
    return as_polygon(out + origin)


def along_across_m(xy_m, origin_xy_m, azimuth_deg: float) -> tuple[np.ndarray, np.ndarray]:
    """Coordinates (along, across) of points in a frame rotated to an azimuth.

    ``along`` is measured towards the azimuth (degrees clockwise from north), ``across``
    to its right, both from ``origin_xy_m``.
    """
    d, r = azimuth_axes(azimuth_deg)
    p = np.asarray(xy_m, dtype=float).reshape(-1, 2) - np.asarray(origin_xy_m, dtype=float)
    return p @ d, p @ r


def azimuth_axes(azimuth_deg: float) -> tuple[np.ndarray, np.ndarray]:
    """Unit vectors (forward, right) in world XY for an azimuth clockwise from north."""
    a = np.radians(azimuth_deg)
    return np.array([np.sin(a), np.cos(a)]), np.array([np.cos(a), -np.sin(a)])


# ----------------------------------------------------------------------------- helpers
def _signed_area(v: np.ndarray) -> float:
    q = np.roll(v, -1, axis=0)
    return float((v[:, 0] * q[:, 1] - q[:, 0] * v[:, 1]).sum() / 2.0)


def _first_crossing(v: np.ndarray) -> tuple[int, int] | None:
    """Indices of the first pair of non-adjacent edges that intersect, or None."""
    k = len(v)
    if k < 4:
        return None
    a, b = v, np.roll(v, -1, axis=0)
    i, j = np.triu_indices(k, 2)
    keep = ~((i == 0) & (j == k - 1))  # the first and last edges share a vertex
    i, j = i[keep], j[keep]

    def orient(p, q, r):
        return np.sign((q[:, 0] - p[:, 0]) * (r[:, 1] - p[:, 1])
                       - (q[:, 1] - p[:, 1]) * (r[:, 0] - p[:, 0]))

    o1, o2 = orient(a[i], b[i], a[j]), orient(a[i], b[i], b[j])
    o3, o4 = orient(a[j], b[j], a[i]), orient(a[j], b[j], b[i])
    proper = (o1 * o2 < 0) & (o3 * o4 < 0)
    touching = (o1 == 0) | (o2 == 0) | (o3 == 0) | (o4 == 0)
    if touching.any():  # collinear or touching: check the bounding boxes overlap
        lo_i, hi_i = np.minimum(a[i], b[i]), np.maximum(a[i], b[i])
        lo_j, hi_j = np.minimum(a[j], b[j]), np.maximum(a[j], b[j])
        boxes = np.all((lo_i <= hi_j) & (lo_j <= hi_i), axis=1)
        on_seg = np.zeros_like(touching)
        for o, (p, q, r) in ((o1, (a[i], b[i], a[j])), (o2, (a[i], b[i], b[j])),
                             (o3, (a[j], b[j], a[i])), (o4, (a[j], b[j], b[i]))):
            lo, hi = np.minimum(p, q), np.maximum(p, q)
            on_seg |= (o == 0) & np.all((r >= lo) & (r <= hi), axis=1)
        proper |= touching & boxes & on_seg
    hits = np.flatnonzero(proper)
    return None if hits.size == 0 else (int(i[hits[0]]), int(j[hits[0]]))
