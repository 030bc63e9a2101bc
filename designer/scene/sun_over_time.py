"""The sun over time: its direction for each photo's moment (docs/world.md, "Sun over
time").

The sun's true azimuth and elevation come from astral (NOAA's solar position
equations, refraction included in the elevation) for the moment and the site. The site
is the project origin converted to WGS 84 latitude/longitude with the project CRS
(pyproj), unless ``<sun-over-time>`` gives latitude-deg and longitude-deg. The world
frame's azimuths are grid azimuths, so the true azimuth is turned by the meridian
convergence γ at the site: grid azimuth = true azimuth − γ (pyproj's
``meridian_convergence``, as in designer.flight.geodesy). A site given by latitude and
longitude in a CRS PROJ does not know keeps γ = 0.
"""

from __future__ import annotations

import datetime as _dt
from collections.abc import Sequence
from dataclasses import dataclass

from designer.core.crs import crs_token
from designer.errors import DesignerError
from designer.project import model as m
from designer.project.utc import EXAMPLE_UTC, parse_utc


@dataclass(frozen=True)
class Site:
    """Where the sun is computed: WGS 84 latitude/longitude (deg) and the meridian
    convergence γ there (deg; grid azimuth = true azimuth − γ)."""

    latitude_deg: float
    longitude_deg: float
    convergence_deg: float = 0.0


def project_site(project: m.Project, sun: m.SunOverTime) -> Site:
    """The site of a sun over time: its own latitude/longitude or the project origin."""
    try:
        from pyproj import CRS, Proj, Transformer

        crs = CRS.from_user_input(crs_token(project.crs))
        if not crs.is_projected:
            crs = None
    except Exception:  # pyproj's CRSError and the like: an unknown label
        crs = None
    if sun.latitude_deg is not None and sun.longitude_deg is not None:
        lat, lon = sun.latitude_deg, sun.longitude_deg
    elif crs is not None:
        to_ll = Transformer.from_crs(crs, "EPSG:4326", always_xy=True)
        lon, lat = to_ll.transform(project.origin.E0, project.origin.N0)
    else:
        raise DesignerError(f"sun-over-time: the project CRS {project.crs!r} is not a projected "
                            "CRS PROJ knows; give latitude-deg and longitude-deg")
    gamma = 0.0
    if crs is not None:
        gamma = float(Proj(crs).get_factors(lon, lat).meridian_convergence)
    return Site(float(lat), float(lon), gamma)


def sun_at(moment: _dt.datetime, site: Site) -> tuple[float, float]:
    """(grid azimuth in [0, 360), elevation) of the sun in degrees at an aware moment."""
    from astral import Observer
    from astral.sun import azimuth, elevation

    observer = Observer(latitude=site.latitude_deg, longitude=site.longitude_deg)
    az = (float(azimuth(observer, moment)) - site.convergence_deg) % 360.0
    return az, float(elevation(observer, moment))


def suns_at(moments: Sequence[_dt.datetime], site: Site) -> list[tuple[float, float]]:
    """The sun (grid azimuth, elevation; deg) at each moment; DesignerError when it is at
    or below the horizon at one of them (a sky-lit, shadowless image, silently unlike the
    moment named)."""
    suns = [sun_at(t, site) for t in moments]
    for t, (_, elevation_deg) in zip(moments, suns, strict=True):
        if elevation_deg <= 0:
            raise DesignerError(
                f"sun-over-time: the sun is {abs(elevation_deg):.1f}° below the horizon at "
                f"{t.isoformat()} ({site.latitude_deg:.4f}°, {site.longitude_deg:.4f}°); "
                "move <time-line> takeoff-utc into daylight")
    return suns


def takeoff_sun(project: m.Project, sun: m.SunOverTime) -> tuple[float, float]:
    """The sun at the time line's take-off (the scene's one sun where one is needed)."""
    time_line = project.trajectory.time_line
    moment = None if time_line is None else parse_utc(time_line.takeoff_utc)
    if moment is None:
        raise DesignerError("sun-over-time needs a <time-line> with a UTC takeoff-utc, e.g. "
                            f"{EXAMPLE_UTC}")
    return sun_at(moment, project_site(project, sun))
