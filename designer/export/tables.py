"""Designer's own ground-truth tables (CSV): camera ω φ κ, GCP truth, GCP image points.

Conventions (designer's, unchanged — these tables are the reference the exchange
formats are checked against):

* comma separated, UTF-8; '#' lines at the top describe the table (pandas:
  ``read_csv(path, comment="#")``), then one header row;
* world coordinates in the given CRS, metres: X = Easting, Y = Northing, Z = height;
* angles in degrees: R_cam_to_world = Rx(ω) · Ry(φ) · Rz(κ), counter-clockwise
  positive, camera axes x = image right, y = image top, z = backwards
  (ω = φ = κ = 0: nadir, image top north);
* pixel coordinates u_px, v_px: continuous, origin at the top-left CORNER of the
  top-left pixel (its centre is (0.5, 0.5)), u right, v down — subtract 0.5 for
  OpenCV / OpenDroneMap, none for COLMAP or Metashape;
* numbers: exact shortest repr of each float64 (no rounding at UTM size).
"""

from __future__ import annotations

import csv
import io
import os
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from designer.core.rotation import opk_from_rotation, rotation_from_opk
from designer.core.truth import (
    CameraPose,
    CameraSet,
    GcpObservation,
    GroundControlPoint,
    ImageTime,
)
from designer.export._text import ExportError, check_crs, check_unique, fmt, write_texts

OPK_COLUMNS = ("image", "X", "Y", "Z", "omega_deg", "phi_deg", "kappa_deg")
#: the OPK table of a project with a time line: the moment each photo is taken, UTC
OPK_TIME_COLUMNS = (*OPK_COLUMNS, "time")
IMAGE_TIME_COLUMNS = ("image", "time", "time_s", "sun_azimuth_deg", "sun_elevation_deg")
GCP_TRUTH_COLUMNS = (
    "gcp_id", "role", "true_X", "true_Y", "true_Z",
    "surveyed_X", "surveyed_Y", "surveyed_Z", "sigma_X", "sigma_Y", "sigma_Z",
)
GCP_OBSERVATION_COLUMNS = ("gcp_id", "image", "u_px", "v_px")
#: the OPK table's column layouts: plain, with time, and either with a rig's camera column
_OPK_LAYOUTS = (OPK_COLUMNS, OPK_TIME_COLUMNS, (*OPK_COLUMNS, "camera"),
                (*OPK_TIME_COLUMNS, "camera"))

_WORLD = "X = Easting, Y = Northing, Z = height, metres"
_PIXELS = (
    "u_px, v_px: continuous pixel coordinates, origin at the top-left corner of the "
    "top-left pixel (its centre is (0.5, 0.5)), u right, v down; subtract 0.5 for "
    "OpenCV/OpenDroneMap"
)


def _table(comments: Sequence[str], columns: Sequence[str], rows: Sequence[Sequence[str]]) -> str:
    lines = [f"# {c}" for c in comments] + [",".join(columns)]
    lines += [",".join(r) for r in rows]
    return "\n".join(lines) + "\n"


def opk_csv(poses: Sequence[CameraPose], crs: str,
            times: Sequence[ImageTime] | None = None,
            cameras: CameraSet | None = None) -> str:
    """Camera table: image, X, Y, Z (perspective centre), omega_deg, phi_deg, kappa_deg,
    ``time`` (ISO 8601 UTC) when the photos have ``times`` (in the same order) and
    ``camera`` (the designer camera id) for a multi-camera rig's ``cameras``."""
    crs = check_crs(crs)
    check_unique((p.image_name for p in poses), "image name")
    if times is not None and [t.image_name for t in times] != [p.image_name for p in poses]:
        raise ExportError("the image times do not list the same images as the poses")
    rows = []
    for k, p in enumerate(poses):
        opk = np.degrees(opk_from_rotation(p.R_cam_to_world))
        rows.append([p.image_name, *(fmt(v) for v in (*p.C_world, *opk))]
                    + ([] if times is None else [times[k].time_utc])
                    + ([] if cameras is None else [cameras.camera_of(p.image_name)]))
    comments = [
        f"designer camera poses; CRS {crs}; {_WORLD}; X, Y, Z = perspective centre",
        "omega, phi, kappa in degrees: R = Rx(omega)*Ry(phi)*Rz(kappa) maps camera axes "
        "(x right, y image top, z backwards) to the world",
    ]
    if times is not None:
        comments.append("time: the moment the photo is taken, ISO 8601 UTC")
    columns = OPK_COLUMNS if times is None else OPK_TIME_COLUMNS
    if cameras is not None:
        comments.append("camera: the id of the project camera (rig mount) that took it")
        columns = (*columns, "camera")
    return _table(comments, columns, rows)


def image_times_csv(times: Sequence[ImageTime]) -> str:
    """Time-line table: image, time (ISO 8601 UTC), time_s (seconds after take-off),
    sun_azimuth_deg (clockwise from grid north), sun_elevation_deg."""
    check_unique((t.image_name for t in times), "image name")
    rows = [[t.image_name, t.time_utc, fmt(t.time_s), fmt(t.sun_azimuth_deg),
             fmt(t.sun_elevation_deg)] for t in times]
    comments = ["designer image times: when each photo is taken on the flight's time line "
                "and the sun it is lit by (docs/world.md)",
                "time: ISO 8601 UTC; time_s: seconds after take-off; sun azimuth clockwise "
                "from grid north and elevation above the horizon, degrees"]
    return _table(comments, IMAGE_TIME_COLUMNS, rows)


def gcp_truth_csv(gcps: Sequence[GroundControlPoint], crs: str) -> str:
    """GCP table: id, role, true X/Y/Z, surveyed X/Y/Z, sigma X/Y/Z (metres)."""
    crs = check_crs(crs)
    check_unique((g.gcp_id for g in gcps), "GCP id")
    rows = [
        [g.gcp_id, g.role, *(fmt(v) for v in (*g.true_xyz, *g.surveyed_xyz, *g.sigma_xyz))]
        for g in gcps
    ]
    comments = [
        f"designer ground control points; CRS {crs}; {_WORLD}",
        "true = exact position shown in the images; surveyed = position given to the SfM "
        "software; sigma = survey standard deviation per axis",
    ]
    return _table(comments, GCP_TRUTH_COLUMNS, rows)


def gcp_observations_csv(observations: Sequence[GcpObservation],
                         cameras: CameraSet | None = None) -> str:
    """GCP image-point table: gcp_id, image, u_px, v_px (designer's pixel convention),
    and ``camera`` (the designer camera id of the image) for a rig's ``cameras``."""
    rows = [[o.gcp_id, o.image_name, fmt(o.uv_px[0]), fmt(o.uv_px[1])]
            + ([] if cameras is None else [cameras.camera_of(o.image_name)])
            for o in observations]
    comments = ["designer GCP image points: projections of the TRUE GCP positions", _PIXELS]
    columns = GCP_OBSERVATION_COLUMNS if cameras is None else (*GCP_OBSERVATION_COLUMNS,
                                                               "camera")
    return _table(comments, columns, rows)


# ----------------------------------------------------------------------- writers
def write_opk_csv(path: str | os.PathLike, poses: Sequence[CameraPose], crs: str) -> Path:
    write_texts({path: opk_csv(poses, crs)})
    return Path(path)


def write_gcp_truth_csv(
    path: str | os.PathLike, gcps: Sequence[GroundControlPoint], crs: str
) -> Path:
    write_texts({path: gcp_truth_csv(gcps, crs)})
    return Path(path)


def write_gcp_observations_csv(
    path: str | os.PathLike, observations: Sequence[GcpObservation]
) -> Path:
    write_texts({path: gcp_observations_csv(observations)})
    return Path(path)


# ----------------------------------------------------------------------- readers
def _read_rows(path: str | os.PathLike, columns: Sequence[str],
               *alternatives: Sequence[str]) -> list[dict[str, str]]:
    text = Path(path).read_text(encoding="utf-8")
    body = "\n".join(line for line in text.splitlines() if not line.startswith("#"))
    reader = csv.DictReader(io.StringIO(body))
    if tuple(reader.fieldnames or ()) not in {tuple(c) for c in (columns, *alternatives)}:
        raise ExportError(f"{path}: expected columns {list(columns)}, got {reader.fieldnames}")
    return list(reader)


def read_opk_csv(path: str | os.PathLike) -> list[CameraPose]:
    """Camera poses from :func:`opk_csv` text (angles → R with rotation_from_opk)."""
    poses = []
    for row in _read_rows(path, *_OPK_LAYOUTS):
        C = [float(row[k]) for k in ("X", "Y", "Z")]
        opk = np.radians([float(row[k]) for k in ("omega_deg", "phi_deg", "kappa_deg")])
        poses.append(CameraPose(row["image"], C, rotation_from_opk(*opk)))
    return poses


def read_image_cameras_csv(path: str | os.PathLike) -> dict[str, str] | None:
    """{image: camera id} from an OPK table of a multi-camera rig; None when the table
    has no camera column (one camera)."""
    rows = _read_rows(path, *_OPK_LAYOUTS)
    if rows and "camera" not in rows[0]:
        return None
    return {row["image"]: row["camera"] for row in rows}


def read_image_times_csv(path: str | os.PathLike) -> list[ImageTime]:
    """Image times from :func:`image_times_csv` text."""
    return [ImageTime(row["image"], float(row["time_s"]), row["time"],
                      float(row["sun_azimuth_deg"]), float(row["sun_elevation_deg"]))
            for row in _read_rows(path, IMAGE_TIME_COLUMNS)]


def read_gcp_truth_csv(path: str | os.PathLike) -> list[GroundControlPoint]:
    """GCPs from :func:`gcp_truth_csv` text."""
    out = []
    for row in _read_rows(path, GCP_TRUTH_COLUMNS):
        def xyz(prefix: str, row=row) -> list[float]:
            return [float(row[f"{prefix}_{a}"]) for a in "XYZ"]
        out.append(GroundControlPoint(
            row["gcp_id"], row["role"], xyz("true"), xyz("surveyed"), xyz("sigma")
        ))
    return out


def read_gcp_observations_csv(path: str | os.PathLike) -> list[GcpObservation]:
    """GCP image points from :func:`gcp_observations_csv` text."""
    return [
        GcpObservation(row["gcp_id"], row["image"], [float(row["u_px"]), float(row["v_px"])])
        for row in _read_rows(path, GCP_OBSERVATION_COLUMNS,
                              (*GCP_OBSERVATION_COLUMNS, "camera"))
    ]
