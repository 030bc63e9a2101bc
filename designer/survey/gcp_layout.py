"""Ground control point layouts, control/check roles and simulated survey error.

Layouts return (N, 2) world XY positions in metres (X east, Y north) inside an area, a
simple polygon as described in :mod:`designer.survey.area`. The true 3-D positions put
each target on the terrain: :func:`true_gcp_xyz` gives Z = the height field's bilinear
height. Random layouts take a ``seed`` and give the same points for the same seed.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from designer.core.heightfield import Heightfield
from designer.errors import DesignerError, ParameterError
from designer.survey import area as _area

CONTROL = "control"
CHECK = "check"

#: density of the densest packing of equal discs in the plane, π/(2√3)
_DISC_PACKING_DENSITY = math.pi / (2.0 * math.sqrt(3.0))
#: candidate points tried in one stratum before the attempt is abandoned
_CANDIDATES_PER_CELL = 256


def manual(xy_m, area=None) -> np.ndarray:
    """User-given positions (N, 2) as a float64 array, checked to lie inside ``area``."""
    xy = np.array(xy_m, dtype=float).reshape(-1, 2)
    if not np.all(np.isfinite(xy)):
        raise DesignerError("a GCP position is not a finite number")
    if area is not None:
        outside = np.flatnonzero(~_area.contains(area, xy))
        if outside.size:
            listed = ", ".join(f"#{i + 1} ({xy[i, 0]:.3f}, {xy[i, 1]:.3f})" for i in outside[:5])
            raise DesignerError(f"{outside.size} GCP(s) lie outside the survey area: {listed}")
    return xy


def grid(nx: int, ny: int, area, margin_m: float = 0.0) -> np.ndarray:
    """A regular nx × ny grid over the area inset by ``margin_m`` (m), row by row from south.

    The grid spans the bounding box of the inset polygon (a single row or column sits
    in the middle); only nodes inside the inset polygon are kept, so a rectangle gives
    all nx·ny points and other shapes may give fewer.
    """
    nx, ny = _count(nx, "nx"), _count(ny, "ny")
    inner = _area.inset(area, margin_m)
    lo, hi = inner.min(axis=0), inner.max(axis=0)
    xs = np.linspace(lo[0], hi[0], nx) if nx > 1 else np.array([(lo[0] + hi[0]) / 2])
    ys = np.linspace(lo[1], hi[1], ny) if ny > 1 else np.array([(lo[1] + hi[1]) / 2])
    X, Y = np.meshgrid(xs, ys)
    xy = np.column_stack([X.ravel(), Y.ravel()])
    xy = xy[_area.contains(inner, xy)]
    if len(xy) == 0:
        raise DesignerError(f"no node of a {nx} x {ny} grid falls inside the area")
    return xy


def perimeter_and_centre(n: int, area, margin_m: float = 0.0) -> np.ndarray:
    """n points: n − 1 on the boundary inset by ``margin_m`` (m), then one in the centre.

    Boundary points go to the inset polygon's vertices first (corners matter most for
    georeferencing); the rest split the longest remaining edge pieces evenly. With fewer
    points than vertices they are spread evenly by arc length from the first vertex.
    The centre is the centroid, or the sampled point farthest from the boundary when
    the centroid of a concave area lies outside it.
    """
    n = _count(n, "n")
    inner = _area.inset(area, margin_m)
    centre = _centre_point(inner)
    m = n - 1
    if m == 0:
        return centre[None, :]
    v = inner - inner[0]
    edges = np.roll(v, -1, axis=0) - v
    lengths = np.hypot(*edges.T)
    if m >= len(v):
        per_edge = np.zeros(len(v), dtype=int)
        for _ in range(m - len(v)):
            per_edge[np.argmax(lengths / (per_edge + 1))] += 1
        pts = []
        for k in range(len(v)):
            t = np.arange(per_edge[k] + 1) / (per_edge[k] + 1)
            pts.append(v[k] + t[:, None] * edges[k])
        boundary = np.concatenate(pts)
    else:
        cumulative = np.concatenate([[0.0], np.cumsum(lengths)])
        s = np.arange(m) * cumulative[-1] / m
        k = np.searchsorted(cumulative, s, side="right") - 1
        t = (s - cumulative[k]) / lengths[k]
        boundary = v[k] + t[:, None] * edges[k]
    return np.vstack([boundary + inner[0], centre])


def random_stratified(
    n: int, area, min_spacing_m: float, seed: int, max_attempts: int = 20
) -> np.ndarray:
    """n random points inside the area, one per stratum, at least ``min_spacing_m`` apart.

    The area's bounding box is cut into square cells of side √(area / n) (shrunk until
    at least n cells touch the polygon); n of those cells are drawn with probability
    proportional to the share of the cell inside the polygon, and one uniform point is
    drawn in each, rejecting candidates closer than the spacing to earlier points. If
    that fails ``max_attempts`` times, points are thrown at the whole area instead
    (random sequential placement). Raises DesignerError when n points at that spacing
    cannot fit (a perfect disc packing is the bound) or were not found.
    """
    n = _count(n, "n")
    if not (math.isfinite(min_spacing_m) and min_spacing_m >= 0):
        raise ParameterError(f"min_spacing_m = {min_spacing_m} must be a distance >= 0 m",
                             name="min_spacing_m", value=min_spacing_m, unit="m",
                             must="at least 0 m")
    poly = _area.as_polygon(area)
    origin = poly[0]
    local = poly - origin
    size_m2 = _area.polygon_area_m2(local)
    perimeter_m = float(np.hypot(*(np.roll(local, -1, axis=0) - local).T).sum())
    capacity = _packing_capacity(size_m2, perimeter_m, min_spacing_m)
    if n > capacity:
        raise DesignerError(
            f"{n} GCPs cannot be {min_spacing_m:g} m apart inside an area of "
            f"{size_m2:.0f} m²: even a perfect packing fits at most {capacity}; "
            f"lower the number of GCPs or the minimum spacing")
    rng = np.random.default_rng(seed)
    for _ in range(max_attempts):
        pts = _stratified_attempt(n, local, size_m2, min_spacing_m, rng)
        if pts is not None:
            return pts + origin
    pts = _sequential_attempt(n, local, min_spacing_m, rng)
    if pts is not None:
        return pts + origin
    raise DesignerError(
        f"could not place {n} GCPs at least {min_spacing_m:g} m apart inside an area of "
        f"{size_m2:.0f} m² (a perfect packing fits at most {capacity}, random placement "
        f"about half of that); lower the number of GCPs or the minimum spacing")


def assign_roles(
    n: int,
    n_check: int,
    seed: int | None = None,
    pattern: str | Sequence[str] | None = None,
) -> np.ndarray:
    """Roles (n,) of GCPs, each ``"control"`` or ``"check"``; exactly n_check checks.

    Give either ``seed`` (the checks are a seeded random choice) or ``pattern``:
    ``"interleaved"`` (checks spread evenly through the list, at indices
    ⌊(k + ½)·n / n_check⌋) or an explicit sequence of n roles, which is validated.
    """
    n = _count(n, "n")
    if isinstance(n_check, bool) or not isinstance(n_check, int | np.integer):
        raise ParameterError(f"n_check = {n_check!r} must be a whole number",
                             name="n_check", value=n_check, must="a whole number")
    if not 0 <= n_check <= n:
        raise ParameterError(f"n_check = {n_check} must be between 0 and the {n} GCPs",
                             name="n_check", value=n_check, must=f"from 0 to the {n} GCPs")
    if (seed is None) == (pattern is None):
        raise DesignerError("give either a seed or a pattern to assign GCP roles, not both")
    roles = np.full(n, CONTROL, dtype="<U7")
    if pattern is None:
        roles[np.random.default_rng(seed).choice(n, size=n_check, replace=False)] = CHECK
    elif isinstance(pattern, str):
        if pattern != "interleaved":
            raise DesignerError(
                f"unknown role pattern {pattern!r}; use 'interleaved' or a list of roles")
        if n_check:
            roles[((np.arange(n_check) + 0.5) * n / n_check).astype(int)] = CHECK
    else:
        given = [str(r) for r in pattern]
        bad = sorted({r for r in given if r not in (CONTROL, CHECK)})
        if len(given) != n or bad:
            raise DesignerError(
                f"a role pattern must list {n} roles, each 'control' or 'check' "
                f"(got {len(given)} roles{', unknown ' + repr(bad) if bad else ''})")
        if given.count(CHECK) != n_check:
            raise DesignerError(
                f"the role pattern has {given.count(CHECK)} check points, not {n_check}")
        roles[:] = given
    return roles


def true_gcp_xyz(xy_m, heightfield: Heightfield) -> np.ndarray:
    """True target positions (N, 3): the given XY with Z = terrain height (bilinear)."""
    xy = np.asarray(xy_m, dtype=float).reshape(-1, 2)
    z = heightfield.height_at(xy[:, 0], xy[:, 1])
    outside = np.flatnonzero(~np.isfinite(z))
    if outside.size:
        raise DesignerError(
            f"{outside.size} GCP(s) lie outside the terrain, e.g. #{outside[0] + 1} at "
            f"({xy[outside[0], 0]:.3f}, {xy[outside[0], 1]:.3f})")
    return np.column_stack([xy, z])


def simulate_survey_error(
    true_xyz_m, sigma_h_m: float, sigma_v_m: float, seed: int
) -> np.ndarray:
    """Surveyed coordinates (N, 3): true + Gaussian error, seeded.

    X and Y each get independent N(0, sigma_h_m²) errors (so the horizontal radial RMS
    is √2·sigma_h_m); Z gets N(0, sigma_v_m²). The input is not modified.
    """
    xyz = np.asarray(true_xyz_m, dtype=float).reshape(-1, 3)
    for name, s in (("sigma_h_m", sigma_h_m), ("sigma_v_m", sigma_v_m)):
        if not (math.isfinite(s) and s >= 0):
            raise DesignerError(f"{name} = {s} must be a standard deviation >= 0 m")
    noise = np.random.default_rng(seed).standard_normal(xyz.shape)
    return xyz + noise * np.array([sigma_h_m, sigma_h_m, sigma_v_m])


# ----------------------------------------------------------------------------- helpers
def _count(value, name: str) -> int:
    if isinstance(value, bool) or not isinstance(value, int | np.integer) or value < 1:
        raise DesignerError(f"{name} = {value!r} must be a whole number >= 1")
    return int(value)


def _packing_capacity(size_m2: float, perimeter_m: float, spacing_m: float) -> int:
    """Upper bound on points ≥ spacing apart: discs of radius spacing/2 around them do
    not overlap and lie in the area grown by that radius (area + perimeter·r + π·r²)."""
    if spacing_m == 0:
        return 2**62
    r = spacing_m / 2.0
    grown = size_m2 + perimeter_m * r + math.pi * r * r
    return int(_DISC_PACKING_DENSITY * grown / (math.pi * r * r))


def _centre_point(poly: np.ndarray) -> np.ndarray:
    c = _area.polygon_centroid(poly)
    if _area.contains(poly, c[None, :])[0]:
        return c
    lo, hi = poly.min(axis=0), poly.max(axis=0)
    X, Y = np.meshgrid(np.linspace(lo[0], hi[0], 101), np.linspace(lo[1], hi[1], 101))
    xy = np.column_stack([X.ravel(), Y.ravel()])
    xy = xy[_area.contains(poly, xy)]
    return xy[np.argmax(_area.distance_to_boundary_m(poly, xy))]


def _far_enough(candidates: np.ndarray, placed: list[np.ndarray], spacing_m: float) -> np.ndarray:
    if not placed or spacing_m == 0:
        return np.ones(len(candidates), dtype=bool)
    P = np.asarray(placed)
    d2 = ((candidates[:, None, :] - P[None, :, :]) ** 2).sum(axis=-1)
    return np.all(d2 >= spacing_m * spacing_m, axis=1)


def _stratified_attempt(n, poly, size_m2, spacing_m, rng) -> np.ndarray | None:
    lo, hi = poly.min(axis=0), poly.max(axis=0)
    cell = math.sqrt(size_m2 / n)
    while True:
        nx = max(1, math.ceil((hi[0] - lo[0]) / cell))
        ny = max(1, math.ceil((hi[1] - lo[1]) / cell))
        # share of each cell inside the polygon, from an 8 × 8 sub-sample
        sub = (np.arange(8) + 0.5) / 8
        jx, iy, sx, sy = np.meshgrid(np.arange(nx), np.arange(ny), sub, sub, indexing="ij")
        xy = np.column_stack([lo[0] + (jx + sx).ravel() * cell, lo[1] + (iy + sy).ravel() * cell])
        share = _area.contains(poly, xy).reshape(nx, ny, 64).mean(axis=2).ravel()
        if np.count_nonzero(share) >= n:
            break
        cell *= 0.9
    cells = rng.choice(share.size, size=n, replace=False, p=share / share.sum())
    placed: list[np.ndarray] = []
    for c in cells:
        jx, iy = divmod(int(c), ny)
        cand = lo + (np.array([jx, iy]) + rng.random((_CANDIDATES_PER_CELL, 2))) * cell
        ok = _area.contains(poly, cand)
        ok[ok] = _far_enough(cand[ok], placed, spacing_m)
        if not ok.any():
            return None
        placed.append(cand[np.argmax(ok)])
    return np.asarray(placed)


def _sequential_attempt(n, poly, spacing_m, rng, batches: int = 400,
                        patience: int = 20) -> np.ndarray | None:
    """Random sequential placement over the whole area; gives up after ``patience``
    batches in a row add nothing (the area is saturated at that spacing)."""
    lo, hi = poly.min(axis=0), poly.max(axis=0)
    placed: list[np.ndarray] = []
    idle = 0
    for _ in range(batches):
        cand = lo + rng.random((max(64, 4 * n), 2)) * (hi - lo)
        cand = cand[_area.contains(poly, cand)]
        cand = cand[_far_enough(cand, placed, spacing_m)]
        before = len(placed)
        for p in cand:
            if _far_enough(p[None, :], placed[before:], spacing_m)[0]:
                placed.append(p)
                if len(placed) == n:
                    return np.asarray(placed)
        idle = idle + 1 if len(placed) == before else 0
        if idle >= patience:
            return None
    return None
