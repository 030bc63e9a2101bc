"""Orthophotos: georeferenced images draped on the terrain by their own geotransform.

An orthophoto texture is not stretched over the terrain extent: each terrain vertex's
texture coordinate is computed from its world X, Y through the inverse of the image's
GDAL geotransform (:func:`designer.scene.georaster.world_to_pixel`), after transforming
X, Y into the image's CRS when it differs from the project's. So the image may cover
another extent, at another resolution, than the DEM and the terrain extent, and every
texel lands on the ground it was taken of.

Texture coordinates follow :mod:`designer.scene.mesh`: (u, v) = (0, 0) is the
bottom-left corner of the image, (1, 1) the top-right corner, so continuous pixel
coordinates (col, row) — (0, 0) at the outer top-left corner of the top-left pixel — map
to ``u = col / W``, ``v = 1 − row / H``. The renderer samples texel (col, row) at its
centre, (col + ½) / W, as Cycles does. Within a triangle the texture coordinates are
interpolated linearly, which is exact when both CRSs agree (the map X, Y → u, v is then
affine); across CRSs the error is that of the projection's curvature over one DEM cell.

Only the part of the image over the terrain (plus a margin of two pixels) is read, so a
large orthophoto costs only the pixels the scene uses.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from designer.errors import DesignerError
from designer.scene.georaster import (
    pixel_to_world,
    project_crs,
    same_crs,
    transform_xy,
    world_to_pixel,
)

#: pixels read beyond the terrain on each side, so linear interpolation has neighbours
MARGIN_PX = 2
#: the largest orthophoto crop side handed to the renderer (px)
MAX_ORTHOPHOTO_PX = 16384


@dataclass(frozen=True, eq=False)
class Orthophoto:
    """The part of an orthophoto the scene uses.

    ``rgb`` (H, W, 3) uint8 sRGB, row 0 at the top; ``transform`` the GDAL geotransform
    of this crop (a, b, c, d, e, f), world metres in ``crs`` (pyproj, or None when the
    file has none and the project is a local frame).
    """

    rgb: np.ndarray
    transform: tuple[float, float, float, float, float, float]
    crs: object | None

    @property
    def texel_size_m(self) -> tuple[float, float]:
        """Ground size of one texel along its columns and rows (m)."""
        a, b, _, d, e, _ = self.transform
        return float(np.hypot(a, d)), float(np.hypot(b, e))


def load_orthophoto(
    path: str | Path,
    crs: str | None,
    extent_m: tuple[float, float, float, float],
) -> Orthophoto:
    """Read the part of a GeoTIFF orthophoto over ``extent_m`` (min X, min Y, max X, max Y,
    world m in the project's ``crs`` label).

    Bands 1–3 are red, green, blue (one band: grey; a fourth band, alpha, is ignored);
    16-bit values are scaled to 8 bits. Refuses (DesignerError naming the file and the
    fix) a file without georeferencing, without a CRS when the project has one, or one
    that does not cover the extent.
    """
    import rasterio
    from pyproj import CRS
    from rasterio.errors import NotGeoreferencedWarning, RasterioError
    from rasterio.windows import Window

    path = Path(path)
    if not path.is_file():
        raise DesignerError(f"orthophoto {path} does not exist; check the texture path")
    target = project_crs(crs)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", NotGeoreferencedWarning)
            with rasterio.open(path) as src:
                t = src.transform
                gt = (t.a, t.b, t.c, t.d, t.e, t.f)
                if t.is_identity and src.crs is None:
                    raise DesignerError(
                        f"orthophoto {path} has no georeferencing (no geotransform); "
                        "export it as a GeoTIFF with its coordinate system and pixel size")
                file_crs = None if src.crs is None else CRS.from_user_input(src.crs.to_wkt())
                if file_crs is None and target is not None:
                    raise DesignerError(
                        f"orthophoto {path} has no coordinate system, the project is in "
                        f"{crs}; assign the image's own CRS (e.g. gdal_edit.py -a_srs "
                        f"EPSG:n {path.name})")
                if file_crs is not None and file_crs.is_geographic and target is None:
                    raise DesignerError(
                        f"orthophoto {path} is in geographic coordinates; give the project "
                        "a projected <crs> in metres (e.g. its UTM zone)")
                window = _window(path, gt, file_crs, target, extent_m, src.width, src.height)
                bands = [1, 2, 3] if src.count >= 3 else [1]
                data = src.read(bands, window=Window(*window))
                dtype = src.dtypes[0]
    except RasterioError as exc:
        first_line = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        raise DesignerError(f"orthophoto {path} is not a readable GeoTIFF ({first_line}); "
                            "export it as GeoTIFF") from None
    col0, row0, _, _ = window
    a, b, c, d, e, f = gt
    crop_gt = (a, b, c + a * col0 + b * row0, d, e, f + d * col0 + e * row0)
    rgb = np.moveaxis(data, 0, -1)
    if dtype == "uint16":
        rgb = ((rgb.astype(np.uint32) + 128) // 257).astype(np.uint8)
    elif dtype != "uint8":
        raise DesignerError(f"orthophoto {path} has {dtype} pixels; save it as 8- or 16-bit "
                            "RGB")
    if rgb.shape[2] == 1:
        rgb = np.repeat(rgb, 3, axis=2)
    return Orthophoto(np.ascontiguousarray(rgb), crop_gt, file_crs)


def _window(path, gt, file_crs, target, extent_m, width, height):
    """(col0, row0, cols, rows) of the image over the extent plus the margin."""
    min_X, min_Y, max_X, max_Y = (float(v) for v in extent_m)
    # The extent's outline, densified so a curved image of it in another CRS is covered.
    s = np.linspace(0.0, 1.0, 33)
    X = np.concatenate([min_X + s * (max_X - min_X), np.full_like(s, max_X),
                        max_X - s * (max_X - min_X), np.full_like(s, min_X)])
    Y = np.concatenate([np.full_like(s, min_Y), min_Y + s * (max_Y - min_Y),
                        np.full_like(s, max_Y), max_Y - s * (max_Y - min_Y)])
    if file_crs is not None and target is not None and not same_crs(file_crs, target):
        X, Y = transform_xy(target, file_crs, X, Y)
    col, row = world_to_pixel(gt, X, Y)
    tol = 1e-6
    if (col.min() < -1.0 - tol or row.min() < -1.0 - tol or col.max() > width + 1.0 + tol
            or row.max() > height + 1.0 + tol):
        x_lo, y_lo = pixel_to_world(gt, [0, width], [height, 0])
        raise DesignerError(
            f"orthophoto {path} covers X {min(x_lo):.3f}..{max(x_lo):.3f}, "
            f"Y {min(y_lo):.3f}..{max(y_lo):.3f} (in its own CRS), not the whole terrain "
            f"extent X {min_X:g}..{max_X:g}, Y {min_Y:g}..{max_Y:g}; shrink <extent> or use "
            "a larger orthophoto")
    col0 = max(0, int(np.floor(col.min())) - MARGIN_PX)
    row0 = max(0, int(np.floor(row.min())) - MARGIN_PX)
    col1 = min(width, int(np.ceil(col.max())) + MARGIN_PX)
    row1 = min(height, int(np.ceil(row.max())) + MARGIN_PX)
    if max(col1 - col0, row1 - row0) > MAX_ORTHOPHOTO_PX:
        raise DesignerError(
            f"orthophoto {path}: the terrain extent spans {col1 - col0} x {row1 - row0} of its "
            f"pixels, more than {MAX_ORTHOPHOTO_PX}; resample the orthophoto to a coarser "
            "pixel (gdalwarp -tr) or shrink <extent>")
    return col0, row0, col1 - col0, row1 - row0


def orthophoto_uv(ortho: Orthophoto, xy_world: np.ndarray, crs: str | None) -> np.ndarray:
    """(N, 2) float64 texture coordinates of world points (N, 2) in the project's ``crs``.

    ``u = col / W``, ``v = 1 − row / H`` with (col, row) the continuous pixel coordinates
    of the point in the orthophoto crop (module docstring).
    """
    xy = np.asarray(xy_world, dtype=np.float64).reshape(-1, 2)
    X, Y = xy[:, 0], xy[:, 1]
    target = project_crs(crs)
    if ortho.crs is not None and target is not None and not same_crs(ortho.crs, target):
        X, Y = transform_xy(target, ortho.crs, X, Y)
    col, row = world_to_pixel(ortho.transform, X, Y)
    height_px, width_px = ortho.rgb.shape[:2]
    return np.column_stack([col / width_px, 1.0 - row / height_px])
