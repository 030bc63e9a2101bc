"""Coordinate reference system labels as projects write them, and the CRS facts exports need.

A project's ``<crs>`` is a label such as ``EPSG:32632 (WGS 84 / UTM zone 32N)``; the
exchange formats want a bare token. OpenDroneMap reads the first line of gcp_list.txt
and geo.txt with ``parse_srs_header`` (OpenDroneMap/ODM opendm/location.py):

* the line is stripped and split on single spaces; ``WGS84 UTM <zone><pole>`` is taken
  only when the first two words are exactly ``WGS84`` and ``UTM`` (case matters), the
  zone is ``int()`` of the third word without its last character and the pole is that
  character upper-cased (anything but ``S`` means north);
* otherwise a line containing ``+proj`` is a PROJ string (``CRS.from_proj4``);
* otherwise a line starting with ``epsg:`` in any case is ``CRS.from_epsg`` of the rest;
* anything else stops ODM with "Bad SRS supplied".

:func:`odm_accepts_crs` accepts a subset of that on which ODM cannot misread: the UTM
form with a zone 1–60 and pole N or S, a ``+proj`` string, or ``EPSG:<digits>``.
ODM then converts the coordinates to latitude/longitude with that CRS, so they must be
projected metres: :func:`odm_crs_problem` (pyproj, imported lazily) rejects geographic
CRSs such as EPSG:4326, where ODM would read metres as degrees, and non-metre units.

:func:`meridian_convergence_deg` gives the angle from true north to grid north (PROJ's
``meridian_convergence``, positive when grid north lies east of true north: east of a
UTM zone's central meridian in the northern hemisphere), for exports whose angles are
referred to true north.
"""

from __future__ import annotations

import re

import numpy as np

_EPSG_PREFIX = re.compile(r"\s*(EPSG:\d+)")
_UTM = re.compile(r"^WGS84 UTM (\d{1,2})[NS]$")
_EPSG = re.compile(r"^EPSG:\d+$", re.IGNORECASE)


def crs_token(label: str) -> str:
    """The leading 'EPSG:n' of a label such as 'EPSG:32632 (WGS 84 / UTM zone 32N)', or
    the label itself when it does not start with one."""
    match = _EPSG_PREFIX.match(label)
    return match.group(1) if match else label


def odm_accepts_crs(line: str) -> bool:
    """Whether OpenDroneMap reads ``line`` as the CRS header of gcp_list.txt / geo.txt,
    exactly as written (see the module doc; no pyproj needed)."""
    line = line.strip()
    utm = _UTM.match(line)
    if utm:
        return 1 <= int(utm.group(1)) <= 60
    if line.startswith("WGS84 UTM") or line.upper().startswith("WGS84 UTM"):
        return False  # malformed UTM form (lower case, zone 0 or > 60, extra words)
    return bool(_EPSG.match(line) or "+proj" in line)


def odm_crs(line: str):
    """The pyproj CRS OpenDroneMap builds from an accepted header line (its rules)."""
    from pyproj import CRS

    line = line.strip()
    utm = _UTM.match(line)
    if utm:
        south = " +south=True" if line.endswith("S") else ""
        return CRS.from_proj4(f"+proj=utm +zone={int(utm.group(1))} +datum=WGS84 +units=m "
                              f"+no_defs=True{south}")
    if "+proj" in line:
        return CRS.from_proj4(line.strip("'"))
    return CRS.from_epsg(int(line[5:]))


def odm_crs_problem(line: str) -> str | None:
    """Why OpenDroneMap cannot use ``line`` for metre coordinates, or None when it can."""
    if not odm_accepts_crs(line):
        return ("OpenDroneMap cannot read it; give 'EPSG:<code>', 'WGS84 UTM <zone 1-60><N|S>' "
                "(upper case) or a PROJ string with +proj")
    from pyproj.exceptions import CRSError

    try:
        crs = odm_crs(line)
    except CRSError as exc:
        return f"pyproj cannot build it ({str(exc).splitlines()[0]})"
    if not crs.is_projected:
        return ("it is not a projected CRS: OpenDroneMap would read the metre coordinates as "
                "degrees; give a projected CRS in metres such as a UTM zone")
    units = {axis.unit_name for axis in crs.axis_info[:2]}
    if units - {"metre", "meter"}:
        return f"its axes are in {', '.join(sorted(units))}, not metres"
    return None


def meridian_convergence_deg(line: str, E_m, N_m) -> np.ndarray:
    """Angle (deg) from true north to grid north at projected points (E_m, N_m) of the
    CRS ``line`` (an OpenDroneMap header): true azimuth = grid azimuth + this."""
    from pyproj import Proj

    proj = Proj(odm_crs(line))
    E, N = np.broadcast_arrays(np.asarray(E_m, float), np.asarray(N_m, float))
    lon, lat = proj(E.ravel().tolist(), N.ravel().tolist(), inverse=True)
    gamma = proj.get_factors(lon, lat).meridian_convergence
    return np.asarray(gamma, dtype=float).reshape(E.shape)
