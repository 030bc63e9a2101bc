"""A project for a real site: a GeoTIFF DEM and (optionally) an orthophoto GeoTIFF.

``designer new PROJECT.xml --site DEM.tif --orthophoto ORTHO.tif`` calls
:func:`site_project`. Everything georeferenced is taken from the data:

* **CRS**: the DEM's, when it is projected in metres; else (a geographic DEM) the
  orthophoto's, when that is projected in metres; else the WGS 84 UTM zone of the DEM's
  centre. The project's ``<crs>`` is written as ``EPSG:n (name)`` and reaches every
  export (ODM headers, Metashape references, tables).
* **Terrain extent**: where the DEM (reprojected if need be, voids excluded) and the
  orthophoto overlap, rounded inwards to 0.1 m.
* **Origin**: the centre of that extent rounded to whole metres; H0 = the median DEM
  height over it (0.01 m).

The rest comes from the example survey (``designer new --template survey``): its camera,
image effects, render settings, lighting and exports; a grid flight over the extent
inset by a tenth of its smaller side, at a GSD of twice the orthophoto's pixel in the
rendered images (so the texture never limits what the images resolve), and six GCP
targets laid out on the inset area's corners, one edge and its centre
(:func:`designer.survey.gcp_layout.perimeter_and_centre`; the edge and centre ones
are check points).
"""

from __future__ import annotations

import dataclasses
import math
import os
from pathlib import Path

import numpy as np

from designer.errors import DesignerError
from designer.project import model as m
from designer.project.templates import survey
from designer.scene.dem import dem_grid
from designer.scene.georaster import (
    crs_label,
    is_metric,
    pixel_to_world,
    read_header,
    same_crs,
    transform_xy,
    utm_crs_for,
)
from designer.survey import gcp_layout
from designer.survey.area import inset, rectangle

#: GCP target side (m) and the simulated survey's standard deviations (m)
TARGET_SIZE_M = 0.8
SURVEY_SIGMA_M = (0.01, 0.01, 0.02)


def check_site_dem(dem_path: str | os.PathLike) -> None:
    """Refuse a DEM that cannot make a site on its own (before an orthophoto is chosen):
    unreadable, without a coordinate system, not in metres, or without a void-free part
    of at least 1 m x 1 m. The one-line :class:`DesignerError` names the file."""
    dem_path = Path(dem_path)
    dem_header = read_header(dem_path, "DEM file")
    crs = _site_crs(dem_path, dem_header, None, None)
    x0, y0, dx, dy, heights = dem_grid(dem_path, crs_label(crs))
    box = (x0, y0, x0 + dx * (heights.shape[1] - 1), y0 + dy * (heights.shape[0] - 1))
    i0, i1, j0, j1 = _valid_block(heights, x0, y0, dx, dy, box, dem_path, None)
    if not (dx * (j1 - j0) > 1 and dy * (i1 - i0) > 1):
        raise DesignerError(f"DEM file {dem_path}: its void-free part is only "
                            f"{dx * (j1 - j0):.2f} x {dy * (i1 - i0):.2f} m; use a DEM "
                            "that covers the site")


def site_project(dem_path: str | os.PathLike, orthophoto_path: str | os.PathLike | None,
                 project_path: str | os.PathLike) -> m.Project:
    """The project for ``dem_path`` (+ ``orthophoto_path``), with file paths written
    relative to ``project_path``'s folder (module docstring)."""
    dem_path, project_path = Path(dem_path), Path(project_path)
    ortho_path = None if orthophoto_path is None else Path(orthophoto_path)
    dem_header = read_header(dem_path, "DEM file")
    ortho_header = None if ortho_path is None else read_header(ortho_path, "orthophoto")
    crs = _site_crs(dem_path, dem_header, ortho_path, ortho_header)
    label = crs_label(crs)

    x0, y0, dx, dy, heights = dem_grid(dem_path, label)
    box = (x0, y0, x0 + dx * (heights.shape[1] - 1), y0 + dy * (heights.shape[0] - 1))
    texel_m = None
    if ortho_header is not None:
        box = _intersect(box, _inner_box(ortho_header, crs), dem_path, ortho_path)
        texel_m = _texel_m(ortho_header, crs)
    i0, i1, j0, j1 = _valid_block(heights, x0, y0, dx, dy, box, dem_path, ortho_path)
    extent = m.Extent(
        math.ceil(round(max(box[0], x0 + j0 * dx) * 10, 6)) / 10,
        math.ceil(round(max(box[1], y0 + i0 * dy) * 10, 6)) / 10,
        math.floor(round(min(box[2], x0 + j1 * dx) * 10, 6)) / 10,
        math.floor(round(min(box[3], y0 + i1 * dy) * 10, 6)) / 10)
    if not (extent.width_m > 1 and extent.length_m > 1):
        if ortho_path is None:
            raise DesignerError(f"DEM file {dem_path}: its void-free part is only "
                                f"{extent.width_m:.2f} x {extent.length_m:.2f} m; use a DEM "
                                "that covers the site")
        raise DesignerError(f"{dem_path}: the usable overlap of the DEM and the orthophoto is "
                            f"only {extent.width_m:.2f} x {extent.length_m:.2f} m; use files "
                            "that cover the same ground")
    H0 = round(float(np.median(heights[i0:i1 + 1, j0:j1 + 1])), 2)
    E0 = float(round((extent.min_X + extent.max_X) / 2))
    N0 = float(round((extent.min_Y + extent.max_Y) / 2))

    base = survey().project
    folder = project_path.parent
    texture = (m.Texture(m.OrthophotoTexture(_relative(ortho_path, folder)), 1, 1, "linear")
               if ortho_path is not None else base.scene.texture)
    margin = 0.1 * min(extent.width_m, extent.length_m)
    area = inset(rectangle(extent.min_X, extent.min_Y, extent.max_X, extent.max_Y), margin)
    plan = dataclasses.replace(
        base.trajectory.flight_plan,
        area=tuple((round(float(x), 3), round(float(y), 3)) for x, y in area),
        altitude_agl_m=None if texel_m else base.trajectory.flight_plan.altitude_agl_m,
        gsd_m=(round(2.0 * texel_m * base.render.resolution_scale, 4) if texel_m else None))
    scene = dataclasses.replace(
        base.scene,
        terrain=m.Terrain(extent, m.DemTerrain(_relative(dem_path, folder))),
        texture=texture,
        targets=m.Targets(_targets(area), m.SurveyAccuracy(m.Sigma3(*SURVEY_SIGMA_M), seed=11)))
    sources = dem_path.name + ("" if ortho_path is None else f" + {ortho_path.name}")
    return dataclasses.replace(
        base, name=f"Site: {sources}",
        description=(f"A survey of the real site {sources} in {label}: terrain extent "
                     f"{extent.width_m:.1f} x {extent.length_m:.1f} m where the files overlap, "
                     "a grid flight over its inner part and six GCP targets. Camera, image "
                     "effects and render settings are those of the example survey."),
        crs=label, origin=m.Origin(E0, N0, H0), scene=scene,
        trajectory=m.Trajectory(flight_plan=plan))


def _site_crs(dem_path, dem_header, ortho_path, ortho_header):
    if dem_header.crs is None:
        raise DesignerError(f"DEM file {dem_path} has no coordinate system; assign it "
                            f"(e.g. gdal_edit.py -a_srs EPSG:n {dem_path.name}) so the site "
                            "can be placed")
    if ortho_header is not None and ortho_header.crs is None:
        raise DesignerError(f"orthophoto {ortho_path} has no coordinate system; assign it "
                            f"(e.g. gdal_edit.py -a_srs EPSG:n {ortho_path.name})")
    if dem_header.crs.is_projected:
        if not is_metric(dem_header.crs):
            raise DesignerError(f"DEM file {dem_path} is in {dem_header.crs.name}, whose units "
                                "are not metres; reproject it to a metric system (e.g. UTM)")
        return dem_header.crs
    if ortho_header is not None and is_metric(ortho_header.crs):
        return ortho_header.crs
    t = dem_header.transform
    lon, lat = pixel_to_world(t, dem_header.width_px / 2, dem_header.height_px / 2)
    return utm_crs_for(float(lon), float(lat))


def _texel_m(header, crs) -> float:
    """The raster's pixel size in metres of the site's ``crs`` (its longer side, at the
    raster's centre): an orthophoto in longitude/latitude has its cells in degrees."""
    col, row = header.width_px / 2, header.height_px / 2
    X, Y = pixel_to_world(header.transform, [col, col + 1, col], [row, row, row + 1])
    if not same_crs(header.crs, crs):
        X, Y = transform_xy(header.crs, crs, X, Y)
    return max(math.hypot(X[1] - X[0], Y[1] - Y[0]), math.hypot(X[2] - X[0], Y[2] - Y[0]))


def _inner_box(header, crs) -> tuple[float, float, float, float]:
    """(min X, min Y, max X, max Y) in ``crs`` inside the raster's footprint."""
    s = np.linspace(0.0, 1.0, 33)
    W, H = header.width_px, header.height_px
    edges = {"a": (s * W, np.zeros_like(s)), "b": (s * W, np.full_like(s, H)),
             "c": (np.zeros_like(s), s * H), "d": (np.full_like(s, W), s * H)}
    xy = {}
    for key, (col, row) in edges.items():
        X, Y = pixel_to_world(header.transform, col, row)
        if header.crs is not None and not same_crs(header.crs, crs):
            X, Y = transform_xy(header.crs, crs, X, Y)
        xy[key] = (X, Y)
    # Which edge lies west/east/south/north, whatever the geotransform's signs.
    by_x = sorted(("c", "d"), key=lambda k: float(np.mean(xy[k][0])))
    by_y = sorted(("a", "b"), key=lambda k: float(np.mean(xy[k][1])))
    return (float(np.max(xy[by_x[0]][0])), float(np.max(xy[by_y[0]][1])),
            float(np.min(xy[by_x[1]][0])), float(np.min(xy[by_y[1]][1])))


def _intersect(a, b, dem_path, ortho_path):
    box = (max(a[0], b[0]), max(a[1], b[1]), min(a[2], b[2]), min(a[3], b[3]))
    if not (box[0] < box[2] and box[1] < box[3]):
        raise DesignerError(
            f"DEM file {dem_path} (X {a[0]:.1f}..{a[2]:.1f}, Y {a[1]:.1f}..{a[3]:.1f}) and "
            f"orthophoto {ortho_path} (X {b[0]:.1f}..{b[2]:.1f}, Y {b[1]:.1f}..{b[3]:.1f}) do "
            "not overlap; give files of the same site")
    return box


def _valid_block(heights, x0, y0, dx, dy, box, dem_path,
                 ortho_path) -> tuple[int, int, int, int]:
    """Node index range (i0, i1, j0, j1) with no voids: the nodes enclosing ``box`` (the
    part overlapping the orthophoto ``ortho_path``, or the whole DEM when None), trimmed
    border line by border line (the one with most voids first)."""
    j0 = max(0, math.floor((box[0] - x0) / dx + 1e-9))
    j1 = min(heights.shape[1] - 1, math.ceil((box[2] - x0) / dx - 1e-9))
    i0 = max(0, math.floor((box[1] - y0) / dy + 1e-9))
    i1 = min(heights.shape[0] - 1, math.ceil((box[3] - y0) / dy - 1e-9))
    void = ~np.isfinite(heights)
    while j1 - j0 >= 2 and i1 - i0 >= 2:
        block = void[i0:i1 + 1, j0:j1 + 1]
        if not block.any():
            return i0, i1, j0, j1
        counts = [block[0].sum(), block[-1].sum(), block[:, 0].sum(), block[:, -1].sum()]
        side = int(np.argmax(counts))
        if side == 0:
            i0 += 1
        elif side == 1:
            i1 -= 1
        elif side == 2:
            j0 += 1
        else:
            j1 -= 1
    if ortho_path is None:
        raise DesignerError(f"DEM file {dem_path} has no void-free part (no area without "
                            "nodata cells); fill its voids (e.g. gdal_fillnodata)")
    raise DesignerError(f"DEM file {dem_path} has no void-free part where it overlaps the "
                        f"orthophoto {ortho_path.name}; fill its voids (e.g. gdal_fillnodata)")


def _targets(area: np.ndarray) -> tuple[m.Target, ...]:
    span = float(min(np.ptp(area[:, 0]), np.ptp(area[:, 1])))
    margin = 0.1 * span
    xy = gcp_layout.perimeter_and_centre(6, area, margin_m=margin)
    corners = inset(area, margin)
    # The corners georeference; the edge point and the centre check.
    to_corner = np.min(np.linalg.norm(xy[:, None, :] - corners[None], axis=2), axis=1)
    roles = ["control" if d < 1e-6 else "check" for d in to_corner]
    return tuple(
        m.Target(id=f"GCP{i + 1:02d}", role=roles[i], shape="checker", size_m=TARGET_SIZE_M,
                 true=m.TruePosition(round(float(x), 3), round(float(y), 3)))
        for i, (x, y) in enumerate(xy))


def _relative(path: Path, folder: Path) -> str:
    """``path`` as the project writes it: relative to its folder, with forward slashes."""
    return Path(os.path.relpath(path.resolve(), folder.resolve())).as_posix()
