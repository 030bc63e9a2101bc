"""A project's planned exposures as a drone flies them, and flown points read back.

The exported flight is the project's PLAN: explicit exterior orientations (imported
photos), in the flight lines they were flown in as the window shows them
(:func:`designer.survey.project_poses.explicit_stations`), followed by the flight plan's
stations without pose noise (the noise models what the real flight will get wrong, not
what it is asked to do). The plan's trigger distance is for the plan's lines; an
imported photo is taken at its own waypoint (:attr:`Exposure.planned` is False). Each
exposure carries its grid position, WGS 84 latitude/longitude, the ground height below
it (from the project's terrain) and DJI gimbal angles with yaw from TRUE north
(:mod:`designer.flight.gimbal`).

Heights: the project's Z is written where a format wants an absolute height (QGC AMSL,
KML ``absolute``, WPML ``WGS84``) plus ``height_offset_m`` (e.g. the geoid undulation
N to turn orthometric heights into the ellipsoidal heights WPML's WGS84 mode expects);
relative heights are Z − take-off height. The take-off point is below the first
exposure, on the terrain, unless a take-off height is given.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from designer.errors import DesignerError
from designer.flight.geodesy import Georef
from designer.flight.gimbal import gimbal_from_rotation, rotation_from_gimbal, wrap_deg
from designer.project import model as m
from designer.project.interiors import interior_from_camera
from designer.scene.build import build_heightfield
from designer.survey.flight import camera_calc
from designer.survey.project_poses import IMAGE_EXTENSIONS, explicit_stations, flight_plan_for

ALTITUDE_MODES = ("relative", "amsl")


@dataclass(frozen=True)
class Exposure:
    """One planned photo: grid position (m), WGS 84 position (deg), ground below (m or
    None without a height-field terrain), gimbal angles (deg, yaw from true north);
    ``planned`` when the flight plan placed it (its line is flown with the plan's
    trigger distance), False for an explicit exterior orientation."""

    name: str
    line: int
    X_m: float
    Y_m: float
    Z_m: float
    lon_deg: float
    lat_deg: float
    ground_m: float | None
    yaw_true_deg: float
    pitch_deg: float
    roll_deg: float
    planned: bool = True


@dataclass(frozen=True)
class FlightSpec:
    """What every writer needs: exposures in flight order and the flight's settings."""

    name: str
    camera: m.Camera
    exposures: tuple[Exposure, ...]
    altitude: str
    terrain_following: bool
    trigger_distance_m: float | None
    takeoff_lon_deg: float
    takeoff_lat_deg: float
    takeoff_Z_m: float
    height_offset_m: float = 0.0
    speed_m_s: float = 5.0

    def absolute_height(self, Z_m: float) -> float:
        """A project height as written where a format wants an absolute height."""
        return Z_m + self.height_offset_m

    def relative_height(self, Z_m: float) -> float:
        return Z_m - self.takeoff_Z_m

    @property
    def lines(self) -> list[list[Exposure]]:
        out: list[list[Exposure]] = []
        for e in self.exposures:
            if not out or out[-1][-1].line != e.line:
                out.append([])
            out[-1].append(e)
        return out


@dataclass(frozen=True)
class FlownPoint:
    """A photo position read from a flight file: WGS 84 (deg), the project's height Z (m)
    and gimbal angles (deg, yaw from true north); ``name`` when the format keeps one."""

    name: str | None
    lon_deg: float
    lat_deg: float
    Z_m: float
    yaw_true_deg: float
    pitch_deg: float
    roll_deg: float


def flight_spec(
    project: m.Project, base_dir: Path, *, altitude: str = "relative",
    takeoff_height_m: float | None = None, height_offset_m: float = 0.0,
    speed_m_s: float = 5.0,
) -> FlightSpec:
    """The planned exposures of ``project`` (see the module docstring)."""
    if altitude not in ALTITUDE_MODES:
        raise DesignerError(f"altitude mode {altitude!r}: use one of {', '.join(ALTITUDE_MODES)}")
    if not (math.isfinite(speed_m_s) and speed_m_s > 0):
        raise DesignerError(f"speed {speed_m_s} m/s must be > 0")
    georef = Georef(project.crs)
    hf = build_heightfield(project.scene.terrain, Path(base_dir), project.crs)
    extension = IMAGE_EXTENSIONS[project.render.output_format]
    rows: list[tuple[str, int, np.ndarray, np.ndarray, bool]] = [
        (s.image_name, s.line_index, s.C_world, s.R_cam_to_world, False)
        for s in explicit_stations(project)]
    cameras = [eo.camera for eo in project.trajectory.exterior_orientations]
    plan = project.trajectory.flight_plan
    trigger = None
    terrain_following = False
    if plan is not None:
        interior = interior_from_camera(project.camera(plan.camera))
        planned = flight_plan_for(plan, interior, hf, extension)
        first = 1 + max((r[1] for r in rows), default=-1)
        rows += [(s.image_name, first + s.line_index, s.C_world, s.R_cam_to_world, True)
                 for s in planned.stations]
        cameras += [plan.camera] * len(planned.stations)
        trigger = camera_calc(
            interior, altitude_agl_m=plan.altitude_agl_m, gsd_m=plan.gsd_m,
            front_overlap_fraction=plan.front_overlap_percent / 100,
            side_overlap_fraction=plan.side_overlap_percent / 100,
            orientation=plan.orientation).trigger_distance_m
        terrain_following = plan.terrain_following
    if not rows:
        raise DesignerError("the project has no camera stations to fly: add exterior "
                            "orientations or a flight plan")
    if len(set(cameras)) > 1:
        raise DesignerError(f"the stations use several cameras ({', '.join(sorted(set(cameras)))})"
                            "; a flight carries one camera")
    C = np.array([r[2] for r in rows])
    lon, lat = georef.to_lonlat(C[:, 0], C[:, 1])
    north = georef.true_north_azimuth_deg(C[:, 0], C[:, 1])
    ground = hf.height_at_clamped(C[:, 0], C[:, 1]) if hf is not None else None
    exposures = []
    for k, (name, line, c, R, is_planned) in enumerate(rows):
        yaw_grid, pitch, roll = gimbal_from_rotation(R)
        exposures.append(Exposure(
            name, line, float(c[0]), float(c[1]), float(c[2]), float(lon[k]), float(lat[k]),
            None if ground is None else float(ground[k]), wrap_deg(yaw_grid - north[k]),
            pitch, roll, is_planned))
    if takeoff_height_m is None:
        if ground is None:
            raise DesignerError("the terrain is a mesh, so the take-off height is unknown; "
                                "give --takeoff-height-m")
        takeoff_height_m = float(ground[0])
    if terrain_following and ground is None:
        raise DesignerError("terrain following needs a height-field terrain (flat, "
                            "procedural or DEM)")
    return FlightSpec(
        name=project.name, camera=project.camera(cameras[0]), exposures=tuple(exposures),
        altitude=altitude, terrain_following=terrain_following, trigger_distance_m=trigger,
        takeoff_lon_deg=float(lon[0]), takeoff_lat_deg=float(lat[0]),
        takeoff_Z_m=float(takeoff_height_m), height_offset_m=float(height_offset_m),
        speed_m_s=float(speed_m_s))


def pose_of(point: FlownPoint, georef: Georef) -> tuple[np.ndarray, np.ndarray]:
    """Grid perspective centre (3,) and R_cam_to_world (3, 3) of a flown point."""
    X, Y = georef.from_lonlat(point.lon_deg, point.lat_deg)
    north = float(georef.true_north_azimuth_deg(X, Y))
    R = rotation_from_gimbal(point.yaw_true_deg + north, point.pitch_deg, point.roll_deg)
    return np.array([float(X), float(Y), point.Z_m]), R
