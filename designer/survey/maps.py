"""PNG maps of a plan's coverage count and GSD (matplotlib, imported lazily).

Axes are world easting and northing in metres (plain numbers, no offset, so UTM
coordinates read as they are). Cells outside the survey area are drawn grey; the
area's outline and, optionally, the stations are drawn on top. Files are written
atomically (a temporary file, then a rename) and never through pyplot, so no global
matplotlib state (backend, open figures) is touched.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from designer.atomic import atomic_path
from designer.survey.coverage import CoverageMap

#: figure size (inches) and resolution of the written maps
FIGURE_SIZE_IN = (7.5, 6.5)
DPI = 150


def write_coverage_map(
    path: str | os.PathLike,
    coverage: CoverageMap,
    *,
    area=None,
    stations_xy: np.ndarray | None = None,
    title: str = "Coverage: images that see each ground cell",
) -> Path:
    """Write the coverage-count map (one colour per count) to a PNG file; return its path."""
    from matplotlib.colors import BoundaryNorm

    count = coverage.count.astype(float)
    top = max(1, int(count[coverage.grid.inside_area].max(initial=0)))
    bounds = np.arange(-0.5, top + 1.5)
    return _write(path, coverage, np.where(coverage.grid.inside_area, count, np.nan),
                  title=title, cbar_label="images seeing the cell (count)", cmap="viridis",
                  norm=BoundaryNorm(bounds, 256), area=area, stations_xy=stations_xy,
                  ticks=_count_ticks(top))


def write_gsd_map(
    path: str | os.PathLike,
    coverage: CoverageMap,
    *,
    area=None,
    stations_xy: np.ndarray | None = None,
    statistic: str = "mean",
    title: str | None = None,
) -> Path:
    """Write the GSD map (cm/px; ``statistic`` "mean" or "min" over the images that
    see the cell) to a PNG file; return its path."""
    if statistic not in ("mean", "min"):
        raise ValueError(f"statistic must be 'mean' or 'min', got {statistic!r}")
    gsd = coverage.gsd_mean_m if statistic == "mean" else coverage.gsd_min_m
    values = np.where(coverage.grid.inside_area, gsd * 100.0, np.nan)
    title = title or f"Ground sample distance ({statistic} over the images seeing the cell)"
    return _write(path, coverage, values, title=title, cbar_label="GSD (cm/px)",
                  cmap="magma_r", norm=None, area=area, stations_xy=stations_xy, ticks=None)


def _write(path, coverage, values, *, title, cbar_label, cmap, norm, area, stations_xy, ticks):
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=FIGURE_SIZE_IN, dpi=DPI)
    FigureCanvasAgg(fig)
    ax = fig.add_subplot()
    ax.set_facecolor("0.85")
    image = ax.imshow(np.ma.masked_invalid(values), origin="lower",
                      extent=coverage.grid.extent_m, cmap=cmap, norm=norm,
                      interpolation="nearest")
    if area is not None:
        poly = np.asarray(area, dtype=float)
        closed = np.vstack([poly, poly[:1]])
        ax.plot(closed[:, 0], closed[:, 1], color="white", linewidth=1.5)
        ax.plot(closed[:, 0], closed[:, 1], color="black", linewidth=0.7)
    if stations_xy is not None and len(stations_xy):
        xy = np.asarray(stations_xy, dtype=float)
        ax.plot(xy[:, 0], xy[:, 1], ".", color="red", markersize=1.5, label="stations")
        ax.legend(loc="upper right", fontsize="small")
    ax.set_title(title)
    ax.set_xlabel("easting X (m)")
    ax.set_ylabel("northing Y (m)")
    ax.ticklabel_format(useOffset=False, style="plain")
    ax.set_aspect("equal")
    bar = fig.colorbar(image, ax=ax, ticks=ticks)
    bar.set_label(cbar_label)
    fig.tight_layout()
    path = Path(path)
    with atomic_path(path) as tmp:
        fig.savefig(tmp, format="png")
    return path


def _count_ticks(top: int) -> np.ndarray:
    step = max(1, int(np.ceil((top + 1) / 12)))
    return np.arange(0, top + 1, step)
