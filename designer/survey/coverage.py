"""What ``designer plan`` reports about a flight plan over real terrain.

World frame X east, Y north, Z up (metres); stations as in :mod:`designer.survey.flight`.
All functions return plain dataclasses of numpy arrays (``summary()`` gives a flat dict).

Definitions (decisions):

* **GSD** of a terrain point in an image = depth · pitch / f, where depth is the
  distance along the camera's viewing axis (m), pitch the pixel width and f the focal
  length: the size of a pixel on a plane facing the camera. It equals
  QGroundControl's H · sw / (W · f) at every pixel of a nadir image of flat ground,
  and at the principal point it is the slant distance · pitch / f. It does not include
  foreshortening: on a surface inclined by θ to the image plane a pixel covers
  1/cos θ times more ground in one direction.
* **Station GSD**: rays through a ``k × k`` grid of pixels (image corners and edges
  included) and through the principal point are cast onto the terrain; the centre GSD
  is the principal point's, mean/min/max are over the grid.
* **Achieved overlap** is measured on those same terrain points, not on a plane:
  front overlap of station i = share of image i's area whose ground also lies inside
  image i + 1 (the next station on the same line); side overlap = share whose ground
  lies inside any image of the neighbouring line (the three stations of that line
  whose principal rays meet the ground nearest to station i's). The share is
  integrated over the two triangles of each cell of the sample grid: the signed
  distance (px) from each of the other image's four border lines is interpolated
  linearly, each line's share of the triangle is exact for it, and the four shares
  are multiplied (exact unless a corner of the other image falls in the triangle),
  so the result is not quantised by the grid: on flat ground it equals the requested
  overlap to rounding. Occlusion is ignored here (it is a footprint overlap); grid
  triangles with a pixel whose ray misses the terrain's surface are left out (a ray past
  the edge of a terrain without surroundings sees void, not the solid ground's side:
  :meth:`TerrainRaycaster.surface_hit`; analyse over the rendered terrain,
  :func:`designer.survey.surroundings.image_ground`, for the surroundings).
* **Coverage count** of a ground-grid node = number of images that see it: inside the
  image and not hidden by terrain (:mod:`designer.survey.visibility`). The shares of the
  area seen by at least 2, 3 and 5 images are over the grid nodes inside the area.
* **Render time** = images × megapixels × samples per pixel × seconds per megapixel
  and sample (a figure measured on the render machine, passed in).
"""

from __future__ import annotations

import itertools
import math
import warnings
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from designer.core.heightfield import Heightfield
from designer.core.interior import InteriorOrientation
from designer.core.projection import project_pairwise
from designer.core.raycast import TerrainRaycaster
from designer.core.rotation import R_CV_FROM_PHOTO
from designer.errors import DesignerError, ParameterError
from designer.survey import area as _area
from designer.survey.flight import FlightPlan, Station
from designer.survey.visibility import visible_pairs

#: thresholds reported by :attr:`CoverageMap.shares`
COVERAGE_THRESHOLDS = (2, 3, 5)
#: the default ground grid has about this many nodes over the area
DEFAULT_GRID_NODES = 40_000
#: margin (px) given to pixels whose ground is behind another camera: far outside
_OUTSIDE_PX = -1e12
#: nearest stations of a neighbouring line considered for side overlap
_SIDE_NEIGHBOURS = 3


# ------------------------------------------------------------------------ ground grid
@dataclass(frozen=True, eq=False)
class GroundGrid:
    """Ground nodes at the centres of square cells over the area's bounding box.

    Node (i, j) lies at X = x0_m + (j + ½)·cell_m, Y = y0_m + (i + ½)·cell_m (rows go
    north), Z = terrain height; ``valid`` marks nodes over the terrain, ``inside_area``
    those also inside the survey area.
    """

    x0_m: float
    y0_m: float
    cell_m: float
    z_m: np.ndarray
    valid: np.ndarray
    inside_area: np.ndarray

    @property
    def shape(self) -> tuple[int, int]:
        return self.z_m.shape

    @property
    def extent_m(self) -> tuple[float, float, float, float]:
        """(x_min, x_max, y_min, y_max) of the cells."""
        ny, nx = self.shape
        return (self.x0_m, self.x0_m + nx * self.cell_m,
                self.y0_m, self.y0_m + ny * self.cell_m)

    def points_world(self) -> np.ndarray:
        """(ny·nx, 3) node positions in row-major order (NaN Z where not valid)."""
        ny, nx = self.shape
        X, Y = np.meshgrid(self.x0_m + (np.arange(nx) + 0.5) * self.cell_m,
                           self.y0_m + (np.arange(ny) + 0.5) * self.cell_m)
        return np.column_stack([X.ravel(), Y.ravel(), self.z_m.ravel()])


def default_cell_m(heightfield: Heightfield, area) -> float:
    """A coarse grid: about DEFAULT_GRID_NODES nodes, never finer than the terrain."""
    size = _area.polygon_area_m2(area)
    return max(min(heightfield.dx_m, heightfield.dy_m), math.sqrt(size / DEFAULT_GRID_NODES))


def ground_grid(heightfield: Heightfield, area, cell_m: float | None = None) -> GroundGrid:
    """The analysis grid over ``area`` with cells of ``cell_m`` (default: default_cell_m)."""
    poly = _area.as_polygon(area)
    cell = default_cell_m(heightfield, poly) if cell_m is None else float(cell_m)
    if not (math.isfinite(cell) and cell > 0):
        raise ParameterError(f"coverage grid cell = {cell_m} m must be > 0", name="cell_m",
                             value=cell_m, unit="m", must="greater than 0 m")
    x0, x1, y0, y1 = heightfield.extent_m
    lo = np.maximum(poly.min(axis=0), [x0, y0])
    hi = np.minimum(poly.max(axis=0), [x1, y1])
    if np.any(hi <= lo):
        raise DesignerError("the survey area does not overlap the terrain")
    nx, ny = (int(v) for v in np.maximum(1, np.ceil((hi - lo) / cell - 1e-9)))
    if nx * ny > 25_000_000:
        raise DesignerError(f"a {cell} m coverage grid has {nx * ny} nodes; use larger cells")
    grid = GroundGrid(float(lo[0]), float(lo[1]), cell, np.zeros((ny, nx)),
                      np.zeros((ny, nx), bool), np.zeros((ny, nx), bool))
    xyz = grid.points_world()
    z = heightfield.height_at(xyz[:, 0], xyz[:, 1]).reshape(ny, nx)
    valid = np.isfinite(z)
    inside = _area.contains(poly, xyz[:, :2]).reshape(ny, nx) & valid
    return GroundGrid(grid.x0_m, grid.y0_m, cell, z, valid, inside)


# ---------------------------------------------------------------------- coverage map
@dataclass(frozen=True, eq=False)
class CoverageMap:
    """Per ground node: images that see it and their GSD (module docstring).

    count: (ny, nx) int; gsd_mean_m / gsd_min_m: (ny, nx) m/px, NaN where unseen.
    """

    grid: GroundGrid
    count: np.ndarray
    gsd_mean_m: np.ndarray
    gsd_min_m: np.ndarray

    def share_seen_by(self, k: int) -> float:
        """Share (0–1) of the area's nodes seen by at least k images."""
        inside = self.grid.inside_area
        return float(np.count_nonzero(self.count[inside] >= k) / max(1, inside.sum()))

    @property
    def shares(self) -> dict[int, float]:
        return {k: self.share_seen_by(k) for k in COVERAGE_THRESHOLDS}


def coverage_map(
    grid: GroundGrid,
    C_world: np.ndarray,
    R_cam_to_world: np.ndarray,
    interior: InteriorOrientation,
    raycaster: TerrainRaycaster | None,
    tol_m: float = 0.01,
) -> CoverageMap:
    """Count the images seeing each node of ``grid`` (``raycaster=None``: no occlusion)."""
    xyz = grid.points_world()
    valid = np.flatnonzero(grid.valid.ravel())
    pairs = visible_pairs(xyz[valid], C_world, R_cam_to_world, interior, raycaster, tol_m=tol_m)
    n = xyz.shape[0]
    node = valid[pairs.point]
    count = np.bincount(node, minlength=n)
    gsd = pairs.depth_m * _pitch_over_f(interior)
    with np.errstate(invalid="ignore", divide="ignore"):
        mean = np.bincount(node, weights=gsd, minlength=n) / count
    low = np.full(n, np.inf)
    np.minimum.at(low, node, gsd)
    low[count == 0] = np.nan
    shape = grid.shape
    return CoverageMap(grid, count.reshape(shape), mean.reshape(shape), low.reshape(shape))


# ------------------------------------------------------------------- GCP visibility
@dataclass(frozen=True, eq=False)
class GcpVisibility:
    """For each GCP: how many images see it, which (station indices) and where (px)."""

    counts: np.ndarray
    images: tuple[np.ndarray, ...]
    uv_px: tuple[np.ndarray, ...]


def gcp_visibility(
    gcp_xyz: np.ndarray,
    C_world: np.ndarray,
    R_cam_to_world: np.ndarray,
    interior: InteriorOrientation,
    raycaster: TerrainRaycaster | None,
    tol_m: float = 0.01,
    border_px: float = 0.0,
) -> GcpVisibility:
    """Images that see each GCP (G, 3) inside the image (≥ border_px from the edges)
    and unoccluded: the sight line meets the terrain no closer than the GCP − tol_m."""
    P = np.asarray(gcp_xyz, dtype=float).reshape(-1, 3)
    pairs = visible_pairs(P, C_world, R_cam_to_world, interior, raycaster,
                          tol_m=tol_m, border_px=border_px)
    order = np.lexsort((pairs.camera, pairs.point))
    cam, pt, uv = pairs.camera[order], pairs.point[order], pairs.uv_px[order]
    bounds = np.searchsorted(pt, np.arange(len(P) + 1))
    images = tuple(cam[a:b] for a, b in itertools.pairwise(bounds))
    uvs = tuple(uv[a:b] for a, b in itertools.pairwise(bounds))
    return GcpVisibility(np.diff(bounds), images, uvs)


# ---------------------------------------------------------------- station analysis
@dataclass(frozen=True, eq=False)
class StationAnalysis:
    """Per station (M,): GSD over the terrain and achieved overlaps (fractions 0–1).

    front_overlap is NaN for the last station of a line; side_overlap_prev/next are
    NaN without a previous/next line in the same grid. centre_ground_xyz (M, 3) is
    where the principal ray meets the terrain (NaN if it misses).
    """

    gsd_centre_m: np.ndarray
    gsd_mean_m: np.ndarray
    gsd_min_m: np.ndarray
    gsd_max_m: np.ndarray
    centre_ground_xyz: np.ndarray
    front_overlap: np.ndarray
    side_overlap_prev: np.ndarray
    side_overlap_next: np.ndarray


def analyse_stations(
    stations: Sequence[Station],
    interior: InteriorOrientation,
    raycaster: TerrainRaycaster,
    samples_per_axis: int = 9,
) -> StationAnalysis:
    """GSD and achieved overlaps of every station over the real terrain (module doc)."""
    k = int(samples_per_axis)
    if k < 2:
        raise DesignerError("samples_per_axis must be at least 2")
    M = len(stations)
    C = np.array([s.C_world for s in stations]).reshape(M, 3)
    R = np.array([s.R_cam_to_world for s in stations]).reshape(M, 3, 3)
    line = np.array([s.line_index for s in stations], dtype=int)
    grid_of = np.array([s.grid_index for s in stations], dtype=int)
    W, H = interior.image_size_px
    U, V = np.meshgrid(np.linspace(0, W, k), np.linspace(0, H, k))
    uv = np.vstack([np.column_stack([U.ravel(), V.ravel()]), [interior.cx_px, interior.cy_px]])
    rays = np.einsum("mij,sj->msi", R @ R_CV_FROM_PHOTO, interior.rays_cv(uv))
    S = uv.shape[0]
    ground = raycaster.surface_hit(np.repeat(C, S, axis=0),
                                   rays.reshape(-1, 3)).reshape(M, S, 3)
    depth = np.einsum("msi,mi->ms", ground - C[:, None, :], -R[:, :, 2])
    gsd = depth * _pitch_over_f(interior)
    grid_gsd = gsd[:, :-1]
    with warnings.catch_warnings():  # a station that sees no ground: All-NaN slice
        warnings.simplefilter("ignore", RuntimeWarning)
        gsd_mean = np.nanmean(grid_gsd, axis=1)
        gsd_min, gsd_max = np.nanmin(grid_gsd, axis=1), np.nanmax(grid_gsd, axis=1)

    # Past the terrain's edge a ray sees what the raycaster's terrain holds there: the
    # surroundings when it is the rendered terrain (designer.survey.surroundings), else
    # nothing (void: left out of the overlap, never the side of the solid ground).
    samples = ground[:, :-1]  # (M, k², 3)
    hit = np.all(np.isfinite(samples), axis=2)
    # neighbours are found by where the images look (an oblique camera looks ahead)
    centre_xy = np.where(np.isfinite(ground[:, -1, :2]), ground[:, -1, :2], C[:, :2])
    pairs = _overlap_pairs(centre_xy, line, grid_of)  # (station, other, role)
    tri_valid = _triangle_valid(hit.reshape(M, k, k))  # (M, T)
    if len(pairs):
        margins = _margins(samples, hit, pairs, C, R, interior)  # (P, 4, k²)
        tri_share = _triangle_shares(margins.reshape(len(pairs), 4, k, k))  # (P, T)
    else:  # one image, or none that overlap: no overlap to measure (NaN below)
        tri_share = np.zeros((0, tri_valid.shape[1]))
    shares = {}
    for role in range(3):
        sel = pairs[:, 2] == role
        best = np.zeros(tri_valid.shape)
        np.maximum.at(best, pairs[sel, 0], tri_share[sel])
        with np.errstate(invalid="ignore", divide="ignore"):
            share = (best * tri_valid).sum(axis=1) / tri_valid.sum(axis=1)
        has = np.zeros(M, dtype=bool)
        has[pairs[sel, 0]] = True
        shares[role] = np.where(has, share, np.nan)
    return StationAnalysis(
        gsd_centre_m=gsd[:, -1], gsd_mean_m=gsd_mean, gsd_min_m=gsd_min, gsd_max_m=gsd_max,
        centre_ground_xyz=ground[:, -1], front_overlap=shares[0],
        side_overlap_prev=shares[1], side_overlap_next=shares[2],
    )


def _overlap_pairs(centre_xy, line, grid_of) -> np.ndarray:
    """(P, 3) int rows (station, other station, role 0 front / 1 prev line / 2 next line);
    on a neighbouring line the _SIDE_NEIGHBOURS stations whose image centres lie
    nearest."""
    M = len(line)
    rows = []
    idx = np.arange(M)
    same = np.flatnonzero(line[:-1] == line[1:])
    rows.append(np.column_stack([same, same + 1, np.zeros_like(same)]))
    for role, step in ((1, -1), (2, 1)):
        for L in np.unique(line):
            mine = idx[line == L]
            other = idx[(line == L + step) & (grid_of == grid_of[mine[0]])]
            if other.size == 0:
                continue
            d2 = ((centre_xy[mine, None] - centre_xy[None, other]) ** 2).sum(axis=-1)
            nearest = np.argsort(d2, axis=1)[:, :_SIDE_NEIGHBOURS]
            rows.append(np.column_stack([np.repeat(mine, nearest.shape[1]),
                                         other[nearest].ravel(),
                                         np.full(nearest.size, role)]))
    return np.concatenate(rows).astype(int) if rows else np.zeros((0, 3), int)


def _margins(samples, hit, pairs, C, R, interior) -> np.ndarray:
    """Signed distances (px) of each pair's station samples to the other image's four
    border lines, positive inside: (P, 4, k²) as (u, W − u, v, H − v)."""
    W, H = interior.image_size_px
    n_s = samples.shape[1]
    # every pair's samples that met the ground, each into the pair's other camera at once
    row, s = np.nonzero(hit[pairs[:, 0]])
    proj = project_pairwise(samples[pairs[row, 0], s], C, R, pairs[row, 1], interior)
    front = proj.in_front
    at = (row * n_s + s)[front]
    u, v = proj.uv_px[front, 0], proj.uv_px[front, 1]
    out = np.full((4, len(pairs) * n_s), _OUTSIDE_PX)
    out[0, at], out[1, at], out[2, at], out[3, at] = u, W - u, v, H - v
    return out.reshape(4, len(pairs), n_s).transpose(1, 0, 2)


def _triangles(a: np.ndarray):
    """The two triangles of every cell of the trailing (k, k) sample grid, as three
    vertex arrays of shape (..., 2·(k − 1)²)."""
    lead = a.shape[:-2]

    def flat(x):
        return x.reshape(*lead, -1)

    p00, p01 = flat(a[..., :-1, :-1]), flat(a[..., :-1, 1:])
    p10, p11 = flat(a[..., 1:, :-1]), flat(a[..., 1:, 1:])
    return (np.concatenate([p00, p00], -1), np.concatenate([p01, p11], -1),
            np.concatenate([p11, p10], -1))


def _triangle_valid(hit: np.ndarray) -> np.ndarray:
    """(M, T) 1.0 where all three samples of a triangle met the terrain."""
    a, b, c = _triangles(hit)
    return (a & b & c).astype(float)


def _triangle_shares(margins: np.ndarray) -> np.ndarray:
    """Share of each triangle inside the other image, (P, T), from margins (P, 4, k, k).

    Each border line's share is exact for the linearly interpolated signed distance;
    the four are multiplied, which is exact wherever at most one border line crosses
    a triangle (only triangles holding a corner of the other image are approximate).
    """
    P, n_border, k = margins.shape[:3]
    # border-major rows: the margins come as a view of border-major arrays (_margins), so
    # this copies nothing
    rows = np.moveaxis(margins, 1, 0).reshape(n_border * P, k * k)
    inside = rows >= 0
    all_in, any_in = inside.all(axis=1), inside.any(axis=1)
    # a border whose samples lie all on one side gives 1 or 0 to every triangle; only
    # those crossing the grid need the triangles (over a 5,000-image block, most pairs'
    # borders cross none: this was 20 of the plan figures' 35 s)
    out = np.ones((P, 2 * (k - 1) ** 2))
    out[(~any_in).reshape(n_border, P).any(axis=0)] = 0.0
    mixed = np.flatnonzero(any_in & ~all_in)
    if not len(mixed):
        return out
    share = _crossed_shares(rows[mixed].reshape(-1, k, k), inside[mixed].reshape(-1, k, k))
    # multiplied in border order, as a product over the four (x · 1 is x exactly, so
    # leaving out the borders that give 1 changes no bit)
    border, pair = np.divmod(mixed, P)
    for b in range(n_border):
        sel = border == b
        out[pair[sel]] *= share[sel]
    return out


def _crossed_shares(grid: np.ndarray, inside: np.ndarray) -> np.ndarray:
    """Share of every triangle of (N, k, k) sample grids where the linear interpolant of
    its vertex values is ≥ 0, (N, T) in :func:`_triangles`' order; only the triangles a
    border crosses are measured (about one in ten: the rest are 1 or 0 from their
    vertices' sides, ``inside``)."""
    N, k = grid.shape[:2]
    flat = grid.ravel()
    s = inside.view(np.int8)
    s00, s01, s10, s11 = s[:, :-1, :-1], s[:, :-1, 1:], s[:, 1:, :-1], s[:, 1:, 1:]
    n_cell = (k - 1) ** 2
    out = np.empty((N, 2 * n_cell))
    # each cell's triangles (p00, p01, p11) and (p00, p11, p10): the offsets of the
    # second and third vertex from p00 in the flat grid
    for half, (n_pos, (dq, dr)) in enumerate((((s00 + s01) + s11, (1, k + 1)),
                                              ((s00 + s11) + s10, (k + 1, k)))):
        n_pos = n_pos.reshape(N, n_cell)
        share = out[:, half * n_cell:(half + 1) * n_cell]
        np.equal(n_pos, 3, out=share, casting="unsafe")
        row, cell = np.nonzero((n_pos == 1) | (n_pos == 2))
        r, c = np.divmod(cell, k - 1)
        p = row * (k * k) + r * k + c
        share[row, cell] = _cut_share(flat[p], flat[p + dq], flat[p + dr], n_pos[row, cell])
    return out


def _cut_share(p, q, r, n_pos):
    """The share ≥ 0 of triangles with one or two vertices ≥ 0 (flat arrays)."""
    # the vertex whose sign differs from the other two, and those two
    lone_is_p = (p >= 0) != (q >= 0)
    lone_is_p &= (p >= 0) != (r >= 0)
    lone_is_q = ~lone_is_p & ((q >= 0) != (p >= 0))
    x = np.where(lone_is_p, p, np.where(lone_is_q, q, r))
    y = np.where(lone_is_p, q, p)
    z = np.where(lone_is_p | lone_is_q, r, q)
    with np.errstate(invalid="ignore", divide="ignore"):
        corner = x * x / ((x - y) * (x - z))
    return np.where(n_pos == 1, corner, 1.0 - corner)


# --------------------------------------------------------------------------- summary
@dataclass(frozen=True, eq=False)
class PlanAnalysis:
    """Everything ``designer plan`` reports; ``summary()`` flattens it to numbers."""

    n_images: int
    stations: StationAnalysis
    station_inside_area: np.ndarray
    coverage: CoverageMap
    gcps: GcpVisibility | None
    render_time_s: float | None

    def median_gsd_m(self) -> float:
        """The flight's GSD (m/px) for its footprint and figures in GSD: the median GSD at
        the image centres of the stations over the area, as ``summary()`` gives it;
        without stations over the area, the median of every station's mean GSD (NaN when
        no image sees the terrain)."""
        centre = self.stations.gsd_centre_m[self.station_inside_area]
        centre = centre[np.isfinite(centre)]
        if centre.size:
            return float(np.median(centre))
        mean = self.stations.gsd_mean_m[np.isfinite(self.stations.gsd_mean_m)]
        return float(np.median(mean)) if mean.size else math.nan

    def summary(self) -> dict:
        """Flat dict of headline figures (m, fractions 0–1, seconds).

        Station figures are over the stations whose principal ray meets the terrain
        inside the area (the run-in and run-out stations past the edges have no
        neighbouring line beside them and would report a meaningless side overlap).
        """
        inside = self.station_inside_area
        st = self.stations
        side = np.concatenate([st.side_overlap_prev[inside], st.side_overlap_next[inside]])
        out = {"n_images": self.n_images, "stations_over_area": int(inside.sum())}
        for name, values in (("gsd_centre_m", st.gsd_centre_m[inside]),
                             ("front_overlap", st.front_overlap[inside]),
                             ("side_overlap", side)):
            v = values[np.isfinite(values)]
            for stat, f in (("median", np.median), ("min", np.min), ("max", np.max)):
                out[f"{name}_{stat}"] = float(f(v)) if v.size else math.nan
            out[f"{name}_p05"] = float(np.percentile(v, 5)) if v.size else math.nan
        for k, share in self.coverage.shares.items():
            out[f"area_seen_by_{k}_or_more"] = share
        if self.gcps is not None:
            counts = self.gcps.counts
            out["gcp_views_min"] = int(counts.min()) if counts.size else 0
            out["gcps_in_fewer_than_3_images"] = int(np.count_nonzero(self.gcps.counts < 3))
        out["render_time_s"] = self.render_time_s
        return out


def analyse_plan(
    plan: FlightPlan | Sequence[Station],
    interior: InteriorOrientation,
    heightfield: Heightfield,
    area,
    *,
    gcp_xyz: np.ndarray | None = None,
    cell_m: float | None = None,
    samples_per_axis: int = 9,
    tol_m: float = 0.01,
    raycaster: TerrainRaycaster | None = None,
) -> PlanAnalysis:
    """Run every analysis of this module on a plan (or a list of stations)."""
    stations = plan.stations if isinstance(plan, FlightPlan) else tuple(plan)
    if len(stations) == 0:
        raise DesignerError("the flight plan has no stations")
    rc = raycaster if raycaster is not None else TerrainRaycaster(heightfield)
    C = np.array([s.C_world for s in stations])
    R = np.array([s.R_cam_to_world for s in stations])
    cover = coverage_map(ground_grid(heightfield, area, cell_m), C, R, interior, rc, tol_m)
    gcps = None if gcp_xyz is None else gcp_visibility(gcp_xyz, C, R, interior, rc, tol_m)
    render = None  # the caller's estimate (designer.render_time.model)
    st = analyse_stations(stations, interior, rc, samples_per_axis)
    centre = st.centre_ground_xyz
    # Over the area: the station itself and the ground its principal ray meets.
    inside = np.isfinite(centre[:, 0]) & _area.contains(area, C[:, :2])
    inside[inside] = _area.contains(area, centre[inside, :2])
    return PlanAnalysis(len(stations), st, inside, cover, gcps, render)


# ----------------------------------------------------------------------------- helpers
def _pitch_over_f(interior: InteriorOrientation) -> float:
    return interior.pixel_pitch_x_mm / interior.focal_length_mm
