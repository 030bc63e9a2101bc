"""Error maps and histograms: nearest-neighbour gridding of per-point errors to a raster.

Axes are world easting and northing in metres. A grid cell takes the error of the
point nearest (in X, Y) to its centre, if that point is within ``max_gap_m``; otherwise
it is empty (NaN). Grids are stored north-up: row 0 is the northern edge, as GeoTIFF
and images expect. Files are written atomically; matplotlib (Agg canvas, no pyplot) and
rasterio are imported lazily.
"""

from __future__ import annotations

import math
import os
import re
import zlib
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from designer.atomic import atomic_path
from designer.core.bounds import column_bounds
from designer.errors import DesignerError

#: the largest grid side (cells) chosen automatically
MAX_CELLS_PER_SIDE = 2000
FIGURE_SIZE_IN = (7.5, 6.5)
DPI = 150
#: subplot margins (figure fractions) that fit the tick labels of UTM-sized coordinates
MAP_MARGINS = {"left": 0.14, "right": 0.97, "bottom": 0.12, "top": 0.94}
HISTOGRAM_MARGINS = {"left": 0.11, "right": 0.97, "bottom": 0.09, "top": 0.94}


@dataclass(frozen=True, eq=False)
class ErrorGrid:
    """``values`` (rows, cols) north-up; cell (i, j) covers easting
    [x_min + j·cell, x_min + (j+1)·cell) and northing (y_max − (i+1)·cell, y_max − i·cell]."""

    values: np.ndarray
    x_min: float
    y_max: float
    cell_m: float

    @property
    def extent(self) -> tuple[float, float, float, float]:
        """(x_min, x_max, y_min, y_max) in metres, for matplotlib's imshow."""
        rows, cols = self.values.shape
        return (self.x_min, self.x_min + cols * self.cell_m,
                self.y_max - rows * self.cell_m, self.y_max)


def _nice(value: float) -> float:
    """The smallest of 1, 2, 2.5, 5 × 10^k that is >= value."""
    exp = math.floor(math.log10(value))
    for m in (1, 2, 2.5, 5, 10):
        if m * 10**exp >= value * (1 - 1e-12):
            return m * 10**exp
    return 10 ** (exp + 1)


def auto_cell_size(xy: np.ndarray) -> float:
    """A cell size holding about two points per cell, at most MAX_CELLS_PER_SIDE cells."""
    lo, hi = column_bounds(xy)
    span = hi - lo
    area = max(float(span[0] * span[1]), 1e-6)
    cell = max(math.sqrt(2.0 * area / len(xy)), float(span.max()) / MAX_CELLS_PER_SIDE, 1e-3)
    return _nice(cell)


def grid_errors(xy_world, values, *, cell_m: float | None = None,
                max_gap_m: float | None = None) -> ErrorGrid:
    """Grid ``values`` (N,) at points ``xy_world`` (N, 2) by nearest neighbour.

    NaN values are ignored. ``cell_m`` defaults to :func:`auto_cell_size`; ``max_gap_m``
    (default 2 cells) is the farthest a point may be from a cell centre to fill it.
    """
    xy = np.asarray(xy_world, dtype=np.float64)[:, :2]
    values = np.asarray(values, dtype=np.float64)
    keep = np.isfinite(values)
    if not keep.all():  # a copy only when there is something to drop
        xy, values = xy[keep], values[keep]
    if len(xy) == 0:
        raise DesignerError("no finite errors to map")
    cell = auto_cell_size(xy) if cell_m is None else float(cell_m)
    if not cell > 0:
        raise DesignerError(f"cell size {cell_m} m: give a value > 0")
    gap = 2.0 * cell if max_gap_m is None else float(max_gap_m)
    lo, hi = column_bounds(xy)
    x_min = math.floor(lo[0] / cell) * cell
    y_max = math.ceil(hi[1] / cell) * cell
    cols = max(1, math.ceil((hi[0] - x_min) / cell) + (1 if hi[0] == x_min else 0))
    rows = max(1, math.ceil((y_max - lo[1]) / cell) + (1 if lo[1] == y_max else 0))
    if rows * cols > 25_000_000:
        raise DesignerError(f"error map of {cols} x {rows} cells at {cell:g} m is too large; "
                            "give a larger cell size")
    # local coordinates keep full precision at UTM size
    from designer.evaluate._grid import nearest_point_grid

    nearest = nearest_point_grid(np.ascontiguousarray(xy[:, 0] - x_min),
                                 np.ascontiguousarray(xy[:, 1] - y_max), rows, cols, cell, gap)
    grid = np.where(nearest >= 0, values[np.maximum(nearest, 0)], np.nan)
    return ErrorGrid(grid.reshape(rows, cols), float(x_min), float(y_max), float(cell))


def _figure():
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=FIGURE_SIZE_IN, dpi=DPI)
    FigureCanvasAgg(fig)
    return fig


def write_error_map_png(path: str | os.PathLike, grid: ErrorGrid, *,
                        limit_m: float | None = None, title: str = "Signed distance to the mesh",
                        label: str = "signed distance (m): + above / outside the mesh") -> Path:
    """Write ``grid`` as a PNG with a diverging colour bar symmetric about 0 (±``limit_m``,
    default the 95 % quantile of |value|); return the path."""
    finite = np.abs(grid.values[np.isfinite(grid.values)])
    if limit_m is None:
        limit_m = float(np.quantile(finite, 0.95)) if finite.size else 1.0
    limit_m = limit_m if limit_m > 0 else 1e-3
    fig = _figure()
    ax = fig.add_subplot()
    ax.set_facecolor("0.85")
    image = ax.imshow(np.ma.masked_invalid(grid.values), origin="upper", extent=grid.extent,
                      cmap="RdBu_r", vmin=-limit_m, vmax=limit_m, interpolation="nearest")
    cbar = fig.colorbar(image, ax=ax, extend="both", shrink=0.85)
    cbar.set_label(label)
    # y given: the title sits where matplotlib would put it (no ticks on top), without
    # measuring the axis' tight box on every draw (a fifth of the figure's time)
    ax.set_title(f"{title} ({grid.cell_m:g} m cells)", y=1.0)
    plan_axes(ax)
    fig.subplots_adjust(**MAP_MARGINS)  # fixed: tight_layout would draw the figure twice
    return _save(fig, path)


def plan_axes(ax) -> None:
    """Label a plan map's axes: easting and northing in metres, written out in full (no
    offset), equal scales, the eastings turned to stay apart."""
    ax.set_xlabel("easting (m)")
    ax.set_ylabel("northing (m)")
    ax.ticklabel_format(useOffset=False, style="plain")
    ax.set_aspect("equal")
    for tick in ax.get_xticklabels():
        tick.set_rotation(30)


def write_histogram_png(path: str | os.PathLike, stats: dict, *,
                        title: str = "Signed distances",
                        xlabel: str = "signed distance (m)") -> Path:
    """Histogram from :func:`distance_statistics` output, with mean, median and ±NMAD."""
    h = stats["histogram"]
    edges = np.asarray(h["edges"])
    fig = _figure()
    ax = fig.add_subplot()
    # one filled outline, not a patch per bar: the same picture, drawn in a fraction
    ax.stairs(h["counts"], edges, fill=True, color="#4477aa")
    for x, style, name in ((stats["mean"], "-", "mean"), (stats["median"], "--", "median")):
        ax.axvline(x, color="black", linestyle=style, linewidth=1, label=f"{name} {x:.4f} m")
    for sign in (-1, 1):
        ax.axvline(stats["median"] + sign * stats["nmad"], color="#cc6677", linestyle=":",
                   label=f"median ± NMAD ({stats['nmad']:.4f} m)" if sign > 0 else None)
    ax.set_xlabel(xlabel)
    ax.set_ylabel("count")
    outside = h["below"] + h["above"]
    note = f"; {outside} outside the plotted range" if outside else ""
    ax.set_title(f"{title}: n = {stats['n']}, RMSE {stats['rmse']:.4f} m{note}", fontsize=10,
                 y=1.0)  # placed as matplotlib would, without measuring (see above)
    ax.legend(fontsize=8)
    fig.subplots_adjust(**HISTOGRAM_MARGINS)
    return _save(fig, path)


def _save(fig, path) -> Path:
    path = Path(path)
    with atomic_path(path) as tmp:
        # fast zlib level and run-length matching: a third of the encoding time of the
        # default for a few percent more bytes (lossless either way)
        fig.savefig(tmp, format="png", pil_kwargs={"compress_level": 1,
                                                   "compress_type": zlib.Z_RLE})
    return path


def write_error_map_geotiff(path: str | os.PathLike, grid: ErrorGrid,
                            crs: str | None = None) -> Path:
    """Write ``grid`` as a float32 GeoTIFF (NaN = no data), in ``crs`` when it is one
    rasterio understands (EPSG:n, WKT, PROJ); return the path."""
    import rasterio
    from rasterio.errors import CRSError
    from rasterio.transform import from_origin

    crs_obj = None
    if crs:
        # project files write e.g. "EPSG:32632 (WGS 84 / UTM zone 32N)"
        epsg = re.match(r"\s*EPSG:\s*(\d+)", crs, re.IGNORECASE)
        try:
            crs_obj = rasterio.crs.CRS.from_user_input(f"EPSG:{epsg[1]}" if epsg else crs)
        except (CRSError, ValueError):
            crs_obj = None  # a free-text CRS still gets a georeferenced grid
    rows, cols = grid.values.shape
    path = Path(path)
    with atomic_path(path) as tmp:
        with rasterio.open(tmp, "w", driver="GTiff", width=cols, height=rows, count=1,
                           dtype="float32", nodata=float("nan"), crs=crs_obj,
                           transform=from_origin(grid.x_min, grid.y_max, grid.cell_m,
                                                 grid.cell_m)) as dst:
            dst.write(grid.values.astype(np.float32), 1)
            dst.update_tags(units="m", description="signed distance, nearest-neighbour grid")
    return path


def write_error_map_npy(path: str | os.PathLike, grid: ErrorGrid) -> Path:
    """Write the grid values (float64, north-up) as .npy; geo-reference goes in the
    summary (x_min, y_max, cell_m)."""
    path = Path(path)
    with atomic_path(path) as tmp, open(tmp, "wb") as fh:
        np.save(fh, grid.values)
    return path
