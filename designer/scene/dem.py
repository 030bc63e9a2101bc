"""Digital elevation models from files: GeoTIFF (through rasterio) and ESRI ASCII grid.

Both return a :class:`~designer.core.heightfield.Heightfield` in the file's own projected
coordinates (metres, X east, Y north, Z up), rows going north. Each raster cell's value
is taken as the height at the cell **centre**, so the height-field nodes are the cell
centres and the grid's extent is half a cell inside the raster's outer edge:

* GeoTIFF: node (row, col) of the file sits at ``transform · (col + 0.5, row + 0.5)``.
  GDAL reports rasters tagged ``AREA_OR_POINT=Point`` with a transform already shifted
  by half a pixel to the area convention (unless ``GTIFF_POINT_GEO_IGNORE=TRUE`` is set),
  so the same rule holds for them. North-up (and south-up)
  transforms are accepted; rotated or sheared ones are rejected.
* ESRI ASCII (``.asc``): ``xllcorner/yllcorner`` give the outer lower-left corner of the
  lower-left cell (its centre is half a cell in); ``xllcenter/yllcenter`` give that
  centre itself. The first data row in the file is the northernmost.

Every problem with the input raises :class:`~designer.errors.DesignerError` with a
one-line message naming the file, what is wrong and what to do.
"""

from __future__ import annotations

import os
import warnings
from pathlib import Path

import numpy as np

from designer.core.heightfield import Heightfield
from designer.errors import DesignerError

GEOTIFF_SUFFIXES = (".tif", ".tiff")
ESRI_ASCII_SUFFIXES = (".asc",)
#: off-diagonal transform terms below this fraction of the pixel size count as zero
_ROTATION_TOL = 1e-9


def load_dem(path: str | os.PathLike) -> Heightfield:
    """Read a DEM (GeoTIFF ``.tif``/``.tiff`` or ESRI ASCII grid ``.asc``) into a Heightfield.

    Heights are float64 metres; NaN or nodata cells are refused (fill the voids first,
    e.g. with ``gdal_fillnodata``). See the module docstring for registration.
    """
    path = Path(path)
    if not path.is_file():
        raise DesignerError(f"DEM file {path} does not exist; check the terrain path")
    suffix = path.suffix.lower()
    if suffix in GEOTIFF_SUFFIXES:
        return _load_geotiff(path)
    if suffix in ESRI_ASCII_SUFFIXES:
        return _load_esri_ascii(path)
    raise DesignerError(
        f"DEM file {path}: unsupported format '{path.suffix}'; "
        "use a GeoTIFF (.tif, .tiff) or an ESRI ASCII grid (.asc)")


# --------------------------------------------------------------------------- GeoTIFF
def _load_geotiff(path: Path) -> Heightfield:
    import rasterio
    from rasterio.errors import NotGeoreferencedWarning, RasterioError

    try:
        with warnings.catch_warnings():
            # An ungeoreferenced file is reported below as an error of its own.
            warnings.simplefilter("ignore", NotGeoreferencedWarning)
            with rasterio.open(path) as src:
                transform, crs, count = src.transform, src.crs, src.count
                georeferenced = not (transform.is_identity and crs is None)
                band = src.read(1, masked=True) if count >= 1 and georeferenced else None
    except RasterioError as exc:
        first_line = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        raise DesignerError(
            f"DEM file {path} is not a readable GeoTIFF ({first_line}); "
            "export the DEM as GeoTIFF or ESRI ASCII grid") from None
    if not georeferenced:
        raise DesignerError(
            f"DEM file {path} has no georeferencing (no geotransform); "
            "export it with its coordinate system and pixel size")
    if band is None:
        raise DesignerError(f"DEM file {path} has no raster band; export the heights band")
    _check_crs(path, crs)

    a, b, c, d, e, f = (transform.a, transform.b, transform.c,
                        transform.d, transform.e, transform.f)
    if abs(b) > _ROTATION_TOL * abs(a) or abs(d) > _ROTATION_TOL * abs(e) or a == 0 or e == 0:
        raise DesignerError(
            f"DEM file {path} has a rotated or sheared geotransform "
            f"({a}, {b}, {c}, {d}, {e}, {f}); resample it to a north-up grid "
            "(e.g. gdalwarp) first")

    heights = np.ma.getdata(band).astype(np.float64)
    mask = np.ma.getmaskarray(band) | ~np.isfinite(heights)
    if mask.any():
        row, col = np.argwhere(mask)[0]
        raise DesignerError(
            f"DEM file {path} has {int(mask.sum())} nodata/NaN cells (first at row {row}, "
            f"column {col}); fill the voids (e.g. gdal_fillnodata) or crop them away")

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
    return _heightfield(path, x0, y0, abs(a), abs(e), heights)


def _check_crs(path: Path, crs) -> None:
    if crs is None:
        return  # a bare geotransform: taken as metres
    if crs.is_geographic:
        raise DesignerError(
            f"DEM file {path} is in geographic coordinates (degrees, {crs}); "
            "reproject it to a projected system in metres (e.g. UTM) first")
    units = (crs.linear_units or "").lower()
    if units and units not in ("metre", "meter", "m", "metres", "meters", "unknown"):
        raise DesignerError(
            f"DEM file {path} has horizontal units '{crs.linear_units}'; "
            "reproject it to a system in metres first")


# --------------------------------------------------------------------------- ESRI ASCII
_ASC_KEYS = {"ncols", "nrows", "xllcorner", "xllcenter", "yllcorner", "yllcenter",
             "cellsize", "dx", "dy", "nodata_value"}


def _load_esri_ascii(path: Path) -> Heightfield:
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
    bad = ~np.isfinite(heights)
    if "nodata_value" in header:
        bad |= heights == header["nodata_value"]
    if bad.any():
        row, col = np.argwhere(bad)[0]
        raise DesignerError(
            f"DEM file {path} has {int(bad.sum())} NODATA cells (first at data row {row}, "
            f"column {col}); fill the voids or crop them away")
    # First data row is the northernmost; the Heightfield's rows go north.
    return _heightfield(path, x0, y0, dx, dy, heights[::-1, :])


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
