"""Buildings and structures as closed triangle meshes in the world (docs/world.md,
Buildings and structures).

World frame X east, Y north, Z up (m), float64. A building stands on the terrain: its
**base** is the lowest terrain height under its footprint (the heightfield nodes inside
the footprint and points every 1/8 grid cell along its edges; for a mesh terrain the
mesh vertices inside it and the nearest vertex to each edge point), and its walls go
down to the base, so on sloping ground they reach into the terrain on the uphill side
and no gap opens on the downhill side. Heights (``eave_height_m``, ``ridge_height_m``)
are metres above the base.

An extruded building is its footprint (counter-clockwise; a clockwise one is reversed)
with vertical walls up to the eaves and a roof:

* ``flat`` — the footprint (any simple polygon) at eave height;
* ``gable`` — a rectangle; two roof planes meet at the ridge, which runs along the
  sides parallel to ``ridge_direction_deg`` (default: the longer sides) through the
  middle of the two end sides; the ends are vertical triangular gables;
* ``hip`` — a rectangle; four roof planes of the same pitch ((ridge − eave) / half the
  width): two trapezoids along the long sides and two triangles over the ends; on a
  square the ridge shrinks to an apex (a pyramid).

A mesh-file building is the file's mesh (its frame: origin at the base centre, +Y
forward, +Z up, m) turned by ``heading_deg`` (clockwise from grid north) and moved to
(X, Y, base), the base under the convex hull of its vertices.

Every face is counter-clockwise seen from outside (outward normals); an extruded
building's mesh is closed (a floor at the base), so its signed volume is its volume.
These meshes are what the renderer draws, the DSM holds and the GCP visibility test
casts rays against.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from designer.errors import DesignerError
from designer.project import model as m

#: face kinds (``BuildingMesh.face_kind``): facade, roof, floor (never seen)
WALL, ROOF, FLOOR = 0, 1, 2
#: a mesh-file face counts as roof when its normal's Z exceeds this
ROOF_NORMAL_Z = 0.5
#: edge sampling for the base height, in grid cells
BASE_EDGE_STEP_CELLS = 0.125


@dataclass(frozen=True, eq=False)
class BuildingMesh:
    """One building as built: ``vertices_world`` (N, 3) m, ``faces`` (M, 3) outward
    counter-clockwise, ``face_kind`` (M,) WALL/ROOF/FLOOR, ``base_z_m`` its base height."""

    id: str
    vertices_world: np.ndarray
    faces: np.ndarray
    face_kind: np.ndarray
    base_z_m: float


# ---------------------------------------------------------------------- plane geometry
def footprint_ccw(building: m.Building) -> np.ndarray:
    """The footprint (n, 2) world X/Y, counter-clockwise."""
    xy = np.array([(p.X, p.Y) for p in building.footprint], float)
    return xy[::-1].copy() if _signed_area(xy) < 0 else xy


def _signed_area(xy: np.ndarray) -> float:
    d = xy - xy[0]
    return 0.5 * float(np.sum(d[:-1, 0] * d[1:, 1] - d[1:, 0] * d[:-1, 1]))


def points_in_polygon(x: np.ndarray, y: np.ndarray, xy: np.ndarray) -> np.ndarray:
    """Boolean mask of the points (x, y) inside the polygon ``xy`` (n, 2), even-odd."""
    x, y = np.asarray(x, float), np.asarray(y, float)
    inside = np.zeros(np.broadcast(x, y).shape, bool)
    for (xa, ya), (xb, yb) in zip(xy, np.roll(xy, -1, axis=0), strict=True):
        crosses = (ya > y) != (yb > y)
        with np.errstate(divide="ignore", invalid="ignore"):
            x_at = xa + (y - ya) * (xb - xa) / (yb - ya)
        inside ^= crosses & (x < x_at)
    return inside


def triangulate_polygon(xy: np.ndarray) -> np.ndarray:
    """Triangles (n − 2, 3) of vertex indices covering the simple counter-clockwise
    polygon ``xy`` (n, 2), each counter-clockwise (ear clipping)."""
    p = np.asarray(xy, float) - xy[0]
    left = list(range(len(p)))
    out = []
    guard = 0
    while len(left) > 3:
        n = len(left)
        for k in range(n):
            a, b, c = left[k - 1], left[k], left[(k + 1) % n]
            if _cross(p[a], p[b], p[c]) <= 0:
                continue  # reflex or flat corner
            others = [i for i in left if i not in (a, b, c)]
            if others and _in_triangle(p[others], p[a], p[b], p[c]).any():
                continue
            out.append((a, b, c))
            left.pop(k)
            break
        else:
            guard += 1
            if guard > 1:
                raise DesignerError("footprint cannot be triangulated: is it self-intersecting?")
            # only collinear corners left: drop one
            left.pop(next(k for k in range(len(left))
                          if abs(_cross(p[left[k - 1]], p[left[k]],
                                        p[left[(k + 1) % len(left)]])) < 1e-12))
    out.append(tuple(left))
    return np.array(out, np.int64)


def _cross(a, b, c) -> float:
    return float((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]))


def _in_triangle(q: np.ndarray, a, b, c) -> np.ndarray:
    def side(p0, p1):
        return (p1[0] - p0[0]) * (q[:, 1] - p0[1]) - (p1[1] - p0[1]) * (q[:, 0] - p0[0])

    return (side(a, b) >= 0) & (side(b, c) >= 0) & (side(c, a) >= 0)


def convex_hull_xy(xy: np.ndarray) -> np.ndarray:
    """Counter-clockwise convex hull (k, 2) of points (n, 2) (monotone chain)."""
    pts = np.unique(np.asarray(xy, float), axis=0)
    if len(pts) < 3:
        return pts

    def half(points):
        h: list = []
        for q in points:
            while len(h) >= 2 and _cross(h[-2], h[-1], q) <= 0:
                h.pop()
            h.append(q)
        return h

    lower, upper = half(pts), half(pts[::-1])
    return np.array(lower[:-1] + upper[:-1])


# ---------------------------------------------------------------------- ground
def base_height_m(ground, xy: np.ndarray) -> float:
    """The lowest terrain height (m) under the polygon ``xy`` (module docstring);
    ``ground`` has ``heightfield`` (or None) and ``terrain`` (vertices_world)."""
    xy = np.asarray(xy, float)
    hf = ground.heightfield
    cell = (min(hf.dx_m, hf.dy_m) if hf is not None
            else _mesh_spacing_m(ground.terrain.vertices_world))
    step = cell * BASE_EDGE_STEP_CELLS
    samples = [xy]
    for a, b in zip(xy, np.roll(xy, -1, axis=0), strict=True):
        n = max(1, math.ceil(np.linalg.norm(b - a) / step))
        t = np.arange(n)[:, None] / n
        samples.append(a + t * (b - a))
    edge = np.vstack(samples)
    if hf is not None:
        heights = [np.asarray(hf.height_at_clamped(edge[:, 0], edge[:, 1])).ravel()]
        ny, nx = hf.heights_m.shape
        lo, hi = xy.min(axis=0), xy.max(axis=0)
        j0, j1 = (max(0, int(np.floor((v - hf.x0_m) / hf.dx_m))) for v in (lo[0], hi[0]))
        i0, i1 = (max(0, int(np.floor((v - hf.y0_m) / hf.dy_m))) for v in (lo[1], hi[1]))
        jj, ii = np.meshgrid(np.arange(j0, min(j1 + 2, nx)), np.arange(i0, min(i1 + 2, ny)))
        gx, gy = hf.x0_m + jj * hf.dx_m, hf.y0_m + ii * hf.dy_m
        inside = points_in_polygon(gx, gy, xy)
        heights.append(hf.heights_m[ii[inside], jj[inside]])
        return float(np.concatenate(heights).min())
    v = ground.terrain.vertices_world
    inside = points_in_polygon(v[:, 0], v[:, 1], xy)
    near = [v[int(np.argmin((v[:, 0] - x) ** 2 + (v[:, 1] - y) ** 2)), 2] for x, y in edge]
    return float(min(min(near), v[inside, 2].min(initial=np.inf)))


def _mesh_spacing_m(v: np.ndarray) -> float:
    span = np.ptp(v[:, :2], axis=0)
    return float(max(np.sqrt(span[0] * span[1] / max(len(v), 1)), 1e-3))


# ---------------------------------------------------------------------- roofs
@dataclass(frozen=True)
class RoofFrame:
    """A pitched roof's rectangle: ``P`` (4, 2) counter-clockwise corners with edge
    P0→P1 along the ridge; ``length_m`` along the ridge, ``width_m`` across it."""

    P: np.ndarray
    length_m: float
    width_m: float

    @property
    def centre(self) -> np.ndarray:
        return self.P.mean(axis=0)

    @property
    def along(self) -> np.ndarray:
        d = self.P[1] - self.P[0]
        return d / np.linalg.norm(d)

    @property
    def across(self) -> np.ndarray:
        a = self.along
        return np.array([-a[1], a[0]])


def roof_frame(building: m.Building) -> RoofFrame:
    """The rectangle of a gable or hip building, turned so its first edge runs along the
    ridge (``ridge_direction_deg``, or the longer side)."""
    xy = footprint_ccw(building)
    if len(xy) != 4:
        raise DesignerError(f"building '{building.id}': a {building.roof} roof needs a "
                            "rectangular footprint (four vertices)")
    lengths = np.linalg.norm(np.roll(xy, -1, axis=0) - xy, axis=1)
    if building.ridge_direction_deg is None:
        k = int(np.argmax(lengths[:2] + lengths[2:]))  # the longer pair of sides
    else:
        d = np.roll(xy, -1, axis=0) - xy
        sides = np.degrees(np.arctan2(d[:, 0], d[:, 1])) % 180.0
        gap = np.abs((sides - building.ridge_direction_deg) % 180.0)
        k = int(np.argmin(np.minimum(gap, 180.0 - gap)))
    P = np.roll(xy, -k, axis=0)
    return RoofFrame(P, float((lengths[k] + lengths[(k + 2) % 4]) / 2),
                     float((lengths[(k + 1) % 4] + lengths[(k + 3) % 4]) / 2))


def roof_height_m(building: m.Building, base_z_m: float, x, y) -> np.ndarray:
    """The top of an extruded building (world Z, m) above world (x, y) inside its
    footprint (NaN outside): the flat roof, or the gable or hip planes."""
    x, y = np.broadcast_arrays(np.asarray(x, float), np.asarray(y, float))
    eave = base_z_m + building.eave_height_m
    inside = points_in_polygon(x, y, footprint_ccw(building))
    if building.roof == "flat":
        z = np.full(x.shape, eave)
    else:
        frame = roof_frame(building)
        rel = np.stack([x, y], axis=-1) - frame.centre
        s = np.abs(rel @ frame.along)
        d = np.abs(rel @ frame.across)
        half_w = frame.width_m / 2
        pitch = (building.ridge_height_m - building.eave_height_m) / half_w
        rise = half_w - d
        if building.roof == "hip":
            rise = np.minimum(rise, frame.length_m / 2 - s)
        z = eave + pitch * rise
    return np.where(inside, z, np.nan)


# ---------------------------------------------------------------------- meshes
def extruded_mesh(building: m.Building, base_z_m: float) -> BuildingMesh:
    """The closed mesh of an extruded building standing at ``base_z_m`` (module
    docstring)."""
    if building.roof == "flat":
        xy = footprint_ccw(building)
    else:
        xy = roof_frame(building).P
    n = len(xy)
    eave = base_z_m + building.eave_height_m
    base_v = np.column_stack([xy, np.full(n, base_z_m)])
    eave_v = np.column_stack([xy, np.full(n, eave)])
    vertices = [base_v, eave_v]
    faces: list[tuple[int, int, int]] = []
    kinds: list[int] = []
    for i in range(n):
        j = (i + 1) % n
        faces += [(i, j, n + j), (i, n + j, n + i)]
        kinds += [WALL, WALL]
    floor = triangulate_polygon(xy)
    faces += [tuple(t) for t in floor[:, ::-1]]
    kinds += [FLOOR] * len(floor)
    if building.roof == "flat":
        faces += [tuple(t) for t in floor + n]
        kinds += [ROOF] * len(floor)
    else:
        roof_faces, roof_kinds, ridge = _pitched_roof(building, xy, n)
        ridge[:, 2] = base_z_m + building.ridge_height_m
        vertices.append(ridge)
        faces += roof_faces
        kinds += roof_kinds
    return BuildingMesh(building.id, np.vstack(vertices), np.array(faces, np.int64),
                        np.array(kinds, np.int64), float(base_z_m))


def _pitched_roof(building: m.Building, P: np.ndarray, n: int):
    """Faces over the eave ring (vertices n..n+3) and the ridge vertices (numbered from
    2n; their Z is set by the caller)."""
    frame = roof_frame(building)
    e = [n + i for i in range(4)]
    m1, m3 = (P[1] + P[2]) / 2, (P[3] + P[0]) / 2  # middles of the end sides
    half_w = frame.width_m / 2
    gable = building.roof == "gable"
    inset = 0.0 if gable else half_w
    ridge_len = np.linalg.norm(m1 - m3) - 2 * inset
    base = 2 * n
    if not gable and ridge_len <= 1e-9 * max(1.0, frame.length_m):
        # a hip roof on a square: four triangles up to one apex
        apex = base
        ridge = np.array([[*frame.centre, 0.0]])
        faces = [(e[i], e[(i + 1) % 4], apex) for i in range(4)]
        kinds = [ROOF] * 4
    else:
        u = (m1 - m3) / np.linalg.norm(m1 - m3)
        ra, rb = base, base + 1  # ridge ends near the end sides P3P0 and P1P2
        ridge = np.array([[*(m3 + inset * u), 0.0], [*(m1 - inset * u), 0.0]])
        end_kind = WALL if gable else ROOF
        faces = [(e[0], e[1], rb), (e[0], rb, ra),       # the side along P0 → P1
                 (e[1], e[2], rb),                        # the end over P1 → P2
                 (e[2], e[3], ra), (e[2], ra, rb),        # the side along P2 → P3
                 (e[3], e[0], ra)]                        # the end over P3 → P0
        kinds = [ROOF, ROOF, end_kind, ROOF, ROOF, end_kind]
    return faces, kinds, ridge


def mesh_file_building(building: m.Building, base_dir: Path, ground) -> BuildingMesh:
    """A mesh-file building placed in the world (module docstring)."""
    from designer.project.files import resolve
    from designer.scene.mesh import load_mesh
    from designer.scene.moving import rotation_z

    mesh = load_mesh(resolve(Path(base_dir), building.file))
    v = np.asarray(mesh.vertices_world, float) @ rotation_z(building.heading_deg).T
    v[:, :2] += (building.position.X, building.position.Y)
    base = base_height_m(ground, convex_hull_xy(v[:, :2]))
    v[:, 2] += base
    f = np.asarray(mesh.faces, np.int64)
    normal = np.cross(v[f[:, 1]] - v[f[:, 0]], v[f[:, 2]] - v[f[:, 0]])
    length = np.linalg.norm(normal, axis=1)
    nz = np.divide(normal[:, 2], length, out=np.zeros(len(f)), where=length > 0)
    return BuildingMesh(building.id, v, f, np.where(nz > ROOF_NORMAL_Z, ROOF, WALL), base)


def build_building(building: m.Building, base_dir: Path, ground) -> BuildingMesh:
    """One building standing on ``ground`` (module docstring)."""
    if building.file is not None:
        return mesh_file_building(building, base_dir, ground)
    return extruded_mesh(building, base_height_m(ground, footprint_ccw(building)))


def build_buildings(project: m.Project, base_dir: Path, ground) -> list[BuildingMesh]:
    """Every building of ``project`` standing on ``ground`` (a BuiltScene or a
    :class:`designer.scene.surfaces.Ground`)."""
    return [build_building(b, base_dir, ground) for b in project.scene.buildings]


def building_meshes_world(project: m.Project, base_dir: Path, ground
                          ) -> list[tuple[np.ndarray, np.ndarray]]:
    """[(vertices_world (N, 3) float64, faces (M, 3) int64)] of every building: closed,
    outward-facing triangle meshes, the geometry the renderer draws."""
    return [(b.vertices_world, b.faces) for b in build_buildings(project, base_dir, ground)]


def mesh_volume_m3(vertices: np.ndarray, faces: np.ndarray) -> float:
    """Signed volume (m³) of a closed mesh: positive when its faces point outwards.
    Computed relative to the first vertex so world coordinates lose no precision."""
    v = np.asarray(vertices, float) - vertices[0]
    a, b, c = v[faces[:, 0]], v[faces[:, 1]], v[faces[:, 2]]
    return float(np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6.0)
