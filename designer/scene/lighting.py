"""Sun and sky lighting, baked once per scene into a light map.

Why bake: a path tracer estimates sunlight and skylight by random sampling, so every
sample count leaves noise in the image — an effect no survey asked for. Here the
lighting of the terrain is computed once, deterministically, in numpy (Lambert shading
from the sun with cast shadows, plus an isotropic sky), stored as a light map over the
terrain extent, and multiplied with the texture in an emission shader. The renderer
then only has to find which surface each camera ray hits: its samples buy
antialiasing, nothing else.

Frames: world X east, Y north, Z up. Sun azimuth is clockwise from grid north, the
elevation above the horizon, both in degrees.
"""

from __future__ import annotations

import datetime as _dt
import math

import numpy as np

from designer.core.heightfield import Heightfield
from designer.errors import DesignerError

#: the light map stores L / LIGHTMAP_SCALE so values up to 2× flat-ground sunlight fit
LIGHTMAP_SCALE = 2.0


def sun_direction_world(azimuth_deg: float, elevation_deg: float) -> np.ndarray:
    """Unit vector (3,) from the ground towards the sun, world frame."""
    az, el = math.radians(azimuth_deg), math.radians(elevation_deg)
    return np.array([math.sin(az) * math.cos(el), math.cos(az) * math.cos(el), math.sin(el)])


def sun_position_deg(date_time_iso: str, latitude_deg: float, longitude_deg: float):
    """(azimuth, elevation) of the sun in degrees for an ISO 8601 moment with a time zone.

    Azimuth is relative to true north; for a projected CRS the difference to grid north
    (meridian convergence) is the user's to include.
    """
    from astral import Observer
    from astral.sun import azimuth, elevation

    try:
        moment = _dt.datetime.fromisoformat(date_time_iso)
    except ValueError as error:
        raise DesignerError(
            f"date-time {date_time_iso!r} is not ISO 8601; write e.g. 2024-06-21T10:30:00+02:00"
        ) from error
    if moment.tzinfo is None:
        raise DesignerError(
            f"date-time {date_time_iso!r} has no time zone; append one, e.g. +00:00 or Z")
    observer = Observer(latitude=latitude_deg, longitude=longitude_deg)
    return float(azimuth(observer, moment)), float(elevation(observer, moment))


def surface_normals(hf: Heightfield, x_m: np.ndarray, y_m: np.ndarray, step_m: float):
    """Unit upward normals (N, 3) of the bilinear surface by central differences."""
    x0, x1, y0, y1 = hf.extent_m
    xa, xb = np.clip(x_m - step_m, x0, x1), np.clip(x_m + step_m, x0, x1)
    ya, yb = np.clip(y_m - step_m, y0, y1), np.clip(y_m + step_m, y0, y1)
    dzdx = (hf.height_at(xb, y_m) - hf.height_at(xa, y_m)) / (xb - xa)
    dzdy = (hf.height_at(x_m, yb) - hf.height_at(x_m, ya)) / (yb - ya)
    n = np.column_stack([-dzdx, -dzdy, np.ones_like(dzdx)])
    return n / np.linalg.norm(n, axis=1, keepdims=True)


def irradiance(
    normals: np.ndarray,
    lit: np.ndarray,
    sun_dir: np.ndarray,
    sun_strength: float,
    sky_strength: float,
) -> np.ndarray:
    """Relative irradiance (N,): 1.0 for flat, unshadowed ground.

    ``sun_strength · max(0, n·s) · lit + sky_strength · (1 + n_z) / 2``, divided by the
    same for a flat open surface. The sky term is an isotropic sky seen by a tilted
    plane; the terrain's own occlusion of the sky is ignored.
    """
    direct = sun_strength * np.clip(normals @ sun_dir, 0.0, None) * lit
    sky = sky_strength * 0.5 * (1.0 + normals[:, 2])
    flat = sun_strength * max(sun_dir[2], 0.0) + sky_strength
    if flat <= 0:
        raise DesignerError("lighting gives no light at all: raise the sun or sky strength")
    return (direct + sky) / flat


def bake_lightmap(
    hf: Heightfield,
    sun_azimuth_deg: float,
    sun_elevation_deg: float,
    sun_strength: float,
    sky_strength: float,
    size_px: tuple[int, int] = (512, 512),
    shadows: bool = True,
) -> np.ndarray:
    """Light map (H, W) float32 over the terrain extent, image top row = north edge.

    Texel (i, j) is sampled at its centre, matching a linearly interpolated texture
    mapped with u east and v north over the extent. Values are relative irradiance
    (1 = flat ground in full sun), see :func:`irradiance`.
    """
    light, _ = _bake(hf, sun_azimuth_deg, sun_elevation_deg, sun_strength, sky_strength,
                     size_px, shadows)
    return light


def bake_lightmap_direct(
    hf: Heightfield,
    sun_azimuth_deg: float,
    sun_elevation_deg: float,
    sun_strength: float,
    sky_strength: float,
    size_px: tuple[int, int] = (512, 512),
) -> tuple[np.ndarray, np.ndarray]:
    """(light map as :func:`bake_lightmap`, its direct-sun part) (H, W) float32, both
    relative irradiance; ``light − direct`` is the sky's share."""
    return _bake(hf, sun_azimuth_deg, sun_elevation_deg, sun_strength, sky_strength,
                 size_px, True)


def lightmap_texel_centres(hf: Heightfield, size_px: tuple[int, int]):
    """World X (W,) west to east and Y (H,) north to south of the light map's texels."""
    W, H = size_px
    x0, x1, y0, y1 = hf.extent_m
    return (x0 + (np.arange(W) + 0.5) / W * (x1 - x0),
            y1 - (np.arange(H) + 0.5) / H * (y1 - y0))


def _bake(hf, sun_azimuth_deg, sun_elevation_deg, sun_strength, sky_strength, size_px,
          shadows):
    W, H = size_px
    xs, ys = lightmap_texel_centres(hf, size_px)
    X, Y = np.meshgrid(xs, ys)
    X, Y = X.ravel(), Y.ravel()
    step = 0.5 * min(hf.dx_m, hf.dy_m)
    normals = surface_normals(hf, X, Y, step)
    sun = sun_direction_world(sun_azimuth_deg, sun_elevation_deg)
    lit = np.ones(len(X))
    if shadows and sun[2] > 0:
        Z = hf.height_at(X, Y)
        # Start a little above the surface so a ray does not hit its own texel.
        start = np.column_stack([X, Y, Z]) + 0.01 * normals
        facing = normals @ sun > 0
        idx = np.flatnonzero(facing)
        hits = hf.intersect_rays(start[idx], np.broadcast_to(sun, (len(idx), 3)), tol_m=1e-3)
        lit[idx[np.isfinite(hits[:, 0])]] = 0.0
    light = irradiance(normals, lit, sun, sun_strength, sky_strength)
    flat = sun_strength * max(sun[2], 0.0) + sky_strength
    direct = sun_strength * np.clip(normals @ sun, 0.0, None) * lit / flat
    return light.reshape(H, W).astype(np.float32), direct.reshape(H, W).astype(np.float32)


def encode_lightmap_png16(light: np.ndarray) -> np.ndarray:
    """16-bit single-channel image of ``light / LIGHTMAP_SCALE`` (clipped to [0, 1])."""
    return np.round(np.clip(light / LIGHTMAP_SCALE, 0.0, 1.0) * 65535).astype(np.uint16)
