"""Surroundings: the world rendered beyond the declared terrain, so no image sees its edge.

A drone survey sees ground to the horizon. The declared terrain (``<terrain><extent>``)
is the area of interest; with ``<surroundings mode="auto">`` the renderer continues it as
far as any image of the project looks — every camera and rig mount, pose noise, terrain
following, orbit and facade flights included (the images of
:func:`designer.survey.project_poses.project_images`):

* procedural terrain continues its own hills (they are fixed to the world,
  :func:`designer.scene.terrain.procedural_terrain`), flat terrain its plane, a DEM its
  edge heights (each edge node held outwards, so the seam has no step);
* a tiled texture continues its tiles: the terrain grows by whole tiles, so the texture
  and its variation at every point of the declared extent stay as they were; an
  orthophoto holds its edge colours.

How far is planned from the images (:mod:`designer.survey.surroundings`, which gives a
:class:`Growth`); this module grows the terrain by it (:func:`grow_terrain`).

Stations are always planned over the declared terrain (altitude references and terrain
following do not change with the surroundings); the surroundings are built from them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from designer.core.heightfield import Heightfield
from designer.errors import DesignerError
from designer.project import model as m

#: extra ground beyond the farthest border ray (fraction of the reach, and at least this
#: many grid spacings): covers motion during the exposure and the pixel footprint
MARGIN_FRACTION = 0.05
MARGIN_SPACINGS = 4
#: the grown grid's node limit (the detailed part); beyond, the far ground takes over
MAX_SURROUNDING_NODES = 16e6


def surroundings_mode(terrain: m.Terrain) -> str:
    """"auto" or "none": the declared mode, else the default of the terrain kind (auto for
    flat and procedural terrain, none for DEM and mesh files)."""
    if terrain.surroundings is not None:
        return terrain.surroundings
    return "auto" if isinstance(terrain.source, (m.FlatTerrain, m.ProceduralTerrain)) else "none"


def grown_extent(declared: tuple[float, float, float, float],
                 reach_m: tuple[float, float, float, float],
                 step_x_m: float, step_y_m: float, spacing_m: float
                 ) -> tuple[int, int, int, int]:
    """Whole steps (west, east, south, north) to grow the declared extent (x0, x1, y0, y1)
    by so it covers the reach with a margin; a step is a texture tile (or a grid
    spacing). The growth is capped so the grid stays within MAX_SURROUNDING_NODES."""
    x0, x1, y0, y1 = declared
    r0, r1, s0, s1 = reach_m
    span = max(r1 - r0, s1 - s0, x1 - x0, y1 - y0, 0.0)
    margin = max(MARGIN_FRACTION * span, MARGIN_SPACINGS * spacing_m)

    def steps(need_m: float, step: float) -> int:
        return max(0, math.ceil((need_m + margin) / step - 1e-9)) if need_m > -margin else 0

    grow = [steps(x0 - r0, step_x_m), steps(r1 - x1, step_x_m),
            steps(y0 - s0, step_y_m), steps(s1 - y1, step_y_m)]

    def nodes(g):
        w = x1 - x0 + (g[0] + g[1]) * step_x_m
        h = y1 - y0 + (g[2] + g[3]) * step_y_m
        return (w / spacing_m + 1) * (h / spacing_m + 1)

    while nodes(grow) > MAX_SURROUNDING_NODES and max(grow) > 0:
        k = int(np.argmax(grow))
        grow[k] -= 1
    return tuple(grow)


@dataclass(frozen=True)
class Surroundings:
    """The rendered terrain (declared extent plus surroundings) and how it was grown."""

    heightfield: Heightfield
    #: whole tiles added on each side (west, east, south, north); the texture's tiles
    #: over the rendered terrain are the declared repeats plus these
    tiles_added: tuple[int, int, int, int]
    #: True when an image looks past the detailed surroundings (towards the horizon)
    horizon: bool

    def texture_tiles(self, repeat: tuple[int, int]) -> tuple[int, int]:
        w, e, s, n = self.tiles_added
        return repeat[0] + w + e, repeat[1] + s + n


def _tile_m(project: m.Project) -> tuple[float, float] | None:
    """Ground size (m) of one texture tile, None for an orthophoto (not tiled)."""
    tex = project.scene.texture
    if isinstance(tex.source, m.OrthophotoTexture):
        return None
    e = project.scene.terrain.extent
    return e.width_m / tex.repeat_X, e.length_m / tex.repeat_Y


@dataclass(frozen=True)
class Growth:
    """How far the rendered terrain reaches beyond the declared one: whole steps (west,
    east, south, north) of :func:`growth_step_m`, and whether an image looks past it."""

    steps: tuple[int, int, int, int] = (0, 0, 0, 0)
    horizon: bool = False


def growth_step_m(project: m.Project, declared: Heightfield) -> tuple[float, float]:
    """The step (m, east and north) the terrain grows by: a texture tile, so the tiled
    texture keeps its place; a grid spacing for a DEM or an orthophoto; the extent for
    flat ground textured by an orthophoto."""
    src = project.scene.terrain.source
    tile = _tile_m(project)
    if isinstance(src, m.DemTerrain) or tile is None:
        if isinstance(src, m.FlatTerrain):
            x0, x1, y0, y1 = declared.extent_m
            return x1 - x0, y1 - y0
        return declared.dx_m, declared.dy_m
    return tile


def grow_terrain(project: m.Project, declared: Heightfield, growth: Growth) -> Surroundings:
    """The height field to render: the declared one grown by ``growth`` (the module
    docstring says how each kind of terrain continues)."""
    src = project.scene.terrain.source
    if not any(growth.steps):
        return Surroundings(declared, (0, 0, 0, 0), growth.horizon)
    if isinstance(src, m.MeshTerrain):
        raise DesignerError("surroundings mode=\"auto\" needs a height-field terrain (flat, "
                            "procedural or DEM); a mesh terrain takes mode=\"none\"")
    x0, x1, y0, y1 = declared.extent_m
    step = growth_step_m(project, declared)
    w, e, s, n = growth.steps
    gx0, gx1 = x0 - w * step[0], x1 + e * step[0]
    gy0, gy1 = y0 - s * step[1], y1 + n * step[1]
    tiled = _tile_m(project) is not None and not isinstance(src, m.DemTerrain)
    if isinstance(src, m.FlatTerrain):
        # nodes on the steps (whole tiles): a bake's rectangle of whole tiles is whole faces
        nx, ny = w + e + round((x1 - x0) / step[0]), s + n + round((y1 - y0) / step[1])
        hf = Heightfield(gx0, gy0, (gx1 - gx0) / max(nx, 1), (gy1 - gy0) / max(ny, 1),
                         np.full((max(ny, 1) + 1, max(nx, 1) + 1), src.height_m))
    elif isinstance(src, m.ProceduralTerrain):
        hf = _procedural(src, gx0, gx1, gy0, gy1)
    else:
        hf = Heightfield(gx0, gy0, declared.dx_m, declared.dy_m,
                         np.pad(declared.heights_m, ((s, n), (w, e)), mode="edge"))
    return Surroundings(hf, growth.steps if tiled else (0, 0, 0, 0), growth.horizon)


@lru_cache(maxsize=2)
def _procedural(src: m.ProceduralTerrain, x0: float, x1: float, y0: float, y1: float
                ) -> Heightfield:
    """The procedural terrain over the grown extent: on the declared grid's nodes when
    whole tiles are whole spacings, else on the nearest even spacing (same heights at
    every node, as they are fixed to the world). The last two are kept (read-only): an
    edit that leaves the growth as it was (a flight height typed in the window, the plan
    figures after the stations) takes the same height field, and its ray caster
    (designer.core.raycast.raycaster_of), without computing the hills again."""
    from designer.scene.terrain import terrain_heights

    d = src.grid_spacing_m
    nx = max(1, round((x1 - x0) / d))
    ny = max(1, round((y1 - y0) / d))
    dx, dy = (x1 - x0) / nx, (y1 - y0) / ny
    x = x0 + np.arange(nx + 1) * dx
    y = y0 + np.arange(ny + 1) * dy
    relief = 0.5 * (src.max_height_m - src.min_height_m)
    z = terrain_heights(x[None, :], y[:, None], d, relief, src.seed,
                        base_height_m=0.5 * (src.max_height_m + src.min_height_m),
                        roughness=src.roughness, hill_size_m=src.hill_size_m)
    z = np.ascontiguousarray(z)
    z.flags.writeable = False
    return Heightfield(x0, y0, dx, dy, z)


#: how far the far ground reaches from the terrain's centre (m): its edge lies within
#: 0.1° of the true horizon for a camera 50 m up
FAR_GROUND_M = 30000.0


def far_ground(hf: Heightfield, radius_m: float = FAR_GROUND_M
               ) -> tuple[np.ndarray, np.ndarray]:
    """A ring of ground from the height field's edge out to a square ``radius_m`` from
    its centre, for images that look towards the horizon: (outer vertices (n, 3) world
    m, faces (2n, 3)). Face indices below ``nx·ny`` are the height field mesh's own edge
    nodes (:func:`designer.scene.mesh.heightfield_to_mesh` numbering), so ring and terrain
    share their seam exactly; the outer ring lies at the mean edge height. Faces are
    counter-clockwise from above (normals up)."""
    ny, nx = hf.heights_m.shape
    # the edge nodes, counter-clockwise: south row west→east, east column south→north,
    # north row east→west, west column north→south
    south = [(0, j) for j in range(nx - 1)]
    east = [(i, nx - 1) for i in range(ny - 1)]
    north = [(ny - 1, j) for j in range(nx - 1, 0, -1)]
    west = [(i, 0) for i in range(ny - 1, 0, -1)]
    loop = np.array(south + east + north + west)
    index = loop[:, 0] * nx + loop[:, 1]
    x = hf.x0_m + loop[:, 1] * hf.dx_m
    y = hf.y0_m + loop[:, 0] * hf.dy_m
    z = hf.heights_m[loop[:, 0], loop[:, 1]]
    x0, x1, y0, y1 = hf.extent_m
    cx, cy = 0.5 * (x0 + x1), 0.5 * (y0 + y1)
    dx, dy = x - cx, y - cy
    scale = radius_m / np.maximum(np.maximum(np.abs(dx), np.abs(dy)), 1e-9)
    outer = np.column_stack([cx + dx * scale, cy + dy * scale, np.full(len(x), z.mean())])
    n = len(loop)
    base = ny * nx
    k = np.arange(n)
    k1 = (k + 1) % n
    faces = np.empty((2 * n, 3), np.int64)
    faces[0::2] = np.column_stack([index[k], base + k, base + k1])
    faces[1::2] = np.column_stack([index[k], base + k1, index[k1]])
    # counter-clockwise from above (the loop runs counter-clockwise, the ring outside it)
    p = np.concatenate([np.column_stack([x, y, z]), outer])
    lookup = np.full(base + n, -1)
    lookup[index] = k
    lookup[base + k] = n + k
    a, b, c = (p[lookup[faces[:, i]]] for i in range(3))
    up = ((b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0]))
    faces[up < 0] = faces[up < 0][:, [0, 2, 1]]
    return outer, faces
