"""OpenDroneMap inputs: ``gcp_list.txt`` (GCP image points) and ``geo.txt`` (image positions).

Conventions at this boundary (sources: ODM docs source/geo.rst; ODM code
opendm/gcp.py, opendm/geo.py, opendm/location.py parse_srs_header,
opendm/photo.py; OpenSfM opensfm/io.py _read_gcp_list_lines and
opensfm/features.py normalized_image_coordinates):

* CRS: the first line of both files, one of ``EPSG:<code>``, ``WGS84 UTM <zone><N|S>``
  (upper case, zone 1–60) or a PROJ string containing ``+proj`` — forms
  parse_srs_header reads as written (its exact rules: :mod:`designer.core.crs`); the
  CRS must be projected with metre axes (ODM turns the coordinates into latitude and
  longitude with it: a geographic CRS such as EPSG:4326 would read metres as degrees).
  Anything else is rejected here. Coordinates are written as designer's world X
  (Easting), Y (Northing), Z (height), metres, exact repr.
* pixel origin: gcp_list.txt uses OpenCV's convention, (0, 0) at the CENTRE of the
  top-left pixel (OpenSfM normalises with (px + 0.5 − W/2) / max(W, H)), so
  im_x = u − 0.5 and im_y = v − 0.5 from designer's corner-origin ``uv_px``.
* gcp_list.txt rows: ``geo_x geo_y geo_z im_x im_y image_name gcp_id`` with the
  SURVEYED coordinates (what a field crew would hand over). By default only
  "control" GCPs are written: ODM uses every row to georeference, so check points
  stay out and are scored separately. OpenSfM groups rows into points by their
  coordinates, so two written GCPs with identical surveyed coordinates are rejected.
* geo.txt rows: ``image geo_x geo_y geo_z yaw pitch roll [horz_acc vert_acc]``,
  angles in degrees in ODM's normalised camera convention (opendm/photo.py):
  yaw 0 = image top points to TRUE north, 90 = east (clockwise); pitch 0 = nadir,
  90 = looking forward (towards the image top); roll about the along-track axis
  with ODM's aerospace sign (positive = right wing down, i.e. the view swings left).
  ODM builds R_ned = Rz(yaw) · Ry(pitch) · Rx(roll) · [[0,1,0],[1,0,0],[0,0,−1]]
  (compute_opk). In designer's terms yaw = heading, pitch = tilt, roll = −roll of
  :func:`designer.core.rotation.heading_tilt_roll_from_rotation`; a test rebuilds
  ODM's matrix from the written angles. compute_opk takes north as the direction of
  increasing latitude (ECEF difference of lat ± δ at the camera's longitude), i.e.
  TRUE north, while designer's heading is measured from GRID north (the CRS's Y
  axis): yaw = heading + γ, γ the meridian convergence at the camera (angle from true
  north to grid north, PROJ's get_factors().meridian_convergence; ~0.1° at
  the example site, up to ~3° at a UTM zone's edge). pitch and roll do not change.
  ODM's docs say the angles are used for radiometric calibration and, through
  compute_opk, as ω φ κ priors.
* ``cameras.json`` (multi-camera rigs only): one OpenSfM camera model per physical
  camera, keyed by the designer camera id, in the form ODM's ``--cameras`` option and
  OpenSfM's camera_models_overrides.json take: ``projection_type`` brown (or
  fisheye_opencv), ``width``, ``height``, ``focal_x``, ``focal_y`` = fx, fy / max(W, H),
  ``c_x``, ``c_y`` = (cx − W/2, cy − H/2) / max(W, H) (OpenSfM's normalised
  coordinates, origin at the image centre, whatever the pixel origin), and k1 k2 k3
  p1 p2 (OpenCV's meaning) or k1..k4. ODM names a camera by its images' EXIF make,
  model, size and focal; the images of a rig are told apart by their names
  (``camera_poses_opk.csv`` lists each image's camera).
"""

from __future__ import annotations

import json
import math
import os
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from designer.core.crs import crs_token, meridian_convergence_deg, odm_crs_problem
from designer.core.distortion import FisheyeEquidistant
from designer.core.rotation import heading_tilt_roll_from_rotation
from designer.core.truth import (
    GCP_ROLES,
    CameraPose,
    CameraSet,
    GcpObservation,
    GroundControlPoint,
)
from designer.export._text import (
    ExportError,
    check_crs,
    check_unique,
    fmt,
    write_texts,
)

#: designer's pixel coordinates minus this are OpenCV/OpenSfM pixel coordinates
OPENCV_PIXEL_SHIFT = 0.5



def odm_crs(crs: str) -> str:
    """The CRS token OpenDroneMap understands from a project's CRS label: a leading
    'EPSG:n' of a longer label such as 'EPSG:32632 (WGS 84 / UTM zone 32N)'."""
    return crs_token(crs)


def check_odm_crs(crs: object) -> str:
    """The CRS line if OpenDroneMap can parse it, else ExportError naming the forms."""
    line = check_crs(crs)
    problem = odm_crs_problem(line)
    if problem is None:
        return line
    raise ExportError(f"OpenDroneMap CRS header {line!r}: {problem}")


def odm_ypr_deg_from_rotation(R_cam_to_world) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """ODM (yaw, pitch, roll) in degrees from R_cam_to_world (..., 3, 3); see module doc.

    yaw ∈ [0, 360) from GRID north (designer's heading), pitch ∈ [−90, 90],
    roll ∈ [−180, 180]; geo.txt adds the meridian convergence to the yaw.
    """
    heading, tilt, roll = heading_tilt_roll_from_rotation(R_cam_to_world)
    return np.degrees(heading), np.degrees(tilt), -np.degrees(roll) + 0.0


def odm_gcp_list_text(
    gcps: Sequence[GroundControlPoint],
    observations: Sequence[GcpObservation],
    crs: str,
    roles: Sequence[str] = ("control",),
) -> str:
    """gcp_list.txt: CRS line, then one row per observation of a GCP whose role is in ``roles``.

    Rows use the GCP's SURVEYED coordinates and OpenCV pixel coordinates (uv − 0.5).
    """
    line = check_odm_crs(crs)
    unknown = set(roles) - set(GCP_ROLES)
    if unknown:
        raise ExportError(f"unknown GCP role(s) {sorted(unknown)}; use {', '.join(GCP_ROLES)}")
    check_unique((g.gcp_id for g in gcps), "GCP id")
    by_id = {g.gcp_id: g for g in gcps}
    # OpenSfM keys GCPs by their coordinates: two written GCPs at one spot would merge
    seen: dict[tuple[float, ...], str] = {}
    for g in gcps:
        if g.role in roles:
            other = seen.setdefault(tuple(g.surveyed_xyz.tolist()), g.gcp_id)
            if other != g.gcp_id:
                raise ExportError(
                    f"GCPs {other!r} and {g.gcp_id!r} have identical surveyed coordinates; "
                    "OpenSfM would merge them into one point"
                )
    rows = [line]
    for obs in observations:
        gcp = by_id.get(obs.gcp_id)
        if gcp is None:
            raise ExportError(f"observation of unknown GCP {obs.gcp_id!r} in {obs.image_name!r}")
        if gcp.role not in roles:
            continue
        x, y, z = (fmt(v) for v in gcp.surveyed_xyz)
        im_x = fmt(obs.uv_px[0] - OPENCV_PIXEL_SHIFT)
        im_y = fmt(obs.uv_px[1] - OPENCV_PIXEL_SHIFT)
        rows.append(f"{x} {y} {z} {im_x} {im_y} {obs.image_name} {gcp.gcp_id}")
    return "\n".join(rows) + "\n"


def odm_geo_text(
    poses: Sequence[CameraPose],
    crs: str,
    horizontal_accuracy_m: float | None = None,
    vertical_accuracy_m: float | None = None,
) -> str:
    """geo.txt: CRS line, then ``image x y z yaw pitch roll [horz_acc vert_acc]`` per image.

    yaw is referred to true north (the camera's heading plus the meridian convergence).

    The accuracies (metres, one standard deviation) are written only when both are given.
    """
    line = check_odm_crs(crs)
    check_unique((p.image_name for p in poses), "image name")
    accuracy = ""
    if (horizontal_accuracy_m is None) != (vertical_accuracy_m is None):
        raise ExportError("give both horizontal_accuracy_m and vertical_accuracy_m, or neither")
    if horizontal_accuracy_m is not None:
        for a in (horizontal_accuracy_m, vertical_accuracy_m):
            if not math.isfinite(a) or a < 0:
                raise ExportError(f"accuracy {a!r} m must be finite and >= 0")
        accuracy = f" {fmt(horizontal_accuracy_m)} {fmt(vertical_accuracy_m)}"
    rows = [line]
    if poses:
        C = np.array([p.C_world for p in poses])
        convergence_deg = meridian_convergence_deg(line, C[:, 0], C[:, 1]).reshape(-1)
    for pose, gamma_deg in zip(poses, convergence_deg if poses else [], strict=True):
        heading, pitch, roll = odm_ypr_deg_from_rotation(pose.R_cam_to_world)
        yaw = (heading + gamma_deg) % 360.0  # grid north → true north
        numbers = " ".join(fmt(v) for v in (*pose.C_world, yaw, pitch, roll))
        rows.append(f"{pose.image_name} {numbers}{accuracy}")
    return "\n".join(rows) + "\n"


def odm_cameras_json(cameras: CameraSet) -> str:
    """cameras.json: an OpenSfM camera model per physical camera (see the module doc)."""
    out = {}
    for camera_id, interior in cameras.interiors.items():
        W, H = interior.image_size_px
        size = float(max(W, H))
        d = interior.distortion
        model: dict = {"width": W, "height": H, "focal_x": interior.fx_px / size,
                       "focal_y": interior.fy_px / size,
                       "c_x": (interior.cx_px - W / 2) / size,
                       "c_y": (interior.cy_px - H / 2) / size}
        if isinstance(d, FisheyeEquidistant):
            model = {"projection_type": "fisheye_opencv", **model,
                     "k1": d.k1, "k2": d.k2, "k3": d.k3, "k4": d.k4}
        else:
            k1, k2, k3, p1, p2 = ((d.k1, d.k2, d.k3, d.p1, d.p2) if d is not None
                                  else (0.0,) * 5)
            model = {"projection_type": "brown", **model,
                     "k1": k1, "k2": k2, "k3": k3, "p1": p1, "p2": p2}
        out[camera_id] = model
    return json.dumps(out, indent=1) + "\n"


def write_odm_gcp_list(
    path: str | os.PathLike,
    gcps: Sequence[GroundControlPoint],
    observations: Sequence[GcpObservation],
    crs: str,
    roles: Sequence[str] = ("control",),
) -> Path:
    """Write gcp_list.txt atomically (see :func:`odm_gcp_list_text`); returns the path."""
    write_texts({path: odm_gcp_list_text(gcps, observations, crs, roles)})
    return Path(path)


def write_odm_geo(
    path: str | os.PathLike,
    poses: Sequence[CameraPose],
    crs: str,
    horizontal_accuracy_m: float | None = None,
    vertical_accuracy_m: float | None = None,
) -> Path:
    """Write geo.txt atomically (see :func:`odm_geo_text`); returns the path."""
    write_texts({path: odm_geo_text(poses, crs, horizontal_accuracy_m, vertical_accuracy_m)})
    return Path(path)
