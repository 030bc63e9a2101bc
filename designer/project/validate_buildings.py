"""Semantic checks of the scene's buildings (docs/world.md, Buildings and structures)."""

from __future__ import annotations

import math
from pathlib import Path

from designer.project import model as m
from designer.project.declare import declared_field
from designer.project.files import mesh_problem, resolve
from designer.project.geometry import (
    point_in_polygon,
    polygon_area,
    polygon_is_degenerate,
    polygon_self_intersection,
    rectangle_corner_error_deg,
)
from designer.project.problems import Issue
from designer.project.validate_shared import file_issue, plain_extent, plain_m

#: the highest wall or ridge a building may have above its base (m)
MAX_BUILDING_HEIGHT_M = declared_field(m.Building, "eave_height_m").attr.high
#: a gable or hip footprint's corners may depart this much from a right angle (deg), and
#: its ridge direction this much from a side's
RECTANGLE_TOL_DEG = 1.0


def side_directions_deg(xy: list[tuple[float, float]]) -> list[float]:
    """Direction of each footprint edge (vertex i to i + 1), deg clockwise from grid
    north, folded into [0, 180)."""
    out = []
    for (xa, ya), (xb, yb) in zip(xy, xy[1:] + xy[:1], strict=True):
        out.append(math.degrees(math.atan2(xb - xa, yb - ya)) % 180.0)
    return out


def angle_gap_deg(a: float, b: float) -> float:
    """The smallest difference (deg) between two undirected directions."""
    d = (a - b) % 180.0
    return min(d, 180.0 - d)


def building_issues(scene: m.Scene, base: Path | None) -> list[Issue]:
    """Problems of the scene's buildings; mesh files are checked when ``base`` is given."""
    out: list[Issue] = []
    seen: set[str] = set()
    extent = scene.terrain.extent
    for b in scene.buildings:
        if not b.id:
            out.append(Issue(b, "building", "a building needs an id", attr="id"))
        elif b.id in seen:
            out.append(Issue(b, "building", f"building id '{b.id}' is used twice; give each "
                             "building its own id", attr="id"))
        seen.add(b.id)
        if bool(b.footprint) == (b.file is not None):
            out.append(Issue(b, "building", f"building '{b.id}' needs exactly one of a "
                             "footprint and a mesh file; give one of them", attr="file"))
            continue
        if b.file is not None:
            out += _mesh_building(b, extent, base)
        else:
            out += _extruded(b, extent, scene.targets)
    return out


def _mesh_building(b: m.Building, extent: m.Extent, base: Path | None) -> list[Issue]:
    out = []
    p = b.position
    if p is None or not (math.isfinite(p.X) and math.isfinite(p.Y)):
        out.append(Issue(b, "building", f"mesh building '{b.id}' needs X and Y (world m) of "
                         "its origin", attr="X"))
    elif not extent.contains(p.X, p.Y):
        out.append(Issue(b, "building", f"building '{b.id}' at X {plain_m(p.X)}, Y {plain_m(p.Y)} "
                         f"lies outside the terrain extent ({plain_extent(extent)}); move it "
                         "inside or enlarge the extent",
                         attr="X", code="outside-extent", value=(f"building '{b.id}'", p.X, p.Y)))
    if base is not None:
        out += file_issue(b, "building", mesh_problem(resolve(base, b.file)))
    return out


def _extruded(b: m.Building, extent: m.Extent, targets: m.Targets | None) -> list[Issue]:
    out = []
    if b.roof not in m.ROOF_SHAPES:
        out.append(Issue(b, "building", f"unknown roof {b.roof!r}; use one of "
                         f"{', '.join(m.ROOF_SHAPES)}", attr="roof", code="choice",
                         value=b.roof, choices=m.ROOF_SHAPES))
    pitched = b.roof in ("gable", "hip")
    if b.roof == "flat":
        for attr, value in (("ridge-height-m", b.ridge_height_m),
                            ("ridge-direction-deg", b.ridge_direction_deg)):
            if value is not None:
                out.append(Issue(b, "building", f"a flat roof has no ridge; remove {attr} or "
                                 "choose a gable or hip roof", attr=attr,
                                 code="flat-roof-ridge"))
    elif pitched:
        r = b.ridge_height_m
        if r is None:
            out.append(Issue(b, "building", f"a {b.roof} roof needs ridge-height-m (m above the "
                             "base, above eave-height-m)", attr="ridge-height-m",
                             code="needs-ridge", value=b.roof))
        elif declared_field(m.Building, "ridge_height_m").in_range(r) and r <= b.eave_height_m:
            out.append(Issue(b, "building", f"ridge-height-m = {r!r} must be above "
                             f"eave-height-m ({b.eave_height_m:g} m) and at most "
                             f"{MAX_BUILDING_HEIGHT_M:g} m", attr="ridge-height-m",
                             code="within", value=r,
                             limits=(b.eave_height_m, MAX_BUILDING_HEIGHT_M)))
    xy = [(p.X, p.Y) for p in b.footprint]
    fp = _footprint_issue(b, xy, extent)
    if fp is not None:
        return out + [fp]
    if pitched:
        out += _rectangle(b, xy)
    if targets is not None:
        for t in targets.targets:
            if point_in_polygon(t.true.X, t.true.Y, xy):
                out.append(Issue(b, "footprint", f"GCP target '{t.id}' lies under building "
                                 f"'{b.id}'; move the target or the building", key="footprint"))
    return out


def _footprint_issue(b: m.Building, xy: list[tuple[float, float]],
                     extent: m.Extent) -> Issue | None:
    def issue(text: str, **fields) -> Issue:
        return Issue(b, "footprint", f"building '{b.id}': {text}", key="footprint", **fields)

    if len(xy) < 3:
        return issue(f"the footprint has {len(xy)} vertex(es); give at least three X Y pairs")
    if not all(math.isfinite(x) and math.isfinite(y) for x, y in xy):
        return issue("the footprint needs an even count of finite numbers (X Y X Y …)")
    for i in range(len(xy)):
        if xy[i] == xy[i - 1]:
            return issue(f"vertex {i + 1 if i else len(xy)} repeats the one before; remove it "
                         "(the polygon closes itself: do not repeat the first vertex)")
    zero = issue("the footprint has zero area (its vertices lie on a line)")
    if polygon_is_degenerate(xy):
        return zero
    crossing = polygon_self_intersection(xy)
    if crossing is not None:
        i, j = crossing
        return issue(f"the footprint crosses itself: edge {i + 1} meets edge {j + 1}; list "
                     "the vertices in order around the building")
    if abs(polygon_area(xy)) < 1e-6:
        return zero
    for i, (x, y) in enumerate(xy):
        if not extent.contains(x, y):
            return issue(f"vertex {i + 1} (X {plain_m(x)}, Y {plain_m(y)}) lies outside the "
                         f"terrain extent ({plain_extent(extent)}); move it inside or "
                         "enlarge the extent", code="outside-extent",
                         value=(f"vertex {i + 1} of building '{b.id}'", x, y))
    return None


def _rectangle(b: m.Building, xy: list[tuple[float, float]]) -> list[Issue]:
    error = rectangle_corner_error_deg(xy)
    if error > RECTANGLE_TOL_DEG:
        shape = (f"has {len(xy)} vertices" if len(xy) != 4
                 else f"has a corner {error:.2f} deg off a right angle")
        return [Issue(b, "footprint", f"building '{b.id}': a {b.roof} roof is built on a "
                      f"rectangular footprint (four corners within {RECTANGLE_TOL_DEG:g} deg of "
                      f"a right angle); this one {shape}: choose a flat roof or a rectangle",
                      key="footprint", code="pitched-roof-shape")]
    if b.ridge_direction_deg is None:
        return []
    if not math.isfinite(b.ridge_direction_deg):
        return []  # its declared range (validate_declared) says so
    sides = side_directions_deg(xy)
    lengths = [math.dist(xy[i], xy[(i + 1) % 4]) for i in range(4)]
    gaps = [angle_gap_deg(b.ridge_direction_deg, s) for s in sides]
    k = min(range(4), key=gaps.__getitem__)
    if gaps[k] > RECTANGLE_TOL_DEG:
        return [Issue(b, "building", f"ridge-direction-deg = {b.ridge_direction_deg:g} runs "
                      f"along no side of the footprint (sides at {sides[0]:.1f} and "
                      f"{sides[1]:.1f} deg); give one of those or leave it out",
                      attr="ridge-direction-deg", code="ridge-direction",
                      value=b.ridge_direction_deg, choices=(f"{sides[0]:.1f}", f"{sides[1]:.1f}"))]
    if b.roof == "hip" and lengths[k] < lengths[(k + 1) % 4] * (1 - 1e-9):
        return [Issue(b, "building", f"a hip roof's ridge runs along the longer side "
                      f"({sides[(k + 1) % 4]:.1f} deg); change ridge-direction-deg or leave "
                      "it out", attr="ridge-direction-deg", code="ridge-direction",
                      value=b.ridge_direction_deg, choices=(f"{sides[(k + 1) % 4]:.1f}",))]
    return []
