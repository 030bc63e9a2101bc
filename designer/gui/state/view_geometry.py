"""What the 3D view draws, as plain arrays: terrain display mesh, camera frusta,
ground footprints, flight lines. Qt-free and VTK-free (numpy only), so it is tested
and benchmarked without a display.

Everything is in **world** coordinates (m, X east, Y north, Z up, float64); the view
subtracts its display offset before handing points to VTK (float32 inside, which at
UTM-sized coordinates would be off by decimetres). Lines are returned in VTK's flat
cell layout ``[n, i0, …, i(n−1), n, …]`` so the view can use them as they are.

Frusta and footprints use the pinhole part of the camera (distortion ignored): they
are pictures of where a camera looks, not measurements; ``designer plan`` measures.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from designer.core.heightfield import Heightfield
from designer.core.interior import InteriorOrientation
from designer.scene.mesh import TerrainMesh

#: the display mesh of a height field keeps at most this many nodes per side
MAX_DISPLAY_NODES_PER_SIDE = 400
#: station count above which footprints use only the 4 image corners
DENSE_FOOTPRINT_LIMIT = 400
#: drawn brightness of flat ground in full sun (relative irradiance 1); slopes facing the
#: sun reach the texture's own colour at irradiance 1 / DISPLAY_GAIN
DISPLAY_GAIN = 0.8


@dataclass(frozen=True, eq=False)
class TerrainDisplay:
    """A triangle mesh to show: ``points_world`` (N, 3), ``faces`` (M, 3), ``uv`` (N, 2)
    in texture repeats (u east, v north, the texture's bottom-left at (0, 0)),
    ``stride`` the height-field nodes per display cell (1 = full resolution)."""

    points_world: np.ndarray
    faces: np.ndarray
    uv: np.ndarray
    stride: int = 1


def terrain_display(hf: Heightfield | None, mesh: TerrainMesh | None,
                    tiles: tuple[int, int] = (1, 1),
                    max_nodes_per_side: int = MAX_DISPLAY_NODES_PER_SIDE) -> TerrainDisplay:
    """The terrain as drawn: a height field thinned to ``max_nodes_per_side`` (every
    s-th node, the last row and column always kept), or a mesh terrain as it is."""
    if hf is None:
        if mesh is None:
            raise ValueError("terrain_display needs a height field or a mesh")
        return TerrainDisplay(mesh.vertices_world, mesh.faces,
                              mesh.uv * np.asarray(tiles, dtype=float), 1)
    z = hf.heights_m
    ny, nx = z.shape
    stride = max(1, math.ceil((max(nx, ny) - 1) / (max_nodes_per_side - 1)))
    cols = np.unique(np.r_[np.arange(0, nx, stride), nx - 1])
    rows = np.unique(np.r_[np.arange(0, ny, stride), ny - 1])
    X, Y = np.meshgrid(hf.x0_m + hf.dx_m * cols, hf.y0_m + hf.dy_m * rows)
    Z = z[np.ix_(rows, cols)]
    points = np.column_stack([X.ravel(), Y.ravel(), Z.ravel()])
    uv = np.column_stack([(cols / (nx - 1))[None, :].repeat(len(rows), 0).ravel() * tiles[0],
                          (rows / (ny - 1))[:, None].repeat(len(cols), 1).ravel() * tiles[1]])
    return TerrainDisplay(points, grid_faces(len(rows), len(cols)), uv, stride)


def vertex_normals(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """Unit normals (N, 3) of a triangle mesh's vertices: the area-weighted mean of the
    normals of the faces around each (counter-clockwise faces: outwards / upwards)."""
    v = np.asarray(vertices, dtype=float)
    f = np.asarray(faces, dtype=np.int64)
    face_n = np.cross(v[f[:, 1]] - v[f[:, 0]], v[f[:, 2]] - v[f[:, 0]])
    n = np.zeros_like(v)
    for k in range(3):
        np.add.at(n, f[:, k], face_n)
    length = np.linalg.norm(n, axis=1, keepdims=True)
    return np.divide(n, length, out=np.tile([0.0, 0.0, 1.0], (len(v), 1)), where=length > 0)


def shade_rgb(irradiance: np.ndarray, base_rgb=(1.0, 1.0, 1.0)) -> np.ndarray:
    """Vertex colours (N, 3) uint8 for a relative irradiance (1 = flat ground in full sun):
    ``base · clip(DISPLAY_GAIN · irradiance, 0, 1)``. The view multiplies the texture by
    them, so the terrain is drawn lit as the renderer lights it, without per-pixel
    lighting (which a software OpenGL pays for on every pixel of every frame)."""
    g = np.clip(DISPLAY_GAIN * np.asarray(irradiance, dtype=float), 0.0, 1.0)
    return np.rint(255 * g[:, None] * np.asarray(base_rgb, dtype=float)[None, :]).astype(
        np.uint8)


def flat_lit_rgb(albedo_linear: np.ndarray) -> np.ndarray:
    """Colours (N, 3) uint8 of faces the renderer lights as flat open ground (plants,
    moving objects): each linear albedo in sRGB, at the brightness of flat ground in full
    sun (:data:`DISPLAY_GAIN`)."""
    a = np.clip(np.asarray(albedo_linear, dtype=float), 0.0, 1.0)
    srgb = np.where(a <= 0.0031308, 12.92 * a, 1.055 * a ** (1 / 2.4) - 0.055)
    return np.rint(255 * min(DISPLAY_GAIN, 1.0) * srgb).astype(np.uint8)


def grid_faces(ny: int, nx: int) -> np.ndarray:
    """Two counter-clockwise triangles per cell of a row-major ny × nx node grid."""
    sw = (np.arange(ny - 1)[:, None] * nx + np.arange(nx - 1)[None, :]).ravel()
    faces = np.empty((2 * len(sw), 3), dtype=np.int64)
    faces[0::2] = np.column_stack([sw, sw + 1, sw + nx + 1])
    faces[1::2] = np.column_stack([sw, sw + nx + 1, sw + nx])
    return faces


#: the drawn surroundings keep at most this many nodes per side (a plain, coarse ring)
MAX_SURROUNDING_DISPLAY_NODES = 64


def _axis_nodes(g0: float, lo: float, hi: float, g1: float, step: float) -> np.ndarray:
    """Nodes from g0 to g1 at most ``step`` apart, with ``lo`` and ``hi`` (the terrain's
    edges) among them, so the ring's inner edge is the terrain's."""
    parts = [np.linspace(a, b, max(1, math.ceil((b - a) / step - 1e-9)) + 1)
             for a, b in ((g0, lo), (lo, hi), (hi, g1)) if b - a > 0]
    return np.unique(np.concatenate(parts))


def surroundings_display(rendered: Heightfield, declared_extent_m: tuple[float, ...],
                         max_nodes_per_side: int = MAX_SURROUNDING_DISPLAY_NODES
                         ) -> TerrainDisplay | None:
    """The rendered terrain's part beyond the declared extent (x0, x1, y0, y1), world
    metres, as a coarse ring of triangles on its heights (about ``max_nodes_per_side``
    nodes across the whole); None when the rendered terrain is the declared one. ``uv``
    is all zeros: the ring is drawn in one plain colour."""
    gx0, gx1, gy0, gy1 = rendered.extent_m
    x0, x1, y0, y1 = declared_extent_m
    if gx0 >= x0 and gx1 <= x1 and gy0 >= y0 and gy1 <= y1:
        return None
    step = max(gx1 - gx0, gy1 - gy0) / (max_nodes_per_side - 1)
    xs = _axis_nodes(gx0, max(x0, gx0), min(x1, gx1), gx1, step)
    ys = _axis_nodes(gy0, max(y0, gy0), min(y1, gy1), gy1, step)
    X, Y = np.meshgrid(xs, ys)
    points = np.column_stack([X.ravel(), Y.ravel(),
                              rendered.height_at_clamped(X, Y).ravel()])
    faces = grid_faces(len(ys), len(xs))
    centre = points[faces].mean(axis=1)
    over = ((centre[:, 0] > x0) & (centre[:, 0] < x1) & (centre[:, 1] > y0)
            & (centre[:, 1] < y1))
    return TerrainDisplay(points, faces[~over], np.zeros((len(points), 2)))


#: the far ground reaches this many times the rendered terrain's half-size beyond it
FAR_GROUND_REACH = 1.5
#: nodes along each side of the rendered terrain's border the far ground starts from
FAR_GROUND_NODES_PER_SIDE = 16


def far_ground_display(rendered: Heightfield,
                       reach: float = FAR_GROUND_REACH,
                       nodes_per_side: int = FAR_GROUND_NODES_PER_SIDE) -> TerrainDisplay:
    """A plain skirt from the border of the rendered terrain (the terrain with its
    surroundings) outwards, ``reach`` times its half-size further, falling from the
    border's heights to their median: ground no image sees, drawn so that the view does
    not end at a ridge against the sky. World metres; ``uv`` all zeros (one colour)."""
    gx0, gx1, gy0, gy1 = rendered.extent_m
    t = np.linspace(0.0, 1.0, nodes_per_side, endpoint=False)
    # the border, anticlockwise from the south-west corner
    x = np.r_[gx0 + t * (gx1 - gx0), np.full_like(t, gx1), gx1 - t * (gx1 - gx0),
              np.full_like(t, gx0)]
    y = np.r_[np.full_like(t, gy0), gy0 + t * (gy1 - gy0), np.full_like(t, gy1),
              gy1 - t * (gy1 - gy0)]
    z = np.asarray(rendered.height_at_clamped(x, y), dtype=float).ravel()
    centre = np.array([(gx0 + gx1) / 2, (gy0 + gy1) / 2])
    half = np.column_stack([x, y]) - centre
    # out along each border point's direction from the centre, as far for every point
    scale = 1.0 + reach * max(gx1 - gx0, gy1 - gy0) / 2 / np.linalg.norm(half, axis=1)
    outer = centre + half * scale[:, None]
    n = len(x)
    points = np.vstack([np.column_stack([x, y, z]),
                        np.column_stack([outer, np.full(n, float(np.median(z)))])])
    k = np.arange(n)
    k1 = (k + 1) % n
    faces = np.vstack([np.column_stack([k, k1, n + k1]), np.column_stack([k, n + k1, n + k])])
    return TerrainDisplay(points, faces.astype(np.int64), np.zeros((len(points), 2)))


# ----------------------------------------------------------------------- stations
@dataclass(frozen=True, eq=False)
class StationGeometry:
    """Cameras as drawn. ``C_world`` (N, 3); frusta: pyramids of height ``glyph_m``;
    footprints: closed polylines where the image border meets the ground; flight lines:
    polylines through the perspective centres of each line in flight order."""

    C_world: np.ndarray
    line_index: np.ndarray
    frustum_points: np.ndarray
    frustum_lines: np.ndarray
    footprint_points: np.ndarray
    footprint_lines: np.ndarray
    flight_points: np.ndarray
    flight_lines: np.ndarray
    glyph_m: float

    @property
    def n_stations(self) -> int:
        return len(self.C_world)


def offset_cells(cells: np.ndarray, offset: int) -> np.ndarray:
    """VTK cells ``[k, id…, k, id…]`` with every id (not the counts) moved by ``offset``."""
    out = np.array(cells, dtype=np.int64)
    i = 0
    while i < len(out):
        k = int(out[i])
        out[i + 1:i + 1 + k] += offset
        i += k + 1
    return out


def with_mount_frusta(platform: StationGeometry,
                      mounts: list[StationGeometry]) -> StationGeometry:
    """``platform``'s flight lines with the frusta and footprints of every camera of a
    rig (``mounts``: one geometry per physical camera, its images only)."""
    def joined(points_name: str, lines_name: str):
        points, lines, offset = [], [], 0
        for g in mounts:
            pts = getattr(g, points_name)
            points.append(pts)
            lines.append(offset_cells(getattr(g, lines_name), offset))
            offset += len(pts)
        return (np.concatenate(points).reshape(-1, 3),
                np.concatenate(lines).astype(np.int64) if lines else np.zeros(0, np.int64))

    fr_points, fr_lines = joined("frustum_points", "frustum_lines")
    fp_points, fp_lines = joined("footprint_points", "footprint_lines")
    return StationGeometry(platform.C_world, platform.line_index, fr_points, fr_lines,
                           fp_points, fp_lines, platform.flight_points, platform.flight_lines,
                           platform.glyph_m)


def border_pixels(interior: InteriorOrientation, per_edge: int = 1) -> np.ndarray:
    """Points (4·per_edge, 2) around the image border, clockwise from the top-left."""
    W, H = interior.image_size_px
    s = np.arange(per_edge) / per_edge
    top = np.column_stack([s * W, np.zeros(per_edge)])
    right = np.column_stack([np.full(per_edge, W), s * H])
    bottom = np.column_stack([W - s * W, np.full(per_edge, H)])
    left = np.column_stack([np.zeros(per_edge), H - s * H])
    return np.vstack([top, right, bottom, left])


def pinhole_directions_cam(interior: InteriorOrientation, uv_px: np.ndarray) -> np.ndarray:
    """Directions (K, 3) in the photogrammetric camera frame (z backwards, so z = −1) of
    pixels, ignoring distortion."""
    uv = np.asarray(uv_px, dtype=float).reshape(-1, 2)
    x = (uv[:, 0] - interior.cx_px) / interior.fx_px
    y = -(uv[:, 1] - interior.cy_px) / interior.fy_px
    return np.column_stack([x, y, -np.ones(len(uv))])


def polyline_cells(n_lines: int, points_per_line: int, closed: bool = False) -> np.ndarray:
    """VTK line cells for ``n_lines`` consecutive runs of ``points_per_line`` points."""
    k = points_per_line + (1 if closed else 0)
    ids = np.arange(points_per_line)
    if closed:
        ids = np.r_[ids, 0]
    cells = np.empty((n_lines, k + 1), dtype=np.int64)
    cells[:, 0] = k
    cells[:, 1:] = ids[None, :] + points_per_line * np.arange(n_lines)[:, None]
    return cells.ravel()


def station_geometry(
    C_world: np.ndarray, R_cam_to_world: np.ndarray, line_index: np.ndarray,
    interior: InteriorOrientation, first_hit=None, ground_z_m: float = 0.0,
    glyph_m: float | None = None,
) -> StationGeometry:
    """Frusta, footprints and flight lines of N stations.

    ``first_hit(origins, directions) -> (K, 3)`` finds where rays meet the terrain (NaN
    for a miss, e.g. :meth:`TerrainRaycaster.surface_hit`); rays that miss fall back to the
    plane Z = ``ground_z_m``; a footprint with a corner above the horizon is left out.
    """
    C = np.asarray(C_world, dtype=float).reshape(-1, 3)
    R = np.asarray(R_cam_to_world, dtype=float).reshape(-1, 3, 3)
    line = np.asarray(line_index, dtype=int).reshape(-1)
    n = len(C)
    if glyph_m is None:
        height = np.median(C[:, 2]) - ground_z_m if n else 1.0
        glyph_m = float(max(0.08 * abs(height), 0.5))

    # Frusta: apex + 4 corners at depth glyph_m; lines apex→corner and the rectangle.
    corners_cam = pinhole_directions_cam(interior, border_pixels(interior, 1)) * glyph_m
    corners = C[:, None, :] + np.einsum("nij,kj->nki", R, corners_cam)
    fr_points = np.concatenate([C[:, None, :], corners], axis=1).reshape(-1, 3)
    # cells [2, apex, c1] … [2, apex, c4], [5, c1, c2, c3, c4, c1]; local ids apex 0, c 1–4
    pattern = np.array([2, 0, 1, 2, 0, 2, 2, 0, 3, 2, 0, 4, 5, 1, 2, 3, 4, 1])
    is_count = np.zeros(len(pattern), bool)
    is_count[[0, 3, 6, 9, 12]] = True
    base = np.where(is_count[None, :], 0, 5 * np.arange(n)[:, None])
    fr_lines = (pattern[None, :] + base).ravel().astype(np.int64)

    # Footprints on the ground.
    per_edge = 4 if n <= DENSE_FOOTPRINT_LIMIT else 1
    dirs_cam = pinhole_directions_cam(interior, border_pixels(interior, per_edge))
    k = len(dirs_cam)
    dirs = np.einsum("nij,kj->nki", R, dirs_cam).reshape(-1, 3)
    origins = np.repeat(C, k, axis=0)
    hits = (first_hit(origins, dirs) if first_hit is not None and n
            else np.full((n * k, 3), np.nan))
    miss = ~np.isfinite(hits[:, 0])
    if miss.any():
        with np.errstate(divide="ignore", invalid="ignore"):
            t = (ground_z_m - origins[miss, 2]) / dirs[miss, 2]
        t = np.where(t > 0, t, np.nan)
        hits[miss] = origins[miss] + t[:, None] * dirs[miss]
    hits = hits.reshape(n, k, 3)
    ok = np.all(np.isfinite(hits[:, :, 0]), axis=1)
    fp_points = hits[ok].reshape(-1, 3)
    fp_lines = polyline_cells(int(ok.sum()), k, closed=True)

    # Flight lines: runs of consecutive stations with the same line index.
    if n:
        breaks = np.flatnonzero(np.diff(line)) + 1
        starts, stops = np.r_[0, breaks], np.r_[breaks, n]
        cells = [np.r_[stop - start, np.arange(start, stop)]
                 for start, stop in zip(starts, stops, strict=True) if stop - start >= 2]
        fl_lines = np.concatenate(cells) if cells else np.zeros(0, np.int64)
    else:
        fl_lines = np.zeros(0, np.int64)
    return StationGeometry(C, line, fr_points, fr_lines, fp_points, fp_lines, C.copy(),
                           fl_lines.astype(np.int64), glyph_m)
