"""``designer import-flight``: flown photos → a project that replays that flight.

Sources: a folder of images (:mod:`.image_meta`), an ODM geo.txt or a reference CSV
(:mod:`.reference`). Each photo becomes an explicit exterior orientation in the base
project's CRS (positions through PROJ, attitudes through the meridian convergence at the
photo, :mod:`.geodesy` and :mod:`.gimbal`); the base project gives the scene and, unless
the metadata names a preset, the camera (:mod:`.camera_pick`).

Heights (``height``): ``absolute`` takes the source's height (images: DJI
AbsoluteAltitude, else EXIF GPSAltitude) plus ``height_offset_m``; ``relative`` takes
DJI RelativeAltitude plus the take-off height, which is ``takeoff_height_m`` or the
base terrain's height below the first photo.
"""

from __future__ import annotations

import dataclasses
import math
import os
from pathlib import Path

import numpy as np

from designer.core.rotation import (
    opk_from_rotation,
    rotation_from_heading_tilt_roll,
    rotation_from_opk,
)
from designer.errors import DesignerError
from designer.flight.camera_pick import pick_camera
from designer.flight.checks import fail
from designer.flight.geodesy import Georef, north_azimuth_in
from designer.flight.gimbal import rotation_from_gimbal
from designer.flight.photos import GIMBAL_TRUE, OPK_GRID, YPR_TRUE, FlownPhoto
from designer.project import model as m

HEIGHT_MODES = ("absolute", "relative")
_FORMAT_OF_SUFFIX = {".png": "png", ".jpg": "jpeg", ".jpeg": "jpeg", ".tif": "tiff",
                     ".tiff": "tiff", ".exr": "exr"}


def read_source(source: Path, csv_crs: str) -> list[FlownPhoto]:
    """The photos of a folder of images, a geo.txt (.txt) or a reference CSV (.csv)."""
    source = Path(source)
    if source.is_dir():
        from designer.flight.image_meta import read_image_folder

        return read_image_folder(source)
    if not source.is_file():
        raise DesignerError(f"{source}: no such file or folder; give a folder of images, a "
                            "geo.txt or a reference CSV")
    suffix = source.suffix.lower()
    if suffix == ".txt":
        from designer.flight.reference import read_geo_txt

        return read_geo_txt(source)
    if suffix == ".csv":
        from designer.flight.reference import read_reference_csv

        return read_reference_csv(source, csv_crs)
    raise DesignerError(f"{source}: unknown source type {suffix!r}; give a folder of images, "
                        "a geo.txt (.txt) or a reference CSV (.csv)")


def base_camera(project: m.Project) -> m.Camera:
    """The camera the base project flies: its flight plan's, its first photo's, its first."""
    traj = project.trajectory
    if traj.flight_plan is not None:
        return project.camera(traj.flight_plan.camera)
    if traj.exterior_orientations:
        return project.camera(traj.exterior_orientations[0].camera)
    return project.cameras[0]


def photo_poses(
    photos: list[FlownPhoto], georef: Georef, *, height: str = "absolute",
    takeoff_height_m: float | None = None, height_offset_m: float = 0.0,
) -> list[tuple[np.ndarray, np.ndarray]]:
    """(C_world (3,), R_cam_to_world (3, 3)) of each photo in the project's frame."""
    if height not in HEIGHT_MODES:
        raise DesignerError(f"--altitude {height}: use one of {', '.join(HEIGHT_MODES)}")
    out = []
    for p in photos:
        X, Y = (float(v) for v in georef.from_crs(p.crs, p.x, p.y))
        if height == "absolute":
            if p.z_m is None:
                raise fail(p.where, p.name, "no absolute height",
                           "write GPSAltitude/AbsoluteAltitude, or use --altitude relative")
            Z = p.z_m + height_offset_m
        else:
            if p.relative_altitude_m is None:
                raise fail(p.where, p.name, "no RelativeAltitude",
                           "use --altitude absolute for this source")
            if takeoff_height_m is None:
                raise DesignerError("relative heights need the take-off height; give "
                                    "--takeoff-height-m")
            Z = p.relative_altitude_m + takeoff_height_m
        if p.angles_deg is None:
            raise fail(p.where, p.name, "no camera angles", "give yaw, pitch and roll")
        kind, a, b, c = p.angles_deg
        if kind == GIMBAL_TRUE:
            R = rotation_from_gimbal(a + float(georef.true_north_azimuth_deg(X, Y)), b, c)
        elif kind == YPR_TRUE:  # ODM geo.txt: yaw from true north
            north = float(georef.true_north_azimuth_deg(X, Y))
            R = rotation_from_heading_tilt_roll(math.radians(a + north), math.radians(b),
                                                -math.radians(c))
        else:
            north = float(north_azimuth_in(p.crs, georef, X, Y))
            if kind == OPK_GRID:
                R = (rotation_from_opk(0.0, 0.0, -math.radians(north))
                     @ rotation_from_opk(*np.radians([a, b, c])))
            else:
                R = rotation_from_heading_tilt_roll(math.radians(a + north), math.radians(b),
                                                    -math.radians(c))
        out.append((np.array([X, Y, Z]), R))
    return out


def import_flight(
    source: Path, base_path: Path, out_path: Path, *, height: str = "absolute",
    takeoff_height_m: float | None = None, height_offset_m: float = 0.0,
    csv_crs: str | None = None,
) -> m.Project:
    """Build and write (atomically) the project replaying the flight in ``source``."""
    from designer.project import load_project, validate_project, write_project

    out_path = Path(out_path)
    if not out_path.parent.is_dir():
        raise DesignerError(f"{out_path}: the folder {out_path.parent} does not exist; "
                            "create it first")
    base_path = Path(base_path)
    project = replay_project(
        source, load_project(base_path), base_path.parent, height=height,
        takeoff_height_m=takeoff_height_m, height_offset_m=height_offset_m, csv_crs=csv_crs)
    project = _rebase(project, base_path.parent, out_path.parent)
    validate_project(project, out_path.parent, str(out_path))
    write_project(project, out_path)
    return project


def replay_project(
    source: Path, base: m.Project, base_dir: Path, *, height: str = "absolute",
    takeoff_height_m: float | None = None, height_offset_m: float = 0.0,
    csv_crs: str | None = None,
) -> m.Project:
    """``base`` (whose files are relative to ``base_dir``) flying the photos of ``source``
    as explicit exterior orientations, with the camera the metadata names; not written,
    not validated."""
    from designer.scene.build import build_heightfield

    georef = Georef(base.crs)
    photos = read_source(Path(source), csv_crs or base.crs)
    camera = pick_camera([p.camera for p in photos], base_camera(base))
    if height == "relative" and takeoff_height_m is None:
        hf = build_heightfield(base.scene.terrain, Path(base_dir), base.crs)
        if hf is None:
            raise DesignerError("the base terrain is a mesh; give --takeoff-height-m")
        first = photos[0]
        X, Y = georef.from_crs(first.crs, first.x, first.y)
        takeoff_height_m = float(hf.height_at_clamped(X, Y))
    poses = photo_poses(photos, georef, height=height, takeoff_height_m=takeoff_height_m,
                        height_offset_m=height_offset_m)
    eos = []
    for p, (C, R) in zip(photos, poses, strict=True):
        omega, phi, kappa = (math.degrees(float(v)) for v in opk_from_rotation(R))
        eos.append(m.ExteriorOrientation(p.name, camera.id, float(C[0]), float(C[1]),
                                         float(C[2]), omega, phi, kappa))
    cameras = base.cameras
    if all(c.id != camera.id for c in cameras):
        cameras = (*cameras, camera)
    elif camera not in cameras:
        camera = dataclasses.replace(camera, id=f"{camera.id}-flown")
        cameras = (*cameras, camera)
        eos = [dataclasses.replace(e, camera=camera.id) for e in eos]
    render = base.render
    suffixes = {_FORMAT_OF_SUFFIX.get(Path(p.name).suffix.lower()) for p in photos}
    if len(suffixes) == 1 and None not in suffixes:
        render = dataclasses.replace(render, output_format=suffixes.pop())
    return dataclasses.replace(
        base, cameras=cameras, render=render,
        trajectory=m.Trajectory(exterior_orientations=tuple(eos)),
        description=(f"{base.description or base.name} — replaying the flight of "
                     f"{Path(source).name} ({len(eos)} photos)"))


def _rebase(project: m.Project, old_dir: Path, new_dir: Path) -> m.Project:
    """The project with its referenced files' paths relative to ``new_dir``."""
    old, new = old_dir.resolve(), new_dir.resolve()
    if old == new:
        return project

    def move(path: str) -> str:
        if os.path.isabs(path):
            return path
        return Path(os.path.relpath(old / path, new)).as_posix()

    scene = project.scene
    terrain_src = scene.terrain.source
    if isinstance(terrain_src, m.DemTerrain | m.MeshTerrain):
        terrain_src = dataclasses.replace(terrain_src, file=move(terrain_src.file))
    texture_src = scene.texture.source
    if isinstance(texture_src, m.ImageTexture):
        texture_src = dataclasses.replace(texture_src, file=move(texture_src.file))
    scene = dataclasses.replace(
        scene, terrain=dataclasses.replace(scene.terrain, source=terrain_src),
        texture=dataclasses.replace(scene.texture, source=texture_src),
        objects=tuple(dataclasses.replace(o, file=move(o.file)) for o in scene.objects))
    return dataclasses.replace(project, scene=scene)
