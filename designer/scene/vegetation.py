"""Vegetation: plants scattered over the terrain by a seeded process and swaying in the
wind per image time (docs/world.md, Vegetation and wind). Pure geometry, numpy only.

A plant's frame: origin at the centre of its base, +Z up (m). Each plant group has one
template mesh (a built-in kind at unit height and unit crown diameter, or a mesh file)
and per plant a base point (world m), a scale (crown, crown, height relative to the
template), a turn about +Z (``yaw``) and a sway phase. Posed at a time ``t``::

    world = base + R_sway(t) · Rz(yaw) · diag(scale) · v

``R_sway`` turns about the horizontal axis perpendicular to the wind direction by
``amplitude · sin(2π t / period + phase)`` (positive: the top leans towards where the
wind blows). Without a time (``t`` None) or without wind the plants stand upright.
The render worker instances the same templates with the same transforms
(:func:`plant_rotations`), so the images show exactly :func:`vegetation_mesh_world`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from designer.project import model as m

#: linear default colours of a kind's (foliage, wood)
KIND_ALBEDO = {"grass-tuft": (0.16, 0.30, 0.06), "shrub": (0.10, 0.24, 0.06),
               "tree": (0.08, 0.20, 0.05)}
WOOD_ALBEDO = (0.22, 0.15, 0.09)
#: heights are drawn within these multiples of the mean (no negative or giant plants)
HEIGHT_CLIP = (0.2, 3.0)
#: how far (m) the built-in meshes reach below their base, so a plant on a slope does not
#: float above the downhill ground
ROOT_DEPTH_M = 0.05


@dataclass(frozen=True)
class PlantTemplate:
    """A group's mesh in the plant's frame (m): vertices (N, 3), faces (M, 3), the
    material of each face (0 foliage, 1 wood) and the size it stands for: height
    ``height_m`` and crown diameter ``crown_m``."""

    vertices: np.ndarray
    faces: np.ndarray
    material_index: np.ndarray
    height_m: float
    crown_m: float


@dataclass(frozen=True)
class PlantSet:
    """One group's plants: ids, base points (world m), heights and crown diameters (m),
    template scale factors (N, 3), yaw and sway phase (rad)."""

    group: int
    kind: str
    template: PlantTemplate
    ids: np.ndarray
    base_world: np.ndarray
    height_m: np.ndarray
    crown_m: np.ndarray
    scale: np.ndarray
    yaw_rad: np.ndarray
    phase_rad: np.ndarray
    albedo_rgb: tuple[float, float, float]

    def __len__(self) -> int:
        return len(self.ids)


# ------------------------------------------------------------------ templates
def _ellipsoid(rx: float, rz: float, z0: float, segments: int = 8,
               rings: int = 6) -> tuple[np.ndarray, np.ndarray]:
    """A low-poly ellipsoid (radii rx, rx, rz) centred at height z0."""
    verts = [[0.0, 0.0, z0 - rz]]
    for i in range(1, rings):
        theta = math.pi * i / rings
        for j in range(segments):
            a = 2 * math.pi * j / segments
            verts.append([rx * math.sin(theta) * math.cos(a), rx * math.sin(theta) * math.sin(a),
                          z0 - rz * math.cos(theta)])
    verts.append([0.0, 0.0, z0 + rz])
    faces = []
    top = len(verts) - 1
    for j in range(segments):
        k = (j + 1) % segments
        faces.append((0, 1 + k, 1 + j))
        for i in range(rings - 2):
            a, b = 1 + i * segments + j, 1 + i * segments + k
            c, d = a + segments, b + segments
            faces += [(a, b, d), (a, d, c)]
        last = 1 + (rings - 2) * segments
        faces.append((last + j, last + k, top))
    return np.array(verts, float), np.array(faces, np.int64)


def _cylinder(radius: float, z0: float, z1: float, sides: int = 6
              ) -> tuple[np.ndarray, np.ndarray]:
    a = 2 * np.pi * np.arange(sides) / sides
    ring = np.column_stack([radius * np.cos(a), radius * np.sin(a)])
    v = np.vstack([np.column_stack([ring, np.full(sides, z0)]),
                   np.column_stack([ring, np.full(sides, z1)])])
    f = []
    for i in range(sides):
        j = (i + 1) % sides
        f += [(i, j, sides + j), (i, sides + j, sides + i)]
    return v, np.array(f, np.int64)


def _grass_tuft(blades: int = 7) -> tuple[np.ndarray, np.ndarray]:
    """Crossed blades of unit height spreading to a unit-diameter crown: each a thin
    triangle from its root at the centre to a tip out and up."""
    verts, faces = [], []
    for k in range(blades):
        a = 2 * math.pi * k / blades + 0.4 * math.sin(3 * k)
        d = np.array([math.cos(a), math.sin(a), 0.0])
        side = np.array([-d[1], d[0], 0.0])
        reach = 0.5 * (0.6 + 0.4 * ((k * 5) % blades) / (blades - 1))
        tip_z = 1.0 - 0.25 * ((k * 3) % blades) / blades
        n = len(verts)
        verts += [list(-0.06 * side + [0, 0, -ROOT_DEPTH_M]),
                  list(0.06 * side + [0, 0, -ROOT_DEPTH_M]),
                  list(reach * d + [0, 0, tip_z])]
        faces.append((n, n + 1, n + 2))
    return np.array(verts, float), np.array(faces, np.int64)


def builtin_template(kind: str) -> PlantTemplate:
    """The built-in mesh of ``kind`` at unit height and unit crown diameter."""
    if kind == "grass-tuft":
        v, f = _grass_tuft()
        return PlantTemplate(v, f, np.zeros(len(f), np.int64), 1.0, 1.0)
    if kind == "shrub":
        v, f = _ellipsoid(0.5, 0.5 + ROOT_DEPTH_M / 2, 0.5 - ROOT_DEPTH_M / 2)
        return PlantTemplate(v, f, np.zeros(len(f), np.int64), 1.0, 1.0)
    if kind == "tree":
        crown_v, crown_f = _ellipsoid(0.5, 0.33, 0.67)
        trunk_v, trunk_f = _cylinder(0.04, -ROOT_DEPTH_M, 0.45)
        v = np.vstack([crown_v, trunk_v])
        f = np.vstack([crown_f, trunk_f + len(crown_v)])
        mat = np.r_[np.zeros(len(crown_f), np.int64), np.ones(len(trunk_f), np.int64)]
        return PlantTemplate(v, f, mat, 1.0, 1.0)
    raise ValueError(f"unknown plant kind {kind!r}")


def group_template(group: m.PlantGroup, base_dir: Path) -> PlantTemplate:
    """The template of a group: its kind's, or its mesh file (size: its own height
    above the base and its widest horizontal extent)."""
    if group.mesh is None:
        return builtin_template(group.kind)
    from designer.project.files import resolve
    from designer.scene.mesh import load_mesh

    mesh = load_mesh(resolve(Path(base_dir), group.mesh))
    v = np.asarray(mesh.vertices_world, float)
    f = np.asarray(mesh.faces, np.int64)
    if f.shape[1] != 3:  # quads → triangles
        f = np.vstack([f[:, [0, 1, 2]], f[:, [0, 2, 3]]])
    height = float(v[:, 2].max()) if len(v) else 1.0
    crown = float(2 * np.hypot(v[:, 0], v[:, 1]).max()) if len(v) else 1.0
    return PlantTemplate(v, f, np.zeros(len(f), np.int64), height if height > 0 else 1.0,
                         crown if crown > 0 else 1.0)


def group_size_m(group: m.PlantGroup, template: PlantTemplate) -> tuple[float, float]:
    """(mean height, crown diameter at that height) of a group, m."""
    if group.kind is not None and group.kind in m.PLANT_KINDS:
        height, crown = m.PLANT_KINDS[group.kind]
    else:
        height, crown = template.height_m, template.crown_m
    height = group.height_m if group.height_m is not None else height
    if group.crown_m is not None:
        crown = group.crown_m
    elif group.height_m is not None and group.mesh is not None:
        crown = template.crown_m * height / template.height_m  # the mesh, scaled as a whole
    return float(height), float(crown)


# ------------------------------------------------------------------ placement
def ground_heights_m(ground, x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Terrain height (world m) below each (x, y): the heightfield (clamped to its extent)
    or, for a mesh terrain, its nearest vertex's height."""
    x, y = np.asarray(x, float), np.asarray(y, float)
    if ground.heightfield is not None:
        return np.asarray(ground.heightfield.height_at_clamped(x, y), float).reshape(x.shape)
    from scipy.spatial import cKDTree

    v = np.asarray(ground.terrain.vertices_world, float)
    _, nearest = cKDTree(v[:, :2]).query(np.column_stack([x, y]))
    return v[np.asarray(nearest, np.int64), 2]


def place_vegetation(project: m.Project, base_dir: Path, ground) -> list[PlantSet]:
    """Every plant of the project's vegetation (``[]`` without one).

    Per group ``g`` a generator ``default_rng([seed, g])`` draws, in this order, a
    Poisson number of plants for the extent's area, their positions (uniform), heights
    (normal, clipped to 0.2–3 × the mean), yaws and sway phases (uniform); plants whose
    crown would leave the extent or come within ``clearance_m`` of a target plate are
    then dropped, as are plants that would reach into a building (the convex hull of its
    ground plan). Adding a group therefore leaves the others as they were.
    """
    veg = project.scene.vegetation
    if veg is None:
        return []
    ext = project.scene.terrain.extent
    targets = project.targets or ()
    target_xy = np.array([(t.true.X, t.true.Y) for t in targets], float).reshape(-1, 2)
    # half the plate's diagonal: the plate turns with the terrain but stays in this circle
    target_r = np.array([t.size_m * math.sqrt(0.5) for t in targets], float)
    lean = math.sin(math.radians(veg.wind.amplitude_deg)) if veg.wind is not None else 0.0
    footprints = _building_footprints(project, base_dir, ground)
    sets, next_id = [], 1
    for g, group in enumerate(veg.plants):
        template = group_template(group, base_dir)
        height_mean, crown_mean = group_size_m(group, template)
        rng = np.random.default_rng([veg.seed, g])
        area = (ext.max_X - ext.min_X) * (ext.max_Y - ext.min_Y)
        n = int(rng.poisson(group.density_per_m2 * area))
        x = rng.uniform(ext.min_X, ext.max_X, n)
        y = rng.uniform(ext.min_Y, ext.max_Y, n)
        height = np.clip(rng.normal(height_mean, group.height_sd_m, n),
                         HEIGHT_CLIP[0] * height_mean, HEIGHT_CLIP[1] * height_mean)
        yaw = rng.uniform(0.0, 2 * np.pi, n)
        phase = rng.uniform(0.0, 2 * np.pi, n)
        crown = crown_mean * height / height_mean
        reach = 0.5 * crown + lean * height  # how far from its base a plant's top can be
        keep = ((x - 0.5 * crown >= ext.min_X) & (x + 0.5 * crown <= ext.max_X)
                & (y - 0.5 * crown >= ext.min_Y) & (y + 0.5 * crown <= ext.max_Y))
        if len(target_xy):
            d = np.hypot(x[:, None] - target_xy[:, 0], y[:, None] - target_xy[:, 1])
            keep &= (d >= target_r + reach[:, None] + veg.clearance_m).all(axis=1)
        for hull in footprints:
            keep &= _clear_of(hull, x, y, reach)
        x, y, height, crown, yaw, phase = (a[keep] for a in (x, y, height, crown, yaw, phase))
        z = ground_heights_m(ground, x, y) if len(x) else np.zeros(0)
        scale = np.column_stack([crown / template.crown_m, crown / template.crown_m,
                                 height / template.height_m])
        ids = np.arange(next_id, next_id + len(x))
        next_id += len(x)
        kind = group.kind if group.mesh is None else Path(group.mesh).name
        albedo = group.albedo_rgb or KIND_ALBEDO.get(group.kind, KIND_ALBEDO["shrub"])
        sets.append(PlantSet(g, kind, template, ids, np.column_stack([x, y, z]), height,
                             crown, scale, yaw, phase, tuple(float(c) for c in albedo)))
    return sets


def _building_footprints(project: m.Project, base_dir: Path, ground) -> list[np.ndarray]:
    """The convex hull (k, 2) of every building's ground plan (world X/Y m)."""
    if not getattr(project.scene, "buildings", ()):
        return []
    from designer.scene.buildings import building_meshes_world, convex_hull_xy

    return [convex_hull_xy(v[:, :2]) for v, _ in building_meshes_world(project, base_dir,
                                                                      ground)]


def _clear_of(hull: np.ndarray, x: np.ndarray, y: np.ndarray, reach: np.ndarray) -> np.ndarray:
    """Which plants (bases x, y; reach m) stay out of the convex polygon ``hull``: base
    outside it and farther than ``reach`` from its edges."""
    from designer.scene.buildings import points_in_polygon

    if len(hull) < 3 or not len(x):
        return np.ones(len(x), bool)
    a, b = hull, np.roll(hull, -1, axis=0)
    ab = b - a
    t = ((x[:, None] - a[:, 0]) * ab[:, 0] + (y[:, None] - a[:, 1]) * ab[:, 1]) / np.maximum(
        (ab ** 2).sum(axis=1), 1e-12)
    t = np.clip(t, 0.0, 1.0)
    d = np.hypot(x[:, None] - (a[:, 0] + t * ab[:, 0]), y[:, None] - (a[:, 1] + t * ab[:, 1]))
    return ~points_in_polygon(x, y, hull) & (d.min(axis=1) >= reach)


# ------------------------------------------------------------------ wind
def sway_angle_rad(wind: m.Wind | None, phase_rad: np.ndarray,
                   time_s: float | None) -> np.ndarray:
    """Each plant's lean at ``time_s`` (rad): amplitude · sin(2π t / period + phase); 0
    without wind or without a time."""
    phase_rad = np.asarray(phase_rad, float)
    if wind is None or time_s is None:
        return np.zeros_like(phase_rad)
    return math.radians(wind.amplitude_deg) * np.sin(
        2 * np.pi * float(time_s) / wind.gust_period_s + phase_rad)


def sway_axis(wind: m.Wind | None) -> np.ndarray:
    """Unit horizontal axis (world) the plants turn about: Z × the wind direction, so a
    positive angle leans their tops where the wind blows."""
    a = math.radians(wind.direction_deg if wind is not None else 0.0)
    d = np.array([math.sin(a), math.cos(a), 0.0])
    return np.cross([0.0, 0.0, 1.0], d)


def plant_rotations(yaw_rad: np.ndarray, phase_rad: np.ndarray, wind: m.Wind | None,
                    time_s: float | None) -> np.ndarray:
    """(N, 3, 3) rotations R_sway(t) · Rz(yaw), plant frame → world."""
    yaw_rad = np.asarray(yaw_rad, float)
    c, s = np.cos(yaw_rad), np.sin(yaw_rad)
    Rz = np.zeros((len(yaw_rad), 3, 3))
    Rz[:, 0, 0], Rz[:, 0, 1], Rz[:, 1, 0], Rz[:, 1, 1], Rz[:, 2, 2] = c, -s, s, c, 1.0
    theta = sway_angle_rad(wind, phase_rad, time_s)
    k = sway_axis(wind)
    K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    # Rodrigues: I + sin θ K + (1 − cos θ) K²
    R_sway = (np.eye(3) + np.sin(theta)[:, None, None] * K
              + (1 - np.cos(theta))[:, None, None] * (K @ K))
    return R_sway @ Rz


def quaternions_wxyz(R: np.ndarray) -> np.ndarray:
    """(N, 4) unit quaternions (w, x, y, z) of rotations R (N, 3, 3)."""
    R = np.asarray(R, float)
    q = np.empty((len(R), 4))
    tr = np.trace(R, axis1=1, axis2=2)
    q[:, 0] = np.sqrt(np.maximum(0.0, 1 + tr)) / 2
    q[:, 1] = np.copysign(np.sqrt(np.maximum(0.0, 1 + R[:, 0, 0] - R[:, 1, 1] - R[:, 2, 2])) / 2,
                          R[:, 2, 1] - R[:, 1, 2])
    q[:, 2] = np.copysign(np.sqrt(np.maximum(0.0, 1 - R[:, 0, 0] + R[:, 1, 1] - R[:, 2, 2])) / 2,
                          R[:, 0, 2] - R[:, 2, 0])
    q[:, 3] = np.copysign(np.sqrt(np.maximum(0.0, 1 - R[:, 0, 0] - R[:, 1, 1] + R[:, 2, 2])) / 2,
                          R[:, 1, 0] - R[:, 0, 1])
    return q / np.linalg.norm(q, axis=1, keepdims=True)


def posed_set(plants: PlantSet, wind: m.Wind | None, time_s: float | None
              ) -> tuple[np.ndarray, np.ndarray]:
    """(vertices_world (N·V, 3) float64, faces (N·F, 3)) of a group posed at ``time_s``."""
    t = plants.template
    if not len(plants):
        return np.zeros((0, 3)), np.zeros((0, 3), np.int64)
    M = plant_rotations(plants.yaw_rad, plants.phase_rad, wind, time_s) * plants.scale[:, None, :]
    v = plants.base_world[:, None, :] + np.einsum("nij,vj->nvi", M, t.vertices)
    faces = t.faces[None] + (np.arange(len(plants)) * len(t.vertices))[:, None, None]
    return v.reshape(-1, 3), faces.reshape(-1, 3)


def vegetation_mesh_world(project: m.Project, base_dir: Path, ground,
                          at_time_s: float | None) -> list[tuple[np.ndarray, np.ndarray]]:
    """The plants posed at ``at_time_s`` (s after take-off; None: upright), one
    (vertices_world (N, 3) float64, faces (M, 3) int64) per plant group — the geometry
    the renderer draws. ``ground`` has ``heightfield`` and ``terrain`` (a BuiltScene or
    designer.scene.surfaces.Ground)."""
    veg = project.scene.vegetation
    if veg is None:
        return []
    out = []
    for plants in place_vegetation(project, base_dir, ground):
        if len(plants):
            out.append(posed_set(plants, veg.wind, at_time_s))
    return out
