"""Georeferenced rasters: coordinate systems, GeoTIFF grids and their reprojection.

The project's CRS is the label in ``<crs>`` (e.g. ``EPSG:32633 (WGS 84 / UTM zone 33N)``);
:func:`project_crs` turns it into a pyproj CRS, or None for a local frame such as
``local engineering frame (m)``. A raster in another CRS than the project's is brought
into it here: a DEM is resampled (bilinear) onto a north-up grid in the project's CRS, an
orthophoto keeps its pixels and only its texture coordinates are computed through the
transformation (:mod:`designer.scene.orthophoto`).

Geotransforms follow GDAL: ``(a, b, c, d, e, f)`` maps continuous pixel coordinates
(col, row), (0, 0) at the **outer top-left corner** of the top-left pixel, to
``X = a·col + b·row + c``, ``Y = d·col + e·row + f``; pixel (col, row) covers
[col, col + 1) × [row, row + 1) and its centre is (col + ½, row + ½) — the pixel
convention of docs/conventions.md.

rasterio and pyproj are imported inside the functions: importing designer.scene stays
light.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from designer.core.crs import crs_token
from designer.errors import DesignerError

_METRE_UNITS = ("metre", "meter", "m", "metres", "meters")


def project_crs(label: str | None):
    """The pyproj CRS a project's ``<crs>`` label names, or None for a local frame."""
    if not label:
        return None
    from pyproj import CRS
    from pyproj.exceptions import CRSError

    token = crs_token(label)
    for text in (token, label):
        try:
            return CRS.from_user_input(text)
        except CRSError:
            continue
    return None


def crs_label(crs) -> str:
    """``EPSG:n (name)`` for a CRS with an EPSG code, else its name (a project's <crs>)."""
    from pyproj import CRS

    crs = CRS.from_user_input(crs)
    code = crs.to_epsg()
    return f"EPSG:{code} ({crs.name})" if code else crs.name


def same_crs(a, b) -> bool:
    """Whether two CRSs (pyproj, rasterio or text) are the same system."""
    from pyproj import CRS

    a, b = CRS.from_user_input(_as_text(a)), CRS.from_user_input(_as_text(b))
    if a.equals(b, ignore_axis_order=True):
        return True
    # The same system written another way (e.g. ESRI WKT of a UTM zone) has one EPSG code.
    code = a.to_epsg(min_confidence=90)
    return code is not None and code == b.to_epsg(min_confidence=90)


def _as_text(crs):
    return crs.to_wkt() if hasattr(crs, "to_wkt") else crs


def utm_crs_for(lon_deg: float, lat_deg: float):
    """The WGS 84 UTM zone CRS (EPSG 326zz north, 327zz south) containing a point."""
    from pyproj import CRS

    zone = int(np.floor((lon_deg + 180.0) / 6.0)) % 60 + 1
    return CRS.from_epsg((32600 if lat_deg >= 0 else 32700) + zone)


def is_metric(crs) -> bool:
    """A projected CRS whose horizontal axes are in metres."""
    from pyproj import CRS

    crs = CRS.from_user_input(_as_text(crs))
    if not crs.is_projected:
        return False
    return all((axis.unit_name or "").lower() in _METRE_UNITS for axis in crs.axis_info[:2])


@dataclass(frozen=True, eq=False)
class GeoGrid:
    """One band of a georeferenced raster: values (rows, cols) float64, NaN = no data,
    the GDAL geotransform ``(a, b, c, d, e, f)`` and the CRS (pyproj, or None)."""

    values: np.ndarray
    transform: tuple[float, float, float, float, float, float]
    crs: object | None


def read_geotiff_band(path: Path, what: str) -> GeoGrid:
    """Band 1 of a GeoTIFF with nodata as NaN; ``what`` ('DEM file') names it in errors."""
    import rasterio
    from pyproj import CRS
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
            f"{what} {path} is not a readable GeoTIFF ({first_line}); "
            "export it as GeoTIFF") from None
    if not georeferenced:
        raise DesignerError(
            f"{what} {path} has no georeferencing (no geotransform); "
            "export it with its coordinate system and pixel size")
    if band is None:
        raise DesignerError(f"{what} {path} has no raster band; export the heights band")
    values = np.ma.getdata(band).astype(np.float64)
    values[np.ma.getmaskarray(band)] = np.nan
    gt = (transform.a, transform.b, transform.c, transform.d, transform.e, transform.f)
    return GeoGrid(values, gt, None if crs is None else CRS.from_user_input(crs.to_wkt()))


def reproject_grid(grid: GeoGrid, dst_crs, path: Path, what: str) -> GeoGrid:
    """Resample ``grid`` bilinearly onto a north-up grid in ``dst_crs`` (NaN outside it).

    The target resolution is GDAL's default for the transformation (about the source's
    pixel size, square pixels), rounded to 1 mm so the grid spacing reads cleanly.
    """
    from affine import Affine
    from rasterio.crs import CRS as RioCRS
    from rasterio.enums import Resampling
    from rasterio.warp import calculate_default_transform, reproject

    src_crs = RioCRS.from_wkt(grid.crs.to_wkt())
    dst = RioCRS.from_wkt(dst_crs.to_wkt())
    rows, cols = grid.values.shape
    src_transform = Affine(*grid.transform)
    x = [0, cols, 0, cols]
    y = [0, 0, rows, rows]
    xs, ys = zip(*(src_transform * (c, r) for c, r in zip(x, y, strict=True)), strict=True)
    bounds = (min(xs), min(ys), max(xs), max(ys))
    default, _, _ = calculate_default_transform(src_crs, dst, cols, rows, *bounds)
    res = max(round(abs(default.a), 3), 0.001)
    transform, width, height = calculate_default_transform(
        src_crs, dst, cols, rows, *bounds, resolution=res)
    out = np.full((height, width), np.nan)
    try:
        reproject(grid.values, out, src_transform=src_transform, src_crs=src_crs,
                  src_nodata=np.nan, dst_transform=transform, dst_crs=dst,
                  dst_nodata=np.nan, resampling=Resampling.bilinear)
    except Exception as exc:  # rasterio raises several unrelated types here
        raise DesignerError(f"{what} {path} cannot be reprojected to {dst_crs.name} "
                            f"({exc}); reproject it yourself (e.g. gdalwarp)") from None
    gt = (transform.a, transform.b, transform.c, transform.d, transform.e, transform.f)
    return GeoGrid(out, gt, dst_crs)


def world_to_pixel(transform, X, Y) -> tuple[np.ndarray, np.ndarray]:
    """Continuous (col, row) of world points through the inverse GDAL geotransform.

    Float64; the translation is removed before the 2 × 2 inverse so UTM-sized
    coordinates keep their precision. (0, 0) is the outer top-left corner of the raster.
    """
    a, b, c, d, e, f = (float(t) for t in transform)
    det = a * e - b * d
    if det == 0:
        raise DesignerError(f"geotransform {transform} is singular (zero pixel size)")
    dx = np.asarray(X, dtype=np.float64) - c
    dy = np.asarray(Y, dtype=np.float64) - f
    return (e * dx - b * dy) / det, (a * dy - d * dx) / det


def pixel_to_world(transform, col, row) -> tuple[np.ndarray, np.ndarray]:
    """World (X, Y) of continuous pixel coordinates through the GDAL geotransform."""
    a, b, c, d, e, f = (float(t) for t in transform)
    col = np.asarray(col, dtype=np.float64)
    row = np.asarray(row, dtype=np.float64)
    return a * col + b * row + c, d * col + e * row + f


def transform_xy(src_crs, dst_crs, X, Y) -> tuple[np.ndarray, np.ndarray]:
    """(X, Y) from ``src_crs`` to ``dst_crs`` (both pyproj), easting/longitude first."""
    from pyproj import Transformer

    t = Transformer.from_crs(src_crs, dst_crs, always_xy=True)
    X = np.asarray(X, dtype=np.float64)
    Y = np.asarray(Y, dtype=np.float64)
    # pyproj takes a one-element array for a scalar (and warns); give it a longer one.
    x, y = t.transform(np.append(X.ravel(), X.ravel()[:1]), np.append(Y.ravel(), Y.ravel()[:1]))
    n = X.size
    return (np.asarray(x[:n], dtype=np.float64).reshape(X.shape),
            np.asarray(y[:n], dtype=np.float64).reshape(Y.shape))


@dataclass(frozen=True)
class RasterHeader:
    """What a GeoTIFF's header says: GDAL geotransform, size (px) and CRS (or None)."""

    transform: tuple[float, float, float, float, float, float]
    width_px: int
    height_px: int
    crs: object | None


def read_header(path: Path, what: str) -> RasterHeader:
    """The header of a georeferenced raster (no pixels read)."""
    import rasterio
    from pyproj import CRS
    from rasterio.errors import NotGeoreferencedWarning, RasterioError

    path = Path(path)
    if not path.is_file():
        raise DesignerError(f"{what} {path} does not exist; check the path")
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", NotGeoreferencedWarning)
            with rasterio.open(path) as src:
                t, crs, width, height = src.transform, src.crs, src.width, src.height
    except RasterioError as exc:
        first_line = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        raise DesignerError(f"{what} {path} is not a readable GeoTIFF ({first_line}); "
                            "export it as GeoTIFF") from None
    if t.is_identity and crs is None:
        raise DesignerError(f"{what} {path} has no georeferencing (no geotransform); "
                            "export it with its coordinate system and pixel size")
    return RasterHeader((t.a, t.b, t.c, t.d, t.e, t.f), width, height,
                        None if crs is None else CRS.from_user_input(crs.to_wkt()))
