"""Digital elevation models from files: GeoTIFF (through rasterio) and ESRI ASCII grid.

Both return a :class:`~designer.core.heightfield.Heightfield` in the project's coordinate
system (metres, X east, Y north, Z up), rows going north: a GeoTIFF in another CRS (another
UTM zone, or geographic degrees) is reprojected into the project's, bilinearly
(:mod:`designer.scene.georaster`). Each raster cell's value
is taken as the height at the cell **centre**, so the height-field nodes are the cell
centres and the grid's extent is half a cell inside the raster's outer edge:

* GeoTIFF: node (row, col) of the file (or of the reprojected grid) sits at
  ``transform · (col + 0.5, row + 0.5)``.
  GDAL reports rasters tagged ``AREA_OR_POINT=Point`` with a transform already shifted
  by half a pixel to the area convention (unless ``GTIFF_POINT_GEO_IGNORE=TRUE`` is set),
  so the same rule holds for them. North-up (and south-up)
  transforms are accepted; rotated or sheared ones are rejected.
* ESRI ASCII (``.asc``): ``xllcorner/yllcorner`` give the outer lower-left corner of the
  lower-left cell (its centre is half a cell in); ``xllcenter/yllcenter`` give that
  centre itself. The first data row in the file is the northernmost.

Given the terrain extent, the grid is cropped to the nodes covering it, and only those
must hold heights: voids elsewhere in the file do not matter.

Every problem with the input raises :class:`~designer.errors.DesignerError` with a
one-line message naming the file, what is wrong and what to do.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from designer.core.heightfield import Heightfield
from designer.errors import DesignerError

GEOTIFF_SUFFIXES = (".tif", ".tiff")
ESRI_ASCII_SUFFIXES = (".asc",)
#: off-diagonal transform terms below this fraction of the pixel size count as zero
_ROTATION_TOL = 1e-9


def load_dem(
    path: str | os.PathLike,
    crs: str | None = None,
    extent_m: tuple[float, float, float, float] | None = None,
) -> Heightfield:
    """Read a DEM (GeoTIFF ``.tif``/``.tiff`` or ESRI ASCII grid ``.asc``) into a Heightfield.

    ``crs`` is the project's ``<crs>`` label. A GeoTIFF in another CRS — another UTM
    zone, or geographic degrees (EPSG:4326) — is reprojected into it (bilinear heights,
    :func:`designer.scene.georaster.reproject_grid`); a GeoTIFF without a CRS is refused
    when the project has one. With ``crs`` None (a local frame) the file's own
    coordinates are used and must be projected metres. An ESRI ASCII grid carries no
    CRS and is taken in the project's.

    ``extent_m`` = (min X, min Y, max X, max Y), the terrain extent (world m): the grid is
    cropped to the nodes covering it, which must all hold heights (nodata or NaN cells
    outside it are fine). Without it, every cell must hold a height. See the module
    docstring for registration; heights are float64 metres.
    """
    path = Path(path)
    x0, y0, dx, dy, heights = dem_grid(path, crs)
    if extent_m is not None:
        x0, y0, heights = _crop(path, x0, y0, dx, dy, heights, extent_m)
    _refuse_holes(path, x0, y0, dx, dy, heights, extent_m is not None)
    return _heightfield(path, x0, y0, dx, dy, heights)


def dem_grid(path: str | os.PathLike, crs: str | None = None
             ) -> tuple[float, float, float, float, np.ndarray]:
    """The DEM's grid in the project's ``crs``, voids kept: (x0, y0, dx, dy, heights).

    Node (i, j) sits at ``X = x0 + j·dx``, ``Y = y0 + i·dy`` (rows go north); heights
    (rows, cols) float64 m, NaN where the file has no data (or a reprojected grid falls
    outside the file). :func:`load_dem` crops and checks it.
    """
    path = Path(path)
    if not path.is_file():
        raise DesignerError(f"DEM file {path} does not exist; check the terrain path")
    suffix = path.suffix.lower()
    if suffix in GEOTIFF_SUFFIXES:
        return _load_geotiff(path, crs)
    if suffix in ESRI_ASCII_SUFFIXES:
        return _load_esri_ascii(path)
    raise DesignerError(
        f"DEM file {path}: unsupported format '{path.suffix}'; "
        "use a GeoTIFF (.tif, .tiff) or an ESRI ASCII grid (.asc)")


# --------------------------------------------------------------------------- GeoTIFF
def _load_geotiff(path: Path, crs_label: str | None):
    from designer.scene.georaster import (
        is_metric,
        project_crs,
        read_geotiff_band,
        reproject_grid,
        same_crs,
    )

    grid = read_geotiff_band(path, "DEM file")
    target = project_crs(crs_label)
    if grid.crs is None and target is not None:
        raise DesignerError(
            f"DEM file {path} has no coordinate system, the project is in {crs_label}; "
            f"assign the DEM's own CRS (e.g. gdal_edit.py -a_srs EPSG:n {path.name}) so it "
            "can be placed")
    if grid.crs is not None:
        _check_units(path, grid.crs, target is not None)
        if target is not None and not same_crs(grid.crs, target):
            if not is_metric(target):
                raise DesignerError(
                    f"DEM file {path}: the project's CRS {crs_label} is not a projected "
                    "system in metres; give the project a metric CRS (e.g. its UTM zone)")
            grid = reproject_grid(grid, target, path, "DEM file")
    a, b, c, d, e, f = grid.transform
    if abs(b) > _ROTATION_TOL * abs(a) or abs(d) > _ROTATION_TOL * abs(e) or a == 0 or e == 0:
        raise DesignerError(
            f"DEM file {path} has a rotated or sheared geotransform "
            f"({a}, {b}, {c}, {d}, {e}, {f}); resample it to a north-up grid "
            "(e.g. gdalwarp) first")

    heights = grid.values
    n_rows, n_cols = heights.shape
    # Cell centres: X = c + a·(col + ½), Y = f + e·(row + ½). Reorder so X grows with the
    # column and Y with the row (rows go north).
    if a > 0:
        x0 = c + 0.5 * a
    else:
        heights = heights[:, ::-1]
        x0 = c + a * (n_cols - 0.5)
    if e < 0:
        heights = heights[::-1, :]
        y0 = f + e * (n_rows - 0.5)
    else:
        y0 = f + 0.5 * e
    return x0, y0, abs(a), abs(e), heights


def _check_units(path: Path, crs, reprojecting: bool) -> None:
    """Geographic DEMs need a project CRS to go to; non-metre units are refused."""
    if crs.is_geographic:
        if reprojecting:
            return
        raise DesignerError(
            f"DEM file {path} is in geographic coordinates (degrees, {crs.name}); "
            "give the project a projected <crs> in metres (e.g. its UTM zone, "
            "EPSG:326zz) to have it reprojected, or reproject it (gdalwarp) first")
    units = [(axis.unit_name or "") for axis in crs.axis_info[:2]]
    bad = [u for u in units if u.lower() not in ("metre", "meter", "m", "metres", "meters")]
    if bad:
        raise DesignerError(
            f"DEM file {path} has horizontal units '{bad[0]}'; "
            "reproject it to a system in metres first (heights must be metres too)")


# --------------------------------------------------------------------------- extent, holes
def _crop(path: Path, x0: float, y0: float, dx: float, dy: float, heights: np.ndarray,
          extent_m) -> tuple[float, float, np.ndarray]:
    """The nodes covering ``extent_m``; the extent may reach half a cell past the nodes
    (to the raster's outer edge)."""
    min_X, min_Y, max_X, max_Y = (float(v) for v in extent_m)
    n_rows, n_cols = heights.shape
    tol = 1e-6
    j0 = int(np.floor((min_X - x0) / dx + tol))
    j1 = int(np.ceil((max_X - x0) / dx - tol))
    i0 = int(np.floor((min_Y - y0) / dy + tol))
    i1 = int(np.ceil((max_Y - y0) / dy - tol))
    if j0 < 0 and min_X >= x0 - 0.5 * dx - tol:
        j0 = 0
    if i0 < 0 and min_Y >= y0 - 0.5 * dy - tol:
        i0 = 0
    if j1 > n_cols - 1 and max_X <= x0 + (n_cols - 0.5) * dx + tol:
        j1 = n_cols - 1
    if i1 > n_rows - 1 and max_Y <= y0 + (n_rows - 0.5) * dy + tol:
        i1 = n_rows - 1
    if j0 < 0 or i0 < 0 or j1 > n_cols - 1 or i1 > n_rows - 1:
        raise DesignerError(
            f"DEM file {path} covers X {x0 - dx / 2:.3f}..{x0 + (n_cols - 0.5) * dx:.3f}, "
            f"Y {y0 - dy / 2:.3f}..{y0 + (n_rows - 0.5) * dy:.3f}, not the whole terrain "
            f"extent X {min_X:g}..{max_X:g}, Y {min_Y:g}..{max_Y:g}; shrink <extent> or "
            "use a larger DEM")
    j1, i1 = max(j1, j0 + 1), max(i1, i0 + 1)
    if j1 > n_cols - 1 or i1 > n_rows - 1:
        j0, i0 = min(j0, n_cols - 2), min(i0, n_rows - 2)
        j1, i1 = min(j1, n_cols - 1), min(i1, n_rows - 1)
    return x0 + j0 * dx, y0 + i0 * dy, heights[i0:i1 + 1, j0:j1 + 1]


def _refuse_holes(path: Path, x0: float, y0: float, dx: float, dy: float,
                  heights: np.ndarray, cropped: bool) -> None:
    bad = ~np.isfinite(heights)
    if bad.any():
        i, j = np.argwhere(bad)[0]
        where = " inside the terrain extent" if cropped else ""
        raise DesignerError(
            f"DEM file {path} has {int(bad.sum())} nodata/NaN cells{where} (first at "
            f"X {x0 + j * dx:.2f}, Y {y0 + i * dy:.2f}); fill the voids (e.g. "
            "gdal_fillnodata) or shrink <extent> to avoid them")


# --------------------------------------------------------------------------- ESRI ASCII
_ASC_KEYS = {"ncols", "nrows", "xllcorner", "xllcenter", "yllcorner", "yllcenter",
             "cellsize", "dx", "dy", "nodata_value"}


def _load_esri_ascii(path: Path):
    try:
        text = path.read_text(encoding="ascii", errors="strict")
    except (OSError, UnicodeDecodeError) as exc:
        raise DesignerError(
            f"DEM file {path} cannot be read as an ESRI ASCII grid ({type(exc).__name__}); "
            "check that it is a text .asc file") from None

    lines = text.splitlines()
    header: dict[str, float] = {}
    n_header = 0
    for n_header, line in enumerate(lines):
        tokens = line.split()
        if not tokens:
            continue
        key = tokens[0].lower()
        if key not in _ASC_KEYS:
            break
        if len(tokens) != 2:
            raise DesignerError(
                f"DEM file {path}, line {n_header + 1}: header '{line.strip()}' must be "
                "'KEY VALUE'; fix the ESRI ASCII header")
        try:
            header[key] = float(tokens[1])
        except ValueError:
            raise DesignerError(
                f"DEM file {path}, line {n_header + 1}: '{tokens[1]}' is not a number; "
                "fix the ESRI ASCII header") from None
    else:
        n_header = len(lines)

    for required in ("ncols", "nrows"):
        if required not in header:
            raise DesignerError(
                f"DEM file {path}: ESRI ASCII header has no '{required}'; "
                "is this an ESRI ASCII grid (.asc)?")
    n_cols, n_rows = int(header["ncols"]), int(header["nrows"])
    if n_cols != header["ncols"] or n_rows != header["nrows"] or min(n_cols, n_rows) < 1:
        raise DesignerError(
            f"DEM file {path}: ncols and nrows must be whole numbers >= 1, got "
            f"{header['ncols']:g} and {header['nrows']:g}; fix the ESRI ASCII header")
    dx = header.get("dx", header.get("cellsize"))
    dy = header.get("dy", header.get("cellsize"))
    if dx is None or dy is None:
        raise DesignerError(f"DEM file {path}: ESRI ASCII header has no 'cellsize'; add it")
    x0 = _lower_left(path, header, "x", dx)
    y0 = _lower_left(path, header, "y", dy)

    try:
        values = np.array(" ".join(lines[n_header:]).split(), dtype=np.float64)
    except ValueError:
        raise DesignerError(
            f"DEM file {path}: the grid holds a value that is not a number; "
            "fix the data rows of the ESRI ASCII grid") from None
    if values.size != n_rows * n_cols:
        raise DesignerError(
            f"DEM file {path}: header says {n_rows} x {n_cols} = {n_rows * n_cols} values, "
            f"the grid holds {values.size}; fix nrows/ncols or the data")
    heights = values.reshape(n_rows, n_cols)
    if "nodata_value" in header:
        heights[heights == header["nodata_value"]] = np.nan
    # First data row is the northernmost; the Heightfield's rows go north.
    return x0, y0, dx, dy, heights[::-1, :]


def _lower_left(path: Path, header: dict[str, float], axis: str, cell_m: float) -> float:
    """Coordinate of the lower-left cell's centre from ``?llcorner`` or ``?llcenter``."""
    corner, centre = header.get(f"{axis}llcorner"), header.get(f"{axis}llcenter")
    if (corner is None) == (centre is None):
        raise DesignerError(
            f"DEM file {path}: ESRI ASCII header needs exactly one of {axis}llcorner and "
            f"{axis}llcenter; fix the header")
    return centre if centre is not None else corner + 0.5 * cell_m


def _heightfield(path: Path, x0: float, y0: float, dx: float, dy: float,
                 heights: np.ndarray) -> Heightfield:
    try:
        return Heightfield(float(x0), float(y0), float(dx), float(dy),
                           np.ascontiguousarray(heights, dtype=np.float64))
    except DesignerError as exc:
        raise DesignerError(f"DEM file {path}: {exc}") from None
