"""Raster products: DSM from a point cloud, the true surface, DEM of difference, dome fit.

World frame X east, Y north, Z up, metres. A :class:`RasterGrid` is north-up: cell
(row i, column j) covers easting [x_min + j·cell, x_min + (j+1)·cell) and northing
(y_max − (i+1)·cell, y_max − i·cell]; its value belongs to the cell centre. Missing
values are NaN (GeoTIFF nodata NaN). Grid arithmetic runs in coordinates local to the
grid corner, so UTM-sized coordinates keep full float64 precision.

* :func:`dsm_from_points` — the **median** height of the points in each cell. A DSM
  compared with the truth should not be biased by matching noise: the maximum (the
  lidar "first return" convention) moves up with the noise spread and the number of
  points per cell (≈ +1.5 σ for 10 points), the median does not, and it ignores the
  isolated blunders dense matching leaves above and below the surface.
* :func:`surface_raster` — the true mesh on the same grid: the height where a ray cast
  down at each cell centre first meets the mesh (its highest triangle there).
* :func:`dem_of_difference` — DSM − true surface, and :func:`fit_dome` — a quadratic
  surface fitted to it, whose peak-to-edge amplitude measures the dome (positive) or
  bowl (negative) a poorly calibrated camera puts into a nadir block.

Writers (GeoTIFF, PNG) and :func:`write_raster_products` are in :mod:`.raster_products`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from designer.errors import DesignerError

#: the most cells a raster may have (a 5000 x 5000 grid)
MAX_CELLS = 25_000_000


@dataclass(frozen=True)
class RasterGrid:
    """Geometry of a north-up grid: top-left corner (``x_min``, ``y_max``) in world
    metres, square cells of ``cell_m``, ``rows`` × ``cols``."""

    x_min: float
    y_max: float
    cell_m: float
    rows: int
    cols: int

    @classmethod
    def from_bounds(cls, bounds, cell_m: float) -> RasterGrid:
        """The grid of ``cell_m`` cells covering ``bounds`` (x_min, y_min, x_max, y_max),
        with its corner snapped outward to a multiple of the cell size."""
        x0, y0, x1, y1 = (float(v) for v in bounds)
        cell = float(cell_m)
        if not (cell > 0 and math.isfinite(cell)):
            raise DesignerError(f"cell size {cell_m} m: give a value > 0")
        if not (x1 > x0 and y1 > y0) or not all(map(math.isfinite, (x0, y0, x1, y1))):
            raise DesignerError(f"raster bounds {bounds}: need x_min < x_max and "
                                "y_min < y_max (metres)")
        x_min, y_max = math.floor(x0 / cell) * cell, math.ceil(y1 / cell) * cell
        cols = max(1, math.ceil((x1 - x_min) / cell - 1e-9))
        rows = max(1, math.ceil((y_max - y0) / cell - 1e-9))
        if rows * cols > MAX_CELLS:
            raise DesignerError(f"raster of {cols} x {rows} cells at {cell:g} m is too large; "
                                "give a larger cell size")
        return cls(x_min, y_max, cell, rows, cols)

    @property
    def shape(self) -> tuple[int, int]:
        return self.rows, self.cols

    @property
    def extent(self) -> tuple[float, float, float, float]:
        """(x_min, x_max, y_min, y_max), for matplotlib's imshow."""
        return (self.x_min, self.x_min + self.cols * self.cell_m,
                self.y_max - self.rows * self.cell_m, self.y_max)

    def centres_local(self) -> tuple[np.ndarray, np.ndarray]:
        """Cell-centre offsets (cols,) east of x_min and (rows,) north of y_max (≤ 0)."""
        return ((np.arange(self.cols) + 0.5) * self.cell_m,
                -(np.arange(self.rows) + 0.5) * self.cell_m)

    def centres_world(self) -> tuple[np.ndarray, np.ndarray]:
        """Cell-centre eastings (cols,) and northings (rows,), float64."""
        x, y = self.centres_local()
        return self.x_min + x, self.y_max + y


@dataclass(frozen=True, eq=False)
class Raster:
    """``values`` (rows, cols) float64 on ``grid``; NaN where there is no value."""

    values: np.ndarray
    grid: RasterGrid

    @property
    def valid(self) -> np.ndarray:
        return np.isfinite(self.values)


@dataclass(frozen=True)
class DomeFit:
    """A quadratic fitted to a DoD: ``amplitude_m`` peak-to-edge (dome > 0, bowl < 0),
    ``amplitude_gsd`` the same in GSD (None without a GSD), ``kind`` "dome", "bowl" or
    "saddle", ``coefficients`` (a0, ax, ay, axx, axy, ayy) of
    z = a0 + ax·u + ay·v + axx·u² + axy·u·v + ayy·v² with (u, v) metres from
    ``centre_world`` (the valid area's centroid), the fitted surface's extreme point
    ``peak_world`` (E, N), the RMS of the DoD around the fit and the cells used."""

    amplitude_m: float
    amplitude_gsd: float | None
    kind: str
    coefficients: tuple[float, ...]
    centre_world: tuple[float, float]
    peak_world: tuple[float, float]
    rms_residual_m: float
    n_cells: int

    def evaluate_local(self, u_m, v_m) -> np.ndarray:
        a0, ax, ay, axx, axy, ayy = self.coefficients
        u, v = np.asarray(u_m, float), np.asarray(v_m, float)
        return a0 + ax * u + ay * v + axx * u * u + axy * u * v + ayy * v * v


def _points_array(points_world) -> np.ndarray:
    p = np.asarray(points_world, dtype=np.float64)
    if p.ndim != 2 or p.shape[1] < 3:
        raise DesignerError(f"points must have shape (N, 3), got {p.shape}")
    return p[:, :3]


def dsm_from_points(points_world, cell_m: float, bounds=None, *,
                    statistic: str = "median", min_points: int = 1) -> Raster:
    """DSM (median Z per cell; ``statistic`` "max" or "mean" on request) of
    ``points_world`` (N, 3) on the grid covering ``bounds`` (x_min, y_min, x_max, y_max;
    default the points' extent). Cells with fewer than ``min_points`` points are NaN."""
    p = _points_array(points_world)
    p = p[np.isfinite(p).all(axis=1)]
    if len(p) == 0:
        raise DesignerError("DSM: the point cloud is empty (no finite point); the dense "
                            "matching produced nothing to grid")
    if statistic not in ("median", "max", "mean"):
        raise DesignerError(f"DSM statistic {statistic!r}: use median, max or mean")
    if bounds is None:
        lo, hi = p[:, :2].min(axis=0), p[:, :2].max(axis=0)
        hi = np.maximum(hi, lo + float(cell_m))
        bounds = (lo[0], lo[1], hi[0], hi[1])
    grid = RasterGrid.from_bounds(bounds, cell_m)
    col = np.floor((p[:, 0] - grid.x_min) / grid.cell_m).astype(np.int64)
    row = np.floor((grid.y_max - p[:, 1]) / grid.cell_m).astype(np.int64)
    inside = (col >= 0) & (col < grid.cols) & (row >= 0) & (row < grid.rows)
    cell = row[inside] * grid.cols + col[inside]
    z = p[inside, 2]
    n_cells = grid.rows * grid.cols
    count = np.bincount(cell, minlength=n_cells)
    out = np.full(n_cells, np.nan)
    filled = count >= max(1, int(min_points))
    if statistic == "mean":
        out[filled] = (np.bincount(cell, weights=z, minlength=n_cells)[filled]
                       / count[filled])
    else:
        order = np.lexsort((z, cell))
        z_sorted = z[order]
        start = np.concatenate([[0], np.cumsum(count)[:-1]])
        n, s = count[filled], start[filled]
        if statistic == "max":
            out[filled] = z_sorted[s + n - 1]
        else:
            out[filled] = 0.5 * (z_sorted[s + (n - 1) // 2] + z_sorted[s + n // 2])
    return Raster(out.reshape(grid.shape), grid)


def surface_raster(vertices_world, faces, grid: RasterGrid) -> Raster:
    """The true surface on ``grid``: at each cell centre, the height of the highest
    triangle of the mesh (``vertices_world`` (V, 3), ``faces`` (M, 3)) there, as a ray
    cast straight down meets it; NaN outside the mesh."""
    from designer.evaluate._rasterise import highest_surface
    from designer.evaluate.distance import _mesh_arrays

    vertices, faces = _mesh_arrays((vertices_world, faces))
    xy = np.column_stack([vertices[:, 0] - grid.x_min, grid.y_max - vertices[:, 1]])
    heights = highest_surface(np.ascontiguousarray(xy), np.ascontiguousarray(vertices[:, 2]),
                              np.ascontiguousarray(faces, dtype=np.int64),
                              float(grid.cell_m), grid.rows, grid.cols)
    return Raster(heights, grid)


def dem_of_difference(dsm: Raster, surface: Raster) -> Raster:
    """DSM − true surface (metres, positive where the DSM is too high), NaN where either
    is missing."""
    if dsm.grid != surface.grid:
        raise DesignerError("DoD: the DSM and the true surface are on different grids; "
                            "rasterise the surface on the DSM's grid")
    if not dsm.valid.any():
        raise DesignerError("DoD: the DSM has no valid cell (all NaN): no point fell in the "
                            "raster, or the cell size is smaller than the point spacing")
    dod = dsm.values - surface.values
    if not np.isfinite(dod).any():
        raise DesignerError("DoD: the DSM and the true surface share no valid cell; "
                            "check that the cloud and the mesh are in the same coordinates")
    return Raster(dod, dsm.grid)


def fit_dome(dod: Raster, gsd_m: float | None = None) -> DomeFit:
    """Fit z = quadratic(u, v) to the valid DoD cells (least squares) and measure its
    amplitude: the fitted quadratic part at its extreme point within the valid area
    minus its mean over the valid area's edge cells (a planar tilt of the DoD does not
    count). Dome (highest in the middle) is positive, bowl negative; a saddle gets the
    sign of the larger curvature."""
    valid = dod.valid
    n = int(valid.sum())
    if n < 6:
        raise DesignerError(f"dome fit: the DoD has {n} valid cells; at least 6 are needed "
                            "(the DSM is nearly empty)")
    x, y = dod.grid.centres_local()
    X, Y = np.meshgrid(x, y)
    cu, cv = float(X[valid].mean()), float(Y[valid].mean())
    U, V = X - cu, Y - cv
    u, v, z = U[valid], V[valid], dod.values[valid]
    scale = max(float(np.abs(u).max()), float(np.abs(v).max()), dod.grid.cell_m)
    us, vs = u / scale, v / scale  # well-conditioned design matrix
    A = np.column_stack([np.ones(n), us, vs, us * us, us * vs, vs * vs])
    coef, *_ = np.linalg.lstsq(A, z, rcond=None)
    rms = float(np.sqrt(np.mean((A @ coef - z) ** 2)))
    coef = coef / np.array([1, scale, scale, scale**2, scale**2, scale**2])
    a0, ax, ay, axx, axy, ayy = (float(c) for c in coef)
    quad = axx * U * U + axy * U * V + ayy * V * V
    # Remove the quadratic part's own best plane over the valid cells: only curvature
    # is dome; a tilt is a different error.
    B = np.column_stack([np.ones(n), us, vs])
    plane, *_ = np.linalg.lstsq(B, quad[valid], rcond=None)
    shape = np.full(quad.shape, np.nan)
    shape[valid] = quad[valid] - B @ plane
    edge = _edge_cells(valid)
    H = np.array([[2 * axx, axy], [axy, 2 * ayy]])
    eig = np.linalg.eigvalsh(H)
    kind = "dome" if eig.max() < 0 else "bowl" if eig.min() > 0 else "saddle"
    if kind == "saddle":
        dome_sign = 1.0 if -eig.min() >= eig.max() else -1.0
    else:
        dome_sign = 1.0 if kind == "dome" else -1.0
    k = int(np.nanargmax(dome_sign * shape))
    amplitude = float(shape.flat[k] - np.mean(shape[edge]))
    peak = (dod.grid.x_min + float(X.flat[k]), dod.grid.y_max + float(Y.flat[k]))
    return DomeFit(
        amplitude_m=amplitude,
        amplitude_gsd=None if not gsd_m else amplitude / float(gsd_m),
        kind=kind, coefficients=(a0, ax, ay, axx, axy, ayy),
        centre_world=(dod.grid.x_min + cu, dod.grid.y_max + cv), peak_world=peak,
        rms_residual_m=rms, n_cells=n)


def _edge_cells(valid: np.ndarray) -> np.ndarray:
    """Valid cells with an invalid (or off-grid) 4-neighbour."""
    padded = np.pad(valid, 1, constant_values=False)
    inner = padded[:-2, 1:-1] & padded[2:, 1:-1] & padded[1:-1, :-2] & padded[1:-1, 2:]
    edge = valid & ~inner
    return edge if edge.any() else valid
