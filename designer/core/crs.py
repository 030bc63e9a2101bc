"""Coordinate reference system labels as projects write them (no pyproj here).

A project's ``<crs>`` is a label such as ``EPSG:32632 (WGS 84 / UTM zone 32N)``; the
exchange formats want a bare token. OpenDroneMap's parse_srs_header (opendm/location.py)
accepts ``EPSG:<code>``, ``WGS84 UTM <zone><N|S>`` or a PROJ string with ``+proj``; the
project validation and the ODM exporter both ask :func:`odm_accepts_crs`.
"""

from __future__ import annotations

import re

_EPSG_PREFIX = re.compile(r"\s*(EPSG:\d+)")
_UTM = re.compile(r"^WGS84 UTM \d{1,2}[NS]$", re.IGNORECASE)
_EPSG = re.compile(r"^EPSG:\d+$", re.IGNORECASE)


def crs_token(label: str) -> str:
    """The leading 'EPSG:n' of a label such as 'EPSG:32632 (WGS 84 / UTM zone 32N)', or
    the label itself when it does not start with one."""
    match = _EPSG_PREFIX.match(label)
    return match.group(1) if match else label


def odm_accepts_crs(line: str) -> bool:
    """Whether OpenDroneMap reads ``line`` as the CRS header of gcp_list.txt / geo.txt."""
    line = line.strip()
    return bool(_EPSG.match(line) or _UTM.match(line) or "+proj" in line)
