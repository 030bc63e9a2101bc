"""Test data of flown surveys: a project's true poses as DJI-style geotagged images.

The DJI angles are computed here independently of designer.flight: true north from a
finite difference of the projection, the ZYX Euler angles with scipy.
"""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import cv2
import numpy as np
import pyexiv2
from pyproj import Transformer
from scipy.spatial.transform import Rotation

from designer.core.crs import crs_token
from designer.core.truth import CameraPose
from designer.project import model as m
from designer.scene.build import build_heightfield
from designer.survey.project_poses import project_poses

EXAMPLE = Path(__file__).resolve().parents[2] / "resources" / "examples" / "survey" / "survey.xml"
DJI_NS = "http://www.dji.com/drone-dji/1.0/"
#: photo axes → gimbal body axes (x optical axis, y image right, z image down); ENU ↔ NED
M_BODY_FROM_PHOTO = np.array([[0.0, 0.0, -1.0], [1.0, 0.0, 0.0], [0.0, -1.0, 0.0]])
T_NED_FROM_ENU = np.array([[0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, -1.0]])


def true_poses(project: m.Project, base_dir: Path) -> list[CameraPose]:
    hf = build_heightfield(project.scene.terrain, base_dir)
    return project_poses(project, hf)[0]


def grid_azimuth_of_true_north_deg(crs: str, X: float, Y: float) -> float:
    """By finite difference: the grid direction of a step north along the meridian."""
    crs = crs_token(crs)
    to_ll = Transformer.from_crs(crs, "EPSG:4326", always_xy=True)
    to_grid = Transformer.from_crs("EPSG:4326", crs, always_xy=True)
    lon, lat = to_ll.transform(X, Y)
    x0, y0 = to_grid.transform(lon, lat - 1e-6)
    x1, y1 = to_grid.transform(lon, lat + 1e-6)
    return math.degrees(math.atan2(x1 - x0, y1 - y0))


def dji_angles_deg(R_cam_to_world: np.ndarray, crs: str, X: float, Y: float):
    """(yaw from true north, pitch, roll) as a DJI gimbal reports them."""
    B = T_NED_FROM_ENU @ R_cam_to_world @ M_BODY_FROM_PHOTO.T
    yaw, pitch, roll = Rotation.from_matrix(B).as_euler("ZYX", degrees=True)
    return yaw - grid_azimuth_of_true_north_deg(crs, X, Y), pitch, roll


def _dms(value_deg: float) -> str:
    v = abs(value_deg)
    d = int(v)
    mnt = int((v - d) * 60)
    s = (v - d - mnt / 60) * 3600
    return f"{d}/1 {mnt}/1 {round(s * 1_000_000)}/1000000"


def write_dji_image(path: Path, pose: CameraPose, crs: str, *, make="DJI", model="FC6310",
                    focal_mm=8.8, size_px=(5472, 3648), takeoff_Z=None, gps=True,
                    gimbal=True, absolute_error_m=0.0) -> None:
    """A tiny JPEG with DJI-style EXIF GPS and XMP (drone-dji) metadata of ``pose``; the
    absolute heights are off by ``absolute_error_m`` (a barometric drift)."""
    cv2.imwrite(str(path), np.full((24, 36, 3), 128, np.uint8))
    X, Y, Z = (float(v) for v in pose.C_world)
    Z_abs = Z + absolute_error_m
    lon, lat = Transformer.from_crs(crs_token(crs), "EPSG:4326", always_xy=True).transform(X, Y)
    exif = {"Exif.Image.Make": make, "Exif.Image.Model": model,
            "Exif.Photo.FocalLength": f"{round(focal_mm * 1000)}/1000",
            "Exif.Photo.PixelXDimension": str(size_px[0]),
            "Exif.Photo.PixelYDimension": str(size_px[1])}
    if gps:
        exif.update({
            "Exif.GPSInfo.GPSLatitudeRef": "N" if lat >= 0 else "S",
            "Exif.GPSInfo.GPSLatitude": _dms(lat),
            "Exif.GPSInfo.GPSLongitudeRef": "E" if lon >= 0 else "W",
            "Exif.GPSInfo.GPSLongitude": _dms(lon),
            "Exif.GPSInfo.GPSAltitudeRef": "0" if Z_abs >= 0 else "1",
            "Exif.GPSInfo.GPSAltitude": f"{round(abs(Z_abs) * 1000)}/1000"})
    yaw, pitch, roll = dji_angles_deg(pose.R_cam_to_world, crs, X, Y)
    xmp = {"Xmp.drone-dji.AbsoluteAltitude": f"{Z_abs:+.4f}"}
    if takeoff_Z is not None:
        xmp["Xmp.drone-dji.RelativeAltitude"] = f"{Z - takeoff_Z:+.4f}"
    if gimbal:
        xmp.update({"Xmp.drone-dji.GimbalYawDegree": f"{yaw:+.6f}",
                    "Xmp.drone-dji.GimbalPitchDegree": f"{pitch:+.6f}",
                    "Xmp.drone-dji.GimbalRollDegree": f"{roll:+.6f}",
                    "Xmp.drone-dji.FlightYawDegree": f"{yaw:+.2f}"})
    pyexiv2.registerNs(DJI_NS, "drone-dji")
    with pyexiv2.Image(str(path)) as image:
        image.modify_exif(exif)
        image.modify_xmp(xmp)


def shifted(project: m.Project, dE: float) -> m.Project:
    """The project moved ``dE`` metres east (scene, targets, area, photos)."""
    o = project.origin
    e = project.scene.terrain.extent
    extent = m.Extent(e.min_X + dE, e.min_Y, e.max_X + dE, e.max_Y)
    targets = project.scene.targets
    if targets is not None:
        targets = dataclasses.replace(targets, targets=tuple(
            dataclasses.replace(t, true=dataclasses.replace(t.true, X=t.true.X + dE),
                                surveyed=None) for t in targets.targets))
    scene = dataclasses.replace(
        project.scene, terrain=dataclasses.replace(project.scene.terrain, extent=extent),
        targets=targets)
    traj = project.trajectory
    plan = traj.flight_plan
    if plan is not None:
        plan = dataclasses.replace(plan, area=tuple((x + dE, y) for x, y in plan.area))
    eos = tuple(dataclasses.replace(p, X=p.X + dE) for p in traj.exterior_orientations)
    return dataclasses.replace(project, origin=m.Origin(o.E0 + dE, o.N0, o.H0), scene=scene,
                               trajectory=m.Trajectory(eos, plan))


def rotation_error_deg(R1: np.ndarray, R2: np.ndarray) -> float:
    """The angle of R1ᵀ·R2 (deg) as |Log|: arccos((trace − 1) / 2) has a floor of
    1.2e-6° (one rounding of the trace), larger than the rounding these tests look for."""
    from designer.core.rotation import rotvec_from_rotation

    return math.degrees(float(np.linalg.norm(rotvec_from_rotation(R1.T @ R2))))
