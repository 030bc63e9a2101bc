"""A project's camera stations: explicit exterior orientations and/or its flight plan.

The flight plan is generated deterministically from its parameters and seed, so the
same file always gives the same poses; ``designer plan --write-poses`` stores them in
the XML as explicit exterior orientations for readers that want them spelled out.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from designer.core.heightfield import Heightfield
from designer.core.interior import InteriorOrientation
from designer.core.rig import mount_image_name, mount_rotation, mount_tilt_deg, mounted_rotation
from designer.core.rotation import rotation_from_opk
from designer.core.truth import CameraPose
from designer.errors import DesignerError
from designer.project import model as m
from designer.project.interiors import interior_from_camera
from designer.survey.flight import FlightPlan, Station, apply_pose_noise, plan_flight
from designer.survey.patterns import facade_stations, orbit_stations

IMAGE_EXTENSIONS = {"png": ".png", "jpeg": ".jpg", "tiff": ".tif", "exr": ".exr"}


def flight_plan_for(
    plan: m.FlightPlan, interior: InteriorOrientation, hf: Heightfield | None,
    extension: str,
) -> FlightPlan:
    """The planned stations (without noise) of a project's flight plan."""
    reference = plan.altitude_reference
    if hf is None and isinstance(reference, str) and not plan.terrain_following:
        raise DesignerError(
            "the flight plan's altitude reference is the terrain's "
            f"{reference} height, but the terrain is a mesh; give a numeric reference height")
    return plan_flight(
        np.array(plan.area, dtype=float), interior,
        altitude_agl_m=plan.altitude_agl_m, gsd_m=plan.gsd_m,
        front_overlap_fraction=plan.front_overlap_percent / 100.0,
        side_overlap_fraction=plan.side_overlap_percent / 100.0,
        grid_angle_deg=plan.grid_angle_deg, crosshatch=plan.crosshatch, heightfield=hf,
        altitude_mode="terrain_following" if plan.terrain_following else "constant",
        altitude_reference=reference, forward_tilt_deg=plan.tilt_deg,
        orientation=plan.orientation, start_corner=plan.start_corner,
        image_name_format=plan.image_prefix + "{index:05d}" + extension, first_index=1)


def planning_camera_id(project: m.Project, camera_or_rig: str) -> str:
    """The camera a flight is planned for: the camera itself, or for a rig the camera of
    the mount looking closest to the platform's axis (the first of equals)."""
    rig = project.trajectory.rig(camera_or_rig)
    if rig is None:
        return camera_or_rig
    tilts = [mount_tilt_deg(mt.omega_deg, mt.phi_deg, mt.kappa_deg) for mt in rig.mounts]
    return rig.mounts[tilts.index(min(tilts))].camera


#: a photo whose heading, or whose step from the previous photo, turns more than this
#: from its line's starts a new flight line (degrees)
LINE_TURN_DEG = 30.0
#: a step longer than this many times its line's median spacing starts a new line
LINE_JUMP = 2.0


def photo_lines(xy_world: np.ndarray, heading_deg: np.ndarray
                ) -> tuple[np.ndarray, np.ndarray]:
    """Flight lines and grids of photos in flight order, as a surveyor reads a pose list.

    xy_world: (M, 2) perspective centres (m); heading_deg: (M,) image-top azimuths
    (clockwise from north). Consecutive photos form a line while the heading stays
    within :data:`LINE_TURN_DEG` of the line's first photo's, each step runs within as
    much of the line's direction (its first to its latest photo) and is at most
    :data:`LINE_JUMP` times the line's median step; a turn or a jump starts the next line.
    A line whose direction (either way) turns more than :data:`LINE_TURN_DEG` from the
    previous line's starts the next grid (a crosshatch). Returns (M,) line and grid
    indices, both counting from 0 in flight order.
    """
    xy = np.asarray(xy_world, dtype=float).reshape(-1, 2)
    heading = np.asarray(heading_deg, dtype=float).reshape(-1)
    M = len(xy)
    line = np.zeros(M, dtype=int)
    start = 0
    for k in range(1, M):
        step = xy[k] - xy[k - 1]
        new = _turn_deg(heading[k], heading[start]) > LINE_TURN_DEG
        if k - start >= 2 and np.hypot(*step) > 0:
            track = xy[k - 1] - xy[start]
            spacing = np.median(np.hypot(*np.diff(xy[start:k], axis=0).T))
            new |= (_turn_deg(_azimuth_deg(step), _azimuth_deg(track)) > LINE_TURN_DEG
                    or np.hypot(*step) > LINE_JUMP * spacing)
        if new:
            start = k
        line[k] = line[k - 1] + int(new)
    grid = np.zeros(M, dtype=int)
    axis = None  # the previous line's direction, modulo 180°
    for L in range(int(line.max(initial=-1)) + 1):
        mine = np.flatnonzero(line == L)
        if len(mine) >= 2:
            a = _azimuth_deg(xy[mine[-1]] - xy[mine[0]]) % 180.0
            turned = axis is not None and min(_turn_deg(a, axis),
                                             _turn_deg(a + 180.0, axis)) > LINE_TURN_DEG
            axis = a
        else:
            turned = False
        grid[mine] = grid[mine[0] - 1] + int(turned) if mine[0] else 0
    return line, grid


def _azimuth_deg(v: np.ndarray) -> float:
    return math.degrees(math.atan2(v[0], v[1]))


def _turn_deg(a: float, b: float) -> float:
    """The angle (0–180°) between azimuths ``a`` and ``b``."""
    return abs((a - b + 180.0) % 360.0 - 180.0)


def explicit_stations(project: m.Project) -> list[Station]:
    """The project's explicit exterior orientations as stations, in order, grouped into
    the flight lines and grids they were flown in (:func:`photo_lines`, both numbered
    from 0); each station's flight azimuth is its image-top azimuth (deg from grid north)."""
    eos = project.trajectory.exterior_orientations
    rotations = [rotation_from_opk(*(math.radians(a) for a in (eo.omega_deg, eo.phi_deg,
                                                               eo.kappa_deg))) for eo in eos]
    headings = np.array([math.degrees(math.atan2(R[0, 1], R[1, 1])) % 360.0
                         for R in rotations])
    lines, grids = photo_lines(np.array([[eo.X, eo.Y] for eo in eos]).reshape(-1, 2),
                               headings)
    return [Station(eo.name, np.array([eo.X, eo.Y, eo.Z]), R, int(line), int(grid),
                    float(heading))
            for eo, R, heading, line, grid in zip(eos, rotations, headings, lines, grids,
                                                  strict=True)]


def platform_stations(
    project: m.Project, hf: Heightfield | None
) -> tuple[list[Station], list[str]]:
    """The stations in order (explicit ones first) and the camera or rig of each."""
    extension = IMAGE_EXTENSIONS[project.render.output_format]
    explicit = explicit_stations(project)
    # numbered below the flight plan's lines and grids (0, 1, …): never their neighbours
    lines = 1 + max((s.line_index for s in explicit), default=-1)
    grids = 1 + max((s.grid_index for s in explicit), default=-1)
    stations: list[Station] = [
        replace(s, line_index=s.line_index - lines,
                            grid_index=s.grid_index - grids) for s in explicit]
    carriers = [eo.camera for eo in project.trajectory.exterior_orientations]
    plan = project.trajectory.flight_plan
    if plan is not None:
        # Flight planning uses the full-size camera: overlaps do not depend on scaling.
        interior = interior_from_camera(project.camera(planning_camera_id(project,
                                                                          plan.camera)))
        planned = list(flight_plan_for(plan, interior, hf, extension).stations)
        noise = plan.pose_noise
        if noise is not None:
            planned = apply_pose_noise(
                planned, (noise.sigma_X_m, noise.sigma_Y_m, noise.sigma_Z_m),
                (noise.sigma_omega_deg, noise.sigma_phi_deg, noise.sigma_kappa_deg),
                seed=plan.random_seed)
        stations.extend(planned)
        carriers.extend([plan.camera] * len(planned))
    for pattern in project.trajectory.patterns:
        line = 1 + max((s.line_index for s in stations), default=-1)
        name_format = pattern.image_prefix + "{index:05d}" + extension
        if isinstance(pattern, m.OrbitPattern):
            c = pattern.centre
            flown = orbit_stations((c.X, c.Y, c.Z), pattern.radius_m, pattern.height_m,
                                   pattern.n_stations, pattern.tilt_deg,
                                   pattern.start_azimuth_deg, name_format, 1, line)
        else:
            flown = facade_stations(pattern.start, pattern.end, pattern.base_Z,
                                    pattern.distance_m, pattern.heights_m, pattern.spacing_m,
                                    pattern.side, pattern.tilt_deg, name_format, 1, line)
        stations.extend(flown)
        carriers.extend([pattern.camera] * len(flown))
    if not stations:
        raise DesignerError("the project has no camera stations: add exterior orientations, "
                            "a flight plan, an orbit or a facade to its trajectory")
    return stations, carriers


def project_stations(
    project: m.Project, hf: Heightfield | None,
    platform: tuple[list[Station], list[str]] | None = None,
) -> tuple[list[Station], str]:
    """All stations of the project in order (explicit ones first) and their camera id.

    Explicit exterior orientations are grouped into flight lines and grids as they were
    flown (:func:`photo_lines`), numbered below the flight plan's. A station flown with a
    rig is the platform's pose, with the rig's planning camera
    (:func:`planning_camera_id`); :func:`project_images` gives its images. Without a rig
    every station must use the same camera; with one the returned camera is the first
    station's planning camera. ``platform``: :func:`platform_stations` of the same
    project and terrain, when the caller has it (the flight is then not planned again).
    """
    stations, carriers = platform if platform is not None else platform_stations(project, hf)
    camera_ids = [planning_camera_id(project, c) for c in carriers]
    # with rigs several cameras are the point: the figures are then the first station's
    # planning camera's (project_images gives every image its own)
    if len(set(camera_ids)) > 1 and not project.trajectory.rigs:
        raise DesignerError(
            f"stations use several cameras ({', '.join(sorted(set(camera_ids)))}); render one "
            "camera per project, or mount them on a rig")
    _check_unique_names([s.image_name for s in stations])
    return stations, camera_ids[0]


@dataclass(frozen=True)
class ProjectImages:
    """Every image of a project in render order: a station without a rig gives one image,
    a rig station one per mount (in mount order, the mount's camera turned by its
    rotation, :mod:`designer.core.rig`).

    ``stations[k]`` is image k's pose, ``camera_ids[k]`` its camera, ``station_index[k]``
    the index of the platform station it was taken at (into ``platform``).
    """

    stations: tuple[Station, ...]
    camera_ids: tuple[str, ...]
    station_index: tuple[int, ...]
    platform: tuple[Station, ...]

    @property
    def is_multi_camera(self) -> bool:
        return len(set(self.camera_ids)) > 1

    def camera_order(self) -> tuple[str, ...]:
        """The distinct camera ids in order of first use."""
        return tuple(dict.fromkeys(self.camera_ids))


def project_images(project: m.Project, hf: Heightfield | None,
                   platform: tuple[list[Station], list[str]] | None = None) -> ProjectImages:
    """All images of the project (see :class:`ProjectImages`); a project without a rig has
    one image per station, exactly :func:`project_stations`'. ``platform``: as
    :func:`project_stations` takes it."""
    platform, carriers = platform if platform is not None else platform_stations(project, hf)
    stations, cameras, index = [], [], []
    for k, (st, carrier) in enumerate(zip(platform, carriers, strict=True)):
        rig = project.trajectory.rig(carrier)
        if rig is None:
            stations.append(st)
            cameras.append(carrier)
            index.append(k)
            continue
        for mount in rig.mounts:
            R = mounted_rotation(st.R_cam_to_world, mount_rotation(
                mount.omega_deg, mount.phi_deg, mount.kappa_deg))
            stations.append(Station(mount_image_name(st.image_name, mount.suffix), st.C_world,
                                    R, st.line_index, st.grid_index, st.flight_azimuth_deg))
            cameras.append(mount.camera)
            index.append(k)
    if len(set(cameras)) > 1 and not project.trajectory.rigs:
        raise DesignerError(
            f"stations use several cameras ({', '.join(sorted(set(cameras)))}); render one "
            "camera per project, or mount them on a rig")
    _check_unique_names([s.image_name for s in stations])
    return ProjectImages(tuple(stations), tuple(cameras), tuple(index), tuple(platform))


def _check_unique_names(names: list[str]) -> None:
    if len(set(names)) != len(names):
        dup = next(n for n in names if names.count(n) > 1)
        raise DesignerError(f"image name {dup} is used twice (explicit and planned stations "
                            "overlap, or a rig's suffix repeats a name); change the flight "
                            "plan's image-prefix or the photo's name")


def project_poses(
    project: m.Project, hf: Heightfield | None
) -> tuple[list[CameraPose], str]:
    """The project's stations as camera poses (see :func:`project_stations`)."""
    stations, camera_id = project_stations(project, hf)
    return [CameraPose(s.image_name, s.C_world, s.R_cam_to_world) for s in stations], camera_id
