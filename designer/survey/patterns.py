"""Orbit and facade flights: stations around a point of interest or along a facade.

World frame X = east, Y = north, Z = up (m); headings clockwise from grid north;
camera rotations from :func:`designer.core.rotation.rotation_from_heading_tilt_roll`
(image top towards the heading, tilted from nadir). Stations are :class:`Station` s of
the grid planner, so a rig, the time line, the exports and the GUI treat them alike.
"""

from __future__ import annotations

import math

import numpy as np

from designer.core.rotation import rotation_from_heading_tilt_roll
from designer.survey.flight import Station


def _azimuth_deg(dx: float, dy: float) -> float:
    return math.degrees(math.atan2(dx, dy)) % 360.0


def orbit_stations(
    centre_world, radius_m: float, height_m: float, n_stations: int,
    tilt_deg: float | None = None, start_azimuth_deg: float = 0.0,
    image_name_format: str = "ORB_{index:05d}.png", first_index: int = 1,
    line_index: int = 0,
) -> list[Station]:
    """``n_stations`` stations evenly spaced clockwise on a circle of ``radius_m`` around
    ``centre_world`` (3,), ``height_m`` above it, the first at ``start_azimuth_deg`` from
    the centre. Each camera faces the centre, image top away from the ground, its viewing
    axis ``tilt_deg`` from nadir (None: aimed exactly at the centre,
    atan(radius / height)). Flight azimuth: along the circle."""
    centre = np.asarray(centre_world, float)
    if tilt_deg is None:
        tilt_deg = math.degrees(math.atan2(radius_m, height_m))
    out = []
    for k in range(n_stations):
        a = math.radians(start_azimuth_deg + 360.0 * k / n_stations)
        C = centre + np.array([radius_m * math.sin(a), radius_m * math.cos(a), height_m])
        heading = (math.degrees(a) + 180.0) % 360.0  # towards the centre
        R = rotation_from_heading_tilt_roll(math.radians(heading), math.radians(tilt_deg), 0.0)
        out.append(Station(image_name_format.format(index=first_index + k), C, R, line_index,
                           0, (math.degrees(a) + 90.0) % 360.0))
    return out


def facade_stations(
    start_xy, end_xy, base_Z: float, distance_m: float, heights_m, spacing_m: float,
    side: str = "right", tilt_deg: float = 0.0,
    image_name_format: str = "FAC_{index:05d}.png", first_index: int = 1,
    first_line_index: int = 0,
) -> list[Station]:
    """Rows of stations parallel to the facade segment ``start_xy`` → ``end_xy`` (world
    X, Y, m) at ``distance_m`` from it on its ``side`` (seen walking from start to end),
    every ``spacing_m`` along it (both ends included when the length is a multiple of
    it), one row per height in ``heights_m`` above ``base_Z``; odd rows are flown
    backwards. Each camera faces the facade, ``tilt_deg`` below the horizontal."""
    p0, p1 = np.asarray(start_xy, float), np.asarray(end_xy, float)
    length = float(np.linalg.norm(p1 - p0))
    along = (p1 - p0) / length
    right = np.array([along[1], -along[0]])  # clockwise from the walking direction
    outward = right if side == "right" else -right
    n = math.floor(length / spacing_m + 1e-9) + 1
    offsets = np.arange(n) * spacing_m
    heading = _azimuth_deg(*-outward)  # towards the facade
    R = rotation_from_heading_tilt_roll(math.radians(heading), math.radians(90.0 - tilt_deg),
                                        0.0)
    out = []
    index = first_index
    for row, h in enumerate(heights_m):
        forward = row % 2 == 0
        order = offsets if forward else offsets[::-1]
        azimuth = _azimuth_deg(*(along if forward else -along))
        for s in order:
            xy = p0 + s * along + distance_m * outward
            out.append(Station(image_name_format.format(index=index),
                               np.array([xy[0], xy[1], base_Z + h]), R,
                               first_line_index + row, 0, azimuth))
            index += 1
    return out
