"""The flight's time line: when each photo is taken (docs/world.md, "Flight time line").

Model: the first station is photographed at the time line's ``takeoff_utc`` (time 0;
the climb from the take-off point to it is not modelled). The stations are then flown
in the order the project lists them (explicit photos, then the flight plan) along
straight legs at ``speed_m_s`` (3-D distance between perspective centres / speed), and
each change of flight line of the plan adds ``turn_s``. Photos are triggered by
distance: at the planned stations, so the overlaps are exactly those planned and the
speed only sets their times. An explicit photo's ``time_s`` replaces its computed time;
the stations after it continue from there.

Times are seconds after take-off (float64) and UTC moments (aware datetimes with
microseconds).
"""

from __future__ import annotations

import datetime as _dt
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from designer.errors import DesignerError
from designer.project import model as m
from designer.project.utc import EXAMPLE_UTC, parse_utc
from designer.survey.flight import Station


@dataclass(frozen=True)
class StationTime:
    """When one photo is taken: seconds after take-off and the UTC moment."""

    image_name: str
    time_s: float
    time_utc: _dt.datetime


def takeoff_moment(time_line: m.TimeLine) -> _dt.datetime:
    """The time line's take-off moment (aware, UTC); DesignerError if it is not UTC."""
    moment = parse_utc(time_line.takeoff_utc)
    if moment is None:
        raise DesignerError(f"time-line takeoff-utc {time_line.takeoff_utc!r} is not an ISO "
                            f"8601 moment in UTC; write it with Z, e.g. {EXAMPLE_UTC}")
    return moment


def station_times_s(
    stations: Sequence[Station], time_line: m.TimeLine,
    fixed_s: Sequence[float | None] = (),
) -> np.ndarray:
    """Seconds after take-off of each station (module docstring).

    ``fixed_s[k]`` (when given and not None) is station k's own time, e.g. an explicit
    photo's ``time-s``. Turns are counted between two planned stations (line index ≥ 0)
    on different lines.
    """
    times = np.zeros(len(stations))
    for k, st in enumerate(stations):
        fixed = fixed_s[k] if k < len(fixed_s) else None
        if fixed is not None:
            times[k] = fixed
            continue
        if k == 0:
            continue
        prev = stations[k - 1]
        leg_m = float(np.linalg.norm(st.C_world - prev.C_world))
        turn = (time_line.turn_s if prev.line_index >= 0 and st.line_index >= 0
                and st.line_index != prev.line_index else 0.0)
        times[k] = times[k - 1] + leg_m / time_line.speed_m_s + turn
    return times


def project_station_times(project: m.Project, stations: Sequence[Station]
                          ) -> list[StationTime] | None:
    """The time of each station of ``project`` (as from project_stations), or None when
    the trajectory has no time line (the static ideal: photos have no time)."""
    time_line = project.trajectory.time_line
    if time_line is None:
        return None
    takeoff = takeoff_moment(time_line)
    fixed = [eo.time_s for eo in project.trajectory.exterior_orientations]
    times = station_times_s(stations, time_line, fixed)
    return [StationTime(st.image_name, float(t), takeoff + _dt.timedelta(seconds=float(t)))
            for st, t in zip(stations, times, strict=True)]


def station_velocities_m_s(stations: Sequence[Station], time_line: m.TimeLine) -> np.ndarray:
    """(N, 3) velocity of the platform at each station, world m/s (docs/world.md,
    "Rolling shutter"): ``speed_m_s`` along the leg flown from the station to the next
    one; where that leg is a turn to another flight line (or there is no next station),
    along the leg that led to it; a station with neither flies horizontally along its
    flight azimuth. The legs are straight and flown at constant speed, as the time line
    times them."""
    n = len(stations)
    out = np.zeros((n, 3))

    def straight(a: Station, b: Station) -> np.ndarray | None:
        turn = a.line_index >= 0 and b.line_index >= 0 and a.line_index != b.line_index
        leg = b.C_world - a.C_world
        length = float(np.linalg.norm(leg))
        return None if turn or length == 0.0 else leg / length

    for k, st in enumerate(stations):
        direction = straight(st, stations[k + 1]) if k + 1 < n else None
        if direction is None and k > 0:
            direction = straight(stations[k - 1], st)
        if direction is None:
            az = np.radians(st.flight_azimuth_deg)
            direction = np.array([np.sin(az), np.cos(az), 0.0])
        out[k] = time_line.speed_m_s * direction
    return out
