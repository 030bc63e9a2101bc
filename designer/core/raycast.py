"""Fast ray queries on a height field: first hit and line of sight, vectorised.

World frame X east, Y north, Z up (metres). The surface is the height field's
bilinear surface; outside its extent there is no terrain. The ground is solid: a ray
that enters the grid's extent from the side below the surface is stopped where it
enters (the core's :meth:`Heightfield.intersect_rays` only finds downward crossings).

Method: conservative sphere tracing. Along a ray ``O + t·d`` (|d| = 1) the vertical gap
``g(t) = O_z + t·d_z − h(x(t), y(t))`` can shrink no faster than
``rate = −d_z + S·|d_xy|``, where S bounds the terrain slope |∇h| over the stretch of
the ray still to be searched; so stepping ``t += g / rate`` never passes the first
crossing. The slope bound and the highest terrain point over a ray's stretch come from
per-block maxima (blocks of ``block_cells`` × ``block_cells`` grid cells) with an O(1)
range-maximum table over the box the stretch spans; the search stops where the ray is
above everything it could still meet. A first-hit search stops as soon as the gap is
below its tolerance. A line-of-sight search stops when the gap reaches zero, and steps
at least MIN_STEP_CELLS of a cell so it does not creep along a sight line that grazes
the terrain: a sight line dipping below the surface for less than that may pass as
clear. A ray that needs more than ``max_iter`` steps (MAX_STEPS unless told) is
finished by :meth:`Heightfield.intersect_rays` (half-cell marching, which can step over
a crossing shorter than half a cell). Steps are compiled and cheap, so the budget is
large: a ray grazing a long slope creeps towards it in many short steps (over the GUI
benchmark's hills, 16 914 of 198 144 image rays needed more than 64 steps, 261 more than
256, none more than 1024; half-cell marching put 16 152 of those 64-step rays' hits up
to 60 m too far, past a crest it stepped over).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from designer.core.compiled import cterrain
from designer.core.heightfield import Heightfield

#: smallest step (in grid cells) of a line-of-sight search close to the surface
MIN_STEP_CELLS = 0.01
#: sphere-tracing steps of a ray before half-cell marching finishes it
MAX_STEPS = 4096


class TerrainRaycaster:
    """Precomputed bounds of one height field for :meth:`first_hit` and :meth:`occluded`."""

    def __init__(self, heightfield: Heightfield, block_cells: int = 8) -> None:
        self.heightfield = heightfield
        z = heightfield.heights_m
        self._ny, self._nx = z.shape
        self._zf = np.ascontiguousarray(z, dtype=np.float64).ravel()
        self._x0, self._y0 = float(heightfield.x0_m), float(heightfield.y0_m)
        self._dx, self._dy = float(heightfield.dx_m), float(heightfield.dy_m)
        x0, x1, y0, y1 = heightfield.extent_m
        self._box = (x0, x1, y0, y1)
        self.z_min_m, self.z_max_m = float(z.min()), float(z.max())
        # (the same arithmetic as written plainly, in place: over a survey's millions of
        # nodes each temporary array is tens of megabytes)
        cell_max = np.maximum(z[:-1, :-1], z[:-1, 1:])
        np.maximum(cell_max, np.maximum(z[1:, :-1], z[1:, 1:]), out=cell_max)
        # within a bilinear cell |dh/dx| is at most the larger of its two x edges' slopes
        ex = np.diff(z, axis=1)
        np.abs(ex, out=ex)
        ex /= self._dx
        ey = np.diff(z, axis=0)
        np.abs(ey, out=ey)
        ey /= self._dy
        cell_slope = np.maximum(ex[:-1], ex[1:])
        del ex
        np.hypot(cell_slope, np.maximum(ey[:, :-1], ey[:, 1:]), out=cell_slope)
        del ey
        self._block = int(block_cells)
        top = _range_max_table(_block_reduce(cell_max, self._block, -np.inf))
        slope = _range_max_table(_block_reduce(cell_slope, self._block, 0.0))
        self._tables = _flat_tables(top, slope)

    # ------------------------------------------------------------------ queries
    def height(self, x_m: np.ndarray, y_m: np.ndarray) -> np.ndarray:
        """Bilinear height at (x, y), clamped to the grid (no NaN)."""
        fx = np.clip((np.asarray(x_m, dtype=float) - self._x0) / self._dx, 0, self._nx - 1)
        fy = np.clip((np.asarray(y_m, dtype=float) - self._y0) / self._dy, 0, self._ny - 1)
        j = np.minimum(fx.astype(np.intp), self._nx - 2)
        i = np.minimum(fy.astype(np.intp), self._ny - 2)
        tx, ty = fx - j, fy - i
        k = i * self._nx + j
        zf = self._zf
        z00, z01 = zf[k], zf[k + 1]
        z10, z11 = zf[k + self._nx], zf[k + self._nx + 1]
        lower = z00 + tx * (z01 - z00)
        return lower + ty * (z10 + tx * (z11 - z10) - lower)

    def first_hit(
        self, origins_world, directions_world, tol_m: float = 1e-3, max_iter: int = MAX_STEPS
    ) -> np.ndarray:
        """First intersection (N, 3) of rays with the terrain; NaN rows for misses.

        The returned point lies on the ray at most ``tol_m`` (vertical gap) above the
        surface, just before the exact crossing. A ray that enters the grid's extent
        from the side below the surface hits where it enters (the ground is solid).
        """
        org, d = _rays(origins_world, directions_world)
        n = len(org)
        t = self._march(org, d, np.zeros(n), np.full(n, np.inf), tol_m, 0.0, max_iter)
        return org + t[:, None] * d

    def surface_hit(
        self, origins_world, directions_world, tol_m: float = 1e-3, max_iter: int = MAX_STEPS
    ) -> np.ndarray:
        """First intersection (N, 3) of rays with the terrain's surface, NaN rows for
        misses: :meth:`first_hit` without the solid ground's sides. A ray from outside the
        grid's extent that enters a side below the surface (on its way down past the edge,
        possibly a kilometre below) sees no ground there: what is rendered past the edge
        is the surroundings or nothing, never the side of the height field."""
        org, d = _rays(origins_world, directions_world)
        hit = self.first_hit(org, d, tol_m, max_iter)
        x0, x1, y0, y1 = self._box
        eps = 1e-6 * max(1.0, abs(x0), abs(x1), abs(y0), abs(y1))
        outside = (org[:, 0] < x0) | (org[:, 0] > x1) | (org[:, 1] < y0) | (org[:, 1] > y1)
        with np.errstate(invalid="ignore"):
            on_side = ((np.abs(hit[:, 0] - x0) < eps) | (np.abs(hit[:, 0] - x1) < eps)
                       | (np.abs(hit[:, 1] - y0) < eps) | (np.abs(hit[:, 1] - y1) < eps))
        side = np.flatnonzero(outside & on_side)
        if side.size:
            below = hit[side, 2] < self.height(hit[side, 0], hit[side, 1]) - 1e-6
            hit[side[below]] = np.nan
        return hit

    def sees_surface(self, origins_world, directions_world) -> np.ndarray:
        """(N,) True where the ray meets the terrain's surface: where :meth:`surface_hit`
        finds a point, without finding it for most rays. A ray going down that is over
        the grid where it comes down to the terrain's highest point (or at its origin,
        when that is lower) and where it reaches the lowest point passes between them
        over the grid, from above the surface (or from inside the solid ground, which
        counts as a hit at the origin) to below it: it meets the surface there. Only the
        other rays are cast."""
        org, d = _rays(origins_world, directions_world)
        oz, dz = org[:, 2], d[:, 2]
        x0, x1, y0, y1 = self._box
        with np.errstate(divide="ignore", invalid="ignore"):
            t_top = np.where(oz > self.z_max_m, (self.z_max_m - oz) / dz, 0.0)
            t_low = (self.z_min_m - oz) / dz
            a = org[:, :2] + t_top[:, None] * d[:, :2]
            b = org[:, :2] + t_low[:, None] * d[:, :2]
            over = ((a[:, 0] >= x0) & (a[:, 0] <= x1) & (a[:, 1] >= y0) & (a[:, 1] <= y1)
                    & (b[:, 0] >= x0) & (b[:, 0] <= x1) & (b[:, 1] >= y0) & (b[:, 1] <= y1))
        sure = (dz < 0) & np.isfinite(t_low) & (t_low >= t_top) & over
        out = sure.copy()
        rest = np.flatnonzero(~sure)
        if rest.size:
            out[rest] = np.isfinite(self.surface_hit(org[rest], d[rest])).all(axis=1)
        return out

    def surely_sees_surface(self, origins_world, corner_directions_world,
                            margin_m: float = 1e-3) -> np.ndarray:
        """(M,) True where every ray from origin k (M, 3) inside the convex cone of its
        corner directions (M, n, 3) is one :meth:`sees_surface` finds over the grid
        without casting it (its ``sure`` test), so a bundle of such rays (an image's) need
        not be tested ray by ray. The test holds for the corners with ``margin_m`` to
        spare: a ray of the cone is a positive blend of the corners, it goes down where
        they all do, and it comes down to a horizontal plane inside the hull of where
        they do (a central projection keeps convex sets convex), so inside the grid's
        box where they all are; the margin leaves room for rounding."""
        org = np.asarray(origins_world, dtype=float).reshape(-1, 3)
        d = np.asarray(corner_directions_world, dtype=float)
        d = d / np.linalg.norm(d, axis=2, keepdims=True)
        x0, x1, y0, y1 = self._box
        oz = org[:, 2:3]
        down = np.all(d[:, :, 2] < -1e-6, axis=1)

        def inside(xy):
            return np.all((xy[..., 0] >= x0 + margin_m) & (xy[..., 0] <= x1 - margin_m)
                          & (xy[..., 1] >= y0 + margin_m) & (xy[..., 1] <= y1 - margin_m),
                          axis=-1)

        with np.errstate(divide="ignore", invalid="ignore"):
            low = org[:, None, :2] + ((self.z_min_m - oz) / d[:, :, 2])[..., None] * d[..., :2]
            top = org[:, None, :2] + ((self.z_max_m - oz) / d[:, :, 2])[..., None] * d[..., :2]
            above = oz[:, 0] > self.z_max_m
            # from above the highest point the rays come down to it over the grid; from
            # between the lowest and the highest point they start over it
            start = np.where(above, inside(top), inside(org[:, None, :2]))
            return down & (oz[:, 0] >= self.z_min_m) & start & inside(low)

    def occluded(
        self, points_world, cameras_world, tol_m: float = 0.01, max_iter: int = MAX_STEPS
    ) -> np.ndarray:
        """(N,) True where the terrain hides point k from camera k (pairwise, N × 3 each).

        The sight line is blocked where it touches or passes below the surface anywhere
        between the camera and ``tol_m`` short of the point, i.e. where the ray from the
        camera meets the terrain first closer than ``|C − P| − tol_m``. The point itself
        may lie on the surface (a GCP, a ground sample). Near the surface the search
        steps at least MIN_STEP_CELLS of a grid cell, so a sight line that dips below
        the surface for less than that (it grazes the terrain) may pass as clear.
        """
        P = np.asarray(points_world, dtype=float).reshape(-1, 3)
        C = np.asarray(cameras_world, dtype=float).reshape(-1, 3)
        P, C = np.broadcast_arrays(P, C)
        v = C - P
        dist = np.linalg.norm(v, axis=1)
        with np.errstate(invalid="ignore", divide="ignore"):
            u = v / dist[:, None]
        out = np.zeros(len(P), dtype=bool)
        todo = np.flatnonzero(dist > tol_m)
        if todo.size:
            min_step = MIN_STEP_CELLS * min(self._dx, self._dy)
            t = self._march(P[todo], u[todo], np.full(todo.size, float(tol_m)), dist[todo],
                            0.0, min_step, max_iter)
            out[todo] = np.isfinite(t)
        return out

    # ---------------------------------------------------------------- internals
    def _march(self, org, d, t0, t1, touch_m, min_step_m, max_iter) -> np.ndarray:
        """Parameter t of the first point in [t0, t1] with gap ≤ touch_m; NaN if none.

        Steps are gap / rate (never past a crossing) but at least ``min_step_m``; with
        ``touch_m = 0`` that minimum lets a sight line pass over a grazing point instead
        of creeping towards it.
        """
        # compiled (designer/core/csrc/terrain.c), ray by ray: [t0, t1] narrowed to where
        # the ray is over the grid and not above its highest point; the terrain's highest
        # point and steepest slope over that stretch (range maxima of the block tables)
        # narrow it further and give the rate; then up to max_iter steps: at p = O + t·d a
        # gap ≤ touch_m is a hit; a ray with rate ≤ 0 or at t1 ends without one; else
        # t += max(gap / rate, min_step_m), at most to t1
        org = np.ascontiguousarray(org, dtype=np.float64)
        d = np.ascontiguousarray(d, dtype=np.float64)
        t = np.array(t0, dtype=np.float64)
        t1 = np.array(t1, dtype=np.float64)
        hit = np.full(len(org), np.nan)
        going = np.zeros(len(org), dtype=np.uint8)
        tb = self._tables
        x0, x1, y0, y1 = self._box
        cterrain().cast(self._zf, self._nx, self._ny, self._x0, self._y0, self._dx, self._dy,
                        tb.top, tb.slope, tb.offset, tb.ncols, self._block, tb.nkx, tb.nky,
                        tb.top.size, x0, x1, y0, y1, self.z_max_m, org, d, t, t1,
                        float(touch_m), float(min_step_m), int(max_iter), hit, going)
        idx = np.flatnonzero(going)
        if idx.size:  # rays still grazing the terrain: finish them with the core's marching
            t = t[idx]
            start = org[idx] + t[:, None] * d[idx]
            p = self.heightfield.intersect_rays(start, d[idx], tol_m=max(touch_m, 1e-6))
            along = np.einsum("ij,ij->i", p - start, d[idx])
            ok = np.isfinite(along) & (t + along <= t1[idx])
            hit[idx[ok]] = (t + along)[ok]
        return hit


def raycaster_of(heightfield: Heightfield) -> TerrainRaycaster:
    """The ray caster of ``heightfield`` (default blocks), made once per height field
    object and kept on it: the window's stations, render estimate and plan figures cast
    over the same grown terrain after each edit."""
    rc = vars(heightfield).get("_raycaster")
    if rc is None:
        rc = TerrainRaycaster(heightfield)
        object.__setattr__(heightfield, "_raycaster", rc)  # a cache, not a field
    return rc


# ----------------------------------------------------------------------------- helpers
def _rays(origins, directions):
    org = np.asarray(origins, dtype=float).reshape(-1, 3)
    d = np.asarray(directions, dtype=float).reshape(-1, 3)
    org, d = np.broadcast_arrays(org, d)
    return org.copy(), d / np.linalg.norm(d, axis=1, keepdims=True)


def _block_reduce(a: np.ndarray, B: int, fill: float) -> np.ndarray:
    ny, nx = a.shape
    by, bx = -(-ny // B), -(-nx // B)
    padded = np.full((by * B, bx * B), fill)
    padded[:ny, :nx] = a
    return padded.reshape(by, B, bx, B).max(axis=(1, 3))


def _range_max_table(a: np.ndarray) -> dict[tuple[int, int], np.ndarray]:
    """Sparse table: T[kx, ky][i, j] = max of a[i:i + 2**ky, j:j + 2**kx]."""
    tables = {}
    cur_x, kx = a, 0
    while True:
        cur, ky = cur_x, 0
        while True:
            tables[(kx, ky)] = cur
            step = 1 << ky
            if cur.shape[0] <= step:
                break
            cur, ky = np.maximum(cur[:-step], cur[step:]), ky + 1
        step = 1 << kx
        if cur_x.shape[1] <= step:
            break
        cur_x, kx = np.maximum(cur_x[:, :-step], cur_x[:, step:]), kx + 1
    return tables


@dataclass(frozen=True)
class _Tables:
    """Both sparse tables of block maxima (:func:`_range_max_table`), each level after
    the other in one array, as the compiled ray cast reads them: level (kx, ky) starts at
    ``offset[kx * nky + ky]`` and has ``ncols[kx]`` columns."""

    top: np.ndarray
    slope: np.ndarray
    offset: np.ndarray
    ncols: np.ndarray
    nkx: int
    nky: int


def _flat_tables(top: dict, slope: dict) -> _Tables:
    nkx = 1 + max(kx for kx, _ in top)
    nky = 1 + max(ky for _, ky in top)
    keys = [(kx, ky) for kx in range(nkx) for ky in range(nky)]
    sizes = [top[k].size for k in keys]
    offset = np.concatenate([[0], np.cumsum(sizes)[:-1]]).astype(np.int64)
    ncols = np.array([top[(kx, 0)].shape[1] for kx in range(nkx)], dtype=np.int64)
    return _Tables(np.concatenate([top[k].ravel() for k in keys]),
                   np.concatenate([slope[k].ravel() for k in keys]), offset, ncols, nkx, nky)
