"""A regular-grid height field (a DEM) and ray intersection with it.

World frame: X east, Y north, Z up, metres. Grid node (row i, column j) lies at
``X = x0_m + j·dx_m``, ``Y = y0_m + i·dy_m`` (rows go north), height ``heights_m[i, j]``;
between nodes the surface is bilinear.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from designer.errors import DesignerError


@dataclass(frozen=True, eq=False)
class Heightfield:
    """Terrain heights on a regular grid (see module docstring for the layout)."""

    x0_m: float
    y0_m: float
    dx_m: float
    dy_m: float
    heights_m: np.ndarray

    def __post_init__(self) -> None:
        z = np.asarray(self.heights_m, dtype=float)
        if z.ndim != 2 or min(z.shape) < 2:
            raise DesignerError(
                f"height field must be a 2-D grid of at least 2 x 2, got {z.shape}")
        if not (self.dx_m > 0 and self.dy_m > 0):
            raise DesignerError("height field spacing dx_m and dy_m must be > 0")
        if not np.all(np.isfinite(z)):
            raise DesignerError("height field has NaN or infinite heights; fill the voids first")
        object.__setattr__(self, "heights_m", z)

    @property
    def extent_m(self) -> tuple[float, float, float, float]:
        """(x_min, x_max, y_min, y_max) of the grid."""
        ny, nx = self.heights_m.shape
        return (self.x0_m, self.x0_m + (nx - 1) * self.dx_m,
                self.y0_m, self.y0_m + (ny - 1) * self.dy_m)

    def contains(self, x_m, y_m) -> np.ndarray:
        """True where (x, y) lies inside the grid extent."""
        x0, x1, y0, y1 = self.extent_m
        x, y = np.asarray(x_m, dtype=float), np.asarray(y_m, dtype=float)
        return (x >= x0) & (x <= x1) & (y >= y0) & (y <= y1)

    def height_at(self, x_m, y_m) -> np.ndarray:
        """Bilinear height at (x, y); NaN outside the grid."""
        x, y = np.broadcast_arrays(np.asarray(x_m, dtype=float), np.asarray(y_m, dtype=float))
        return np.where(self.contains(x, y), self.height_at_clamped(x, y), np.nan)

    def height_at_clamped(self, x_m, y_m) -> np.ndarray:
        """Bilinear height with (x, y) clamped onto the grid: the edge heights extend
        outwards. Ray marching uses it so a crossing just inside an edge is not lost."""
        x, y = np.broadcast_arrays(np.asarray(x_m, dtype=float), np.asarray(y_m, dtype=float))
        ny, nx = self.heights_m.shape
        fx = np.clip((x - self.x0_m) / self.dx_m, 0, nx - 1)
        fy = np.clip((y - self.y0_m) / self.dy_m, 0, ny - 1)
        fx = np.where(np.isfinite(fx), fx, 0.0)
        fy = np.where(np.isfinite(fy), fy, 0.0)
        j = np.minimum(fx.astype(int), nx - 2)
        i = np.minimum(fy.astype(int), ny - 2)
        tx, ty = fx - j, fy - i
        z = self.heights_m
        return ((z[i, j] * (1 - tx) + z[i, j + 1] * tx) * (1 - ty)
                + (z[i + 1, j] * (1 - tx) + z[i + 1, j + 1] * tx) * ty)

    def intersect_rays(
        self,
        origins_world: np.ndarray,
        directions_world: np.ndarray,
        tol_m: float = 1e-6,
        max_range_m: float | None = None,
    ) -> np.ndarray:
        """First intersection of rays with the surface → (N, 3); NaN where a ray misses.

        Marches each ray in steps of half a grid cell from where it enters the height
        band [min, max] of the terrain, then refines the first sign change of
        ``Z_ray − height`` by bisection to ``tol_m``. Heights are evaluated with the edge
        values extended outwards, and a crossing that lies outside the grid counts as a
        miss. Steps of half a cell can step over a ridge thinner than that only when the
        ray grazes it.
        """
        origins = np.asarray(origins_world, dtype=float).reshape(-1, 3)
        dirs = np.asarray(directions_world, dtype=float).reshape(-1, 3)
        origins, dirs = np.broadcast_arrays(origins, dirs)
        dirs = dirs / np.linalg.norm(dirs, axis=1, keepdims=True)
        z_lo, z_hi = float(self.heights_m.min()), float(self.heights_m.max())
        x0, x1, y0, y1 = self.extent_m
        step = 0.5 * min(self.dx_m, self.dy_m)
        diag = float(np.hypot(x1 - x0, y1 - y0) + (z_hi - z_lo))

        # Parameter range in which the ray is inside the height band.
        with np.errstate(divide="ignore", invalid="ignore"):
            t_a = (z_hi - origins[:, 2]) / dirs[:, 2]
            t_b = (z_lo - origins[:, 2]) / dirs[:, 2]
        flat = dirs[:, 2] == 0
        inband = (origins[:, 2] >= z_lo) & (origins[:, 2] <= z_hi)
        t_start = np.where(flat, np.where(inband, 0.0, np.inf), np.minimum(t_a, t_b))
        t_stop = np.where(flat, np.where(inband, np.inf, -np.inf), np.maximum(t_a, t_b))
        t_start = np.maximum(t_start, 0.0)
        t_stop = np.minimum(t_stop, t_start + diag + step)
        # no hit lies farther than the box's farthest corner: a nearly horizontal ray
        # (z ~ 1e-17) would otherwise enter the band at t ~ 1e17, where a step of half a
        # cell no longer changes t and the march never ends
        far = np.sqrt(sum(np.maximum((lo - origins[:, k]) ** 2, (hi - origins[:, k]) ** 2)
                          for k, (lo, hi) in enumerate(((x0, x1), (y0, y1), (z_lo, z_hi)))))
        t_stop = np.minimum(t_stop, far)
        if max_range_m is not None:
            t_stop = np.minimum(t_stop, max_range_m)

        def gap(t, idx):
            p = origins[idx] + t[:, None] * dirs[idx]
            return p[:, 2] - self.height_at_clamped(p[:, 0], p[:, 1])

        hit_t = np.full(len(origins), np.nan)
        active = np.flatnonzero(t_start <= t_stop)
        t_prev = t_start[active]
        g_prev = gap(t_prev, active)
        starts_below = g_prev <= 0
        hit_t[active[starts_below]] = t_prev[starts_below]
        keep = ~starts_below
        active, t_prev, g_prev = active[keep], t_prev[keep], g_prev[keep]
        while active.size:
            t_next = np.minimum(t_prev + step, t_stop[active])
            g_next = gap(t_next, active)
            crossed = g_next <= 0
            if crossed.any():
                hit_t[active[crossed]] = _bisect(
                    gap, active[crossed], t_prev[crossed], t_next[crossed], tol_m
                )
            cont = ~crossed & (t_next < t_stop[active])
            active, t_prev, g_prev = active[cont], t_next[cont], g_next[cont]
        hits = origins + hit_t[:, None] * dirs
        x0, x1, y0, y1 = self.extent_m
        eps = 1e-9 * max(1.0, abs(x0), abs(x1), abs(y0), abs(y1))
        outside = ~((hits[:, 0] >= x0 - eps) & (hits[:, 0] <= x1 + eps)
                    & (hits[:, 1] >= y0 - eps) & (hits[:, 1] <= y1 + eps))
        hits[outside] = np.nan
        return hits


def _bisect(gap, idx, t_lo, t_hi, tol_m):
    t_lo, t_hi = t_lo.copy(), t_hi.copy()
    while np.any(t_hi - t_lo > tol_m):
        mid = 0.5 * (t_lo + t_hi)
        below = gap(mid, idx) <= 0
        t_hi = np.where(below, mid, t_hi)
        t_lo = np.where(below, t_lo, mid)
    return t_hi
