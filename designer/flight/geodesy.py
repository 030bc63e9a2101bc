"""The project's CRS and WGS 84: positions and the direction of true north.

Drones and flight software work in WGS 84 latitude/longitude (EPSG:4326) and measure
headings from TRUE north; the project's world frame is its CRS's grid (X = Easting,
Y = Northing). Grid north and true north differ by the meridian convergence γ; pyproj's
``Proj.get_factors(...).meridian_convergence`` is γ in degrees with the sign that makes

    grid azimuth = true azimuth − γ

(east of a UTM zone's central meridian in the northern hemisphere γ > 0: true north
points to the west of grid north). :func:`Georef.true_north_azimuth_deg` returns −γ, the
grid azimuth of true north; a test checks it against a finite difference of the
projection on both sides of the central meridian.

Heights pass through unchanged: the project's Z is whatever height its CRS label says
(a UTM CRS is 2-D; see docs/real-data.md for the height assumptions of each format).
"""

from __future__ import annotations

import numpy as np

from designer.core.crs import crs_token
from designer.errors import DesignerError

WGS84 = "EPSG:4326"


class Georef:
    """Conversions between one projected CRS (the project's) and WGS 84 / other CRSs."""

    def __init__(self, crs_label: str):
        from pyproj import CRS, Proj, Transformer
        from pyproj.exceptions import CRSError

        token = crs_token(crs_label)
        try:
            self.crs = CRS.from_user_input(token)
        except CRSError as error:
            raise DesignerError(f"CRS {crs_label!r} is not known to PROJ ({error}); give an "
                                "'EPSG:<code>' label") from None
        if not self.crs.is_projected:
            raise DesignerError(f"CRS {crs_label!r} is not a projected CRS; the project's world "
                                "frame needs metres (e.g. a UTM zone, EPSG:326xx)")
        self.label = token
        self._proj = Proj(self.crs)
        self._to_ll = Transformer.from_crs(self.crs, WGS84, always_xy=True)
        self._from_ll = Transformer.from_crs(WGS84, self.crs, always_xy=True)

    def to_lonlat(self, X, Y) -> tuple[np.ndarray, np.ndarray]:
        """WGS 84 longitude, latitude (deg) of grid points X, Y (m)."""
        lon, lat = self._to_ll.transform(np.asarray(X, float), np.asarray(Y, float))
        return np.asarray(lon, float), np.asarray(lat, float)

    def from_lonlat(self, lon, lat) -> tuple[np.ndarray, np.ndarray]:
        """Grid X, Y (m) of WGS 84 longitude, latitude (deg)."""
        X, Y = self._from_ll.transform(np.asarray(lon, float), np.asarray(lat, float))
        return np.asarray(X, float), np.asarray(Y, float)

    def from_crs(self, crs_label: str, x, y) -> tuple[np.ndarray, np.ndarray]:
        """Grid X, Y (m) of points given in another CRS (x, y in that CRS's east/north or
        lon/lat order)."""
        if crs_token(crs_label) == self.label:
            return np.asarray(x, float), np.asarray(y, float)
        from pyproj import Transformer

        t = Transformer.from_crs(_crs(crs_label), self.crs, always_xy=True)
        X, Y = t.transform(np.asarray(x, float), np.asarray(y, float))
        return np.asarray(X, float), np.asarray(Y, float)

    def true_north_azimuth_deg(self, X, Y) -> np.ndarray:
        """Grid azimuth (deg, clockwise from grid north) of true north at grid X, Y."""
        lon, lat = self.to_lonlat(X, Y)
        factors = self._proj.get_factors(lon, lat)
        return -np.asarray(factors.meridian_convergence, float)


def north_azimuth_in(crs_label: str, georef: Georef, X, Y) -> np.ndarray:
    """Grid azimuth in the project's CRS of the north of ``crs_label`` at project X, Y.

    A geographic CRS's north is true north; a projected CRS's north is its grid north
    (the difference of the two CRSs' convergences). Zero for the project's own CRS.
    """
    if crs_token(crs_label) == georef.label:
        return np.zeros(np.shape(X))
    other = _crs(crs_label)
    tn = georef.true_north_azimuth_deg(X, Y)
    if other.is_geographic:
        return tn
    from pyproj import Proj

    lon, lat = georef.to_lonlat(X, Y)
    gamma_other = np.asarray(Proj(other).get_factors(lon, lat).meridian_convergence, float)
    return tn + gamma_other


def _crs(label: str):
    from pyproj import CRS
    from pyproj.exceptions import CRSError

    try:
        return CRS.from_user_input(crs_token(label))
    except CRSError as error:
        raise DesignerError(f"CRS {label!r} is not known to PROJ ({error}); give an "
                            "'EPSG:<code>' label") from None
