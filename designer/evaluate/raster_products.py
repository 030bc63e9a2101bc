"""Raster files: GeoTIFFs of DSM, true surface and DoD, DoD map and profile PNGs.

:func:`write_raster_products` is the one call a processing run makes: cloud and true
mesh in, ``dsm.tif``, ``surface.tif``, ``dod.tif``, ``dod.png`` and ``dod_profile.png``
out, plus a summary dict (dome amplitude, DoD median / NMAD / RMSE, coverage).
GeoTIFFs are in the project's CRS (an EPSG code, ``"EPSG:n"`` with optional trailing
text as project files write it, or WKT), north-up, NaN nodata. Heights (DSM, surface)
are stored as float64 so that 0.1 mm survives any terrain height; the DoD as float32.
Every file is written atomically; rasterio and matplotlib load on first use.
"""

from __future__ import annotations

import os
import re
from pathlib import Path

import numpy as np

from designer.atomic import atomic_path
from designer.errors import DesignerError
from designer.evaluate.maps import plan_axes
from designer.evaluate.rasters import (
    DomeFit,
    Raster,
    dem_of_difference,
    dsm_from_points,
    fit_dome,
    surface_raster,
)

NMAD_FACTOR = 1.4826


def crs_from_user(crs):
    """A rasterio CRS from an EPSG code (int), ``"EPSG:n ..."`` or WKT/PROJ text; None
    for None. Anything else is a :class:`DesignerError` naming the accepted forms."""
    import rasterio.crs
    from rasterio.errors import CRSError

    if crs is None or (isinstance(crs, str) and not crs.strip()):
        return None
    try:
        if isinstance(crs, (int, np.integer)):
            return rasterio.crs.CRS.from_epsg(int(crs))
        epsg = re.match(r"\s*EPSG:\s*(\d+)", str(crs), re.IGNORECASE)
        return rasterio.crs.CRS.from_user_input(f"EPSG:{epsg[1]}" if epsg else str(crs))
    except (CRSError, ValueError) as exc:
        raise DesignerError(f"CRS {crs!r} is not one GDAL knows ({exc}); give an EPSG code "
                            "(e.g. EPSG:32632) or WKT") from None


def write_geotiff(path: str | os.PathLike, raster: Raster, crs=None, *,
                  dtype: str = "float64", description: str = "") -> Path:
    """Write ``raster`` as a single-band GeoTIFF (NaN nodata) in ``crs``; return the path."""
    import rasterio
    from rasterio.transform import from_origin

    crs_obj = crs_from_user(crs)
    g = raster.grid
    path = Path(path)
    with atomic_path(path) as tmp:
        with rasterio.open(tmp, "w", driver="GTiff", width=g.cols, height=g.rows, count=1,
                           dtype=dtype, nodata=float("nan"), crs=crs_obj, compress="deflate",
                           transform=from_origin(g.x_min, g.y_max, g.cell_m, g.cell_m)) as dst:
            dst.write(raster.values.astype(dtype), 1)
            dst.update_tags(units="m", description=description)
    return path


def dod_statistics(dod: Raster, surface: Raster) -> dict:
    """Median, NMAD, RMSE, mean of the DoD (m) and coverage: the share of cells with a
    true surface that have a DoD value."""
    d = dod.values[dod.valid]
    median = float(np.median(d))
    return {"n_cells": int(d.size), "median_m": median,
            "nmad_m": NMAD_FACTOR * float(np.median(np.abs(d - median))),
            "rmse_m": float(np.sqrt(np.mean(d * d))), "mean_m": float(np.mean(d)),
            "coverage": float(d.size / max(int(surface.valid.sum()), 1))}


def _figure(size_in=(7.5, 6.5)):
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=size_in, dpi=150)
    FigureCanvasAgg(fig)
    return fig


def _save(fig, path) -> Path:
    path = Path(path)
    with atomic_path(path) as tmp:
        fig.savefig(tmp, format="png")
    return path


def _limit(dod: Raster) -> float:
    d = np.abs(dod.values[dod.valid])
    limit = float(np.quantile(d, 0.98)) if d.size else 0.0
    return limit if limit > 0 else 1e-3


def write_dod_png(path, dod: Raster, dome: DomeFit | None = None, stats: dict | None = None,
                  gsd_m: float | None = None, dome_area_world=None) -> Path:
    """DoD map: diverging colours symmetric about 0 (±98 % quantile of |DoD|), colour
    bar, the statistics and the dome amplitude in the title; ``dome_area_world``: the
    polygon the dome was fitted over, outlined."""
    limit = _limit(dod)
    fig = _figure()
    ax = fig.add_subplot()
    ax.set_facecolor("0.85")
    image = ax.imshow(np.ma.masked_invalid(dod.values), origin="upper",
                      extent=dod.grid.extent, cmap="RdBu_r", vmin=-limit, vmax=limit,
                      interpolation="nearest")
    fig.colorbar(image, ax=ax, extend="both", shrink=0.85).set_label(
        "DSM − true surface (m): + DSM too high")
    title = f"DEM of difference ({dod.grid.cell_m:g} m cells)"
    if stats:
        title += f"\nmedian {stats['median_m']:+.4f} m, NMAD {stats['nmad_m']:.4f} m"
    if dome is not None:
        gsd = f" = {dome.amplitude_gsd:+.2f} GSD" if dome.amplitude_gsd is not None else ""
        title += f", {dome.kind} {dome.amplitude_m:+.4f} m{gsd}"
        if dome_area_world is not None:
            title += " over the survey area (outlined)"
            ring = np.vstack([dome_area_world, dome_area_world[:1]])
            ax.plot(ring[:, 0], ring[:, 1], "-", color="k", lw=0.8)
    ax.set_title(title, fontsize=10)
    plan_axes(ax)
    fig.tight_layout()
    return _save(fig, path)


def write_dod_profile_png(path, dod: Raster, dome: DomeFit | None = None) -> Path:
    """DoD along the west–east and south–north lines through the dome fit's centre
    (or the raster's centre), with the fitted quadratic along the same lines."""
    g = dod.grid
    xs, ys = g.centres_world()
    cx, cy = dome.centre_world if dome is not None else (xs.mean(), ys.mean())
    i = int(np.clip(np.floor((g.y_max - cy) / g.cell_m), 0, g.rows - 1))
    j = int(np.clip(np.floor((cx - g.x_min) / g.cell_m), 0, g.cols - 1))
    fig = _figure((8.0, 6.0))
    lines = (("west–east", xs - xs[0], dod.values[i, :], xs - cx, np.full(g.cols, ys[i] - cy),
              f"northing {ys[i]:.2f} m"),
             ("south–north", ys[::-1] - ys[-1], dod.values[::-1, j],
              np.full(g.rows, xs[j] - cx), ys[::-1] - cy, f"easting {xs[j]:.2f} m"))
    for k, (name, s, values, u, v, where) in enumerate(lines):
        ax = fig.add_subplot(2, 1, k + 1)
        ax.axhline(0.0, color="0.6", linewidth=0.8)
        ax.plot(s, values, ".", markersize=2, color="#4477aa", label="DoD")
        if dome is not None:
            ax.plot(s, dome.evaluate_local(u, v), "-", color="#cc6677",
                    label=f"quadratic fit ({dome.kind} {dome.amplitude_m:+.4f} m)")
        ax.set_title(f"DoD profile {name} at {where}", fontsize=9)
        ax.set_xlabel("distance along the profile (m)")
        ax.set_ylabel("DSM − truth (m)")
        ax.legend(fontsize=7, loc="best")
    fig.tight_layout()
    return _save(fig, path)


#: fewest DoD cells inside the survey area for the dome to be fitted there
MIN_DOME_CELLS = 36


def _cells_inside(grid, polygon_world: np.ndarray) -> np.ndarray:
    """(rows, cols) mask of the cells of ``grid`` whose centre lies in the polygon."""
    from designer.scene.buildings import points_in_polygon

    x, y = grid.centres_local()
    X, Y = np.meshgrid(x, y)
    origin = polygon_world[0]
    return points_in_polygon(X + (grid.x_min - origin[0]), Y + (grid.y_max - origin[1]),
                             polygon_world - origin)


def _dome_dict(dome) -> dict:
    return {"kind": dome.kind, "amplitude_m": dome.amplitude_m,
            "amplitude_gsd": dome.amplitude_gsd, "peak_world": list(dome.peak_world),
            "rms_residual_m": dome.rms_residual_m, "cells": dome.n_cells}


def dome_over_area(dod: Raster, gsd_m: float | None, survey_area_world=None):
    """(dome fit, the area it covers: "the survey area" or "the whole DoD") of ``dod``:
    over the cells inside ``survey_area_world`` ((K, 2) world polygon) when there are
    at least :data:`MIN_DOME_CELLS` of them, else over every valid cell."""
    if survey_area_world is not None:
        inside = _cells_inside(dod.grid, np.asarray(survey_area_world, float)) & dod.valid
        if int(inside.sum()) >= MIN_DOME_CELLS:
            return (fit_dome(Raster(np.where(inside, dod.values, np.nan), dod.grid), gsd_m),
                    "the survey area")
    return fit_dome(dod, gsd_m), "the whole DoD"


def _dsm_surface_dod(points: np.ndarray, vertices: np.ndarray, faces, cell_m: float,
                     what: str) -> tuple[Raster, Raster, Raster]:
    """(median DSM, true surface, DoD) of the cloud ``points`` (N, 3 world) on the grid of
    ``cell_m`` cells over the part of its extent inside the mesh's; a one-line error
    naming ``what`` when they do not overlap in plan."""
    lo = np.maximum(points[:, :2].min(axis=0), vertices[:, :2].min(axis=0))
    hi = np.minimum(points[:, :2].max(axis=0), vertices[:, :2].max(axis=0))
    if not (hi > lo).all():
        raise DesignerError(f"{what}: the cloud and the true mesh do not overlap in plan; "
                            "are they in the same coordinates?")
    dsm = dsm_from_points(points, cell_m, (lo[0], lo[1], hi[0], hi[1]))
    surface = surface_raster(vertices, faces, dsm.grid)
    return dsm, surface, dem_of_difference(dsm, surface)


def cloud_dome(points_world, true_mesh, cell_m: float, gsd_m: float | None = None,
               survey_area_world=None) -> dict:
    """The dome of a cloud (N, 3 world) against the true mesh, as
    :func:`write_raster_products` fits it, without writing files: a median DSM of
    ``cell_m`` cells minus the true surface, fitted over the survey area."""
    from designer.evaluate.distance import _mesh_arrays

    vertices, faces = _mesh_arrays(true_mesh)
    _, _, dod = _dsm_surface_dod(np.asarray(points_world, dtype=np.float64), vertices, faces,
                                 cell_m, "dome")
    dome, area = dome_over_area(dod, gsd_m, survey_area_world)
    return {**_dome_dict(dome), "area": area, "cell_m": float(cell_m)}


def write_raster_products(out_dir, cloud_points_world, true_mesh, crs, cell_m: float,
                          gsd_m: float | None = None, survey_area_world=None) -> dict:
    """Grid the cloud (N, 3) world into a median DSM, rasterise the true mesh
    ((vertices, faces), a ReferenceMesh or a TerrainMesh) on the same grid and write
    dsm.tif, surface.tif, dod.tif, dod.png and dod_profile.png into ``out_dir``.

    The grid covers the part of the cloud's extent inside the mesh's. Returns the
    summary: DoD statistics, dome amplitude (m and GSD), grid and file names.

    The dome is fitted over ``survey_area_world`` ((K, 2) world polygon: the area the
    flight was planned over) when it is given and holds at least
    :data:`MIN_DOME_CELLS` DoD cells, else over the whole DoD; ``dome_whole_dod`` is
    the fit over the whole DoD either way. A peak-to-edge amplitude grows with the
    square of the area fitted, and a cloud reaches as far beyond the survey area as the
    images look — farther for tilted images —, with the few, narrow-baseline views of
    the block's edge there: over the survey area, flights of different geometry are
    measured on the same ground (docs/processing.md, "Doming: measured")."""
    from designer.evaluate.distance import _mesh_arrays

    vertices, faces = _mesh_arrays(true_mesh)
    points = np.asarray(cloud_points_world, dtype=np.float64)
    if points.ndim != 2 or points.shape[1] != 3 or len(points) == 0:
        raise DesignerError("raster products: the point cloud is empty; there is nothing "
                            "to grid")
    crs_from_user(crs)  # a bad CRS fails before any file is written
    dsm, surface, dod = _dsm_surface_dod(points, vertices, faces, cell_m, "raster products")
    whole = fit_dome(dod, gsd_m)
    dome, area_name = dome_over_area(dod, gsd_m, survey_area_world)
    stats = dod_statistics(dod, surface)
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    files = {"dsm": "dsm.tif", "surface": "surface.tif", "dod": "dod.tif",
             "dod_png": "dod.png", "dod_profile": "dod_profile.png"}
    write_geotiff(out / files["dsm"], dsm, crs, description="DSM: median point height per cell")
    write_geotiff(out / files["surface"], surface, crs,
                  description="true surface: highest mesh triangle at the cell centre")
    write_geotiff(out / files["dod"], dod, crs, dtype="float32",
                  description="DoD: DSM minus true surface")
    write_dod_png(out / files["dod_png"], dod, dome, stats, gsd_m,
                  np.asarray(survey_area_world, float) if area_name == "the survey area"
                  else None)
    write_dod_profile_png(out / files["dod_profile"], dod, dome)
    g = dsm.grid
    return {
        "cell_m": g.cell_m, "rows": g.rows, "cols": g.cols, "x_min": g.x_min, "y_max": g.y_max,
        "dsm_statistic": "median", "gsd_m": gsd_m, "dod": stats,
        "dome": {**_dome_dict(dome), "area": area_name},
        "dome_whole_dod": _dome_dict(whole),
        "files": files,
    }
