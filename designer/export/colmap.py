"""COLMAP text model (cameras.txt, images.txt, points3D.txt) of the true survey.

Conventions at this boundary (COLMAP doc/format.rst "Output Format" and
doc/database.rst; every camera model below is checked numerically against
pycolmap's own projection in tests/export/test_colmap.py):

* pixel origin: COLMAP puts (0, 0) at the upper-left image corner and the centre of
  the upper-left pixel at (0.5, 0.5) (doc/database.rst, "Keypoints and
  Descriptors") — identical to designer's, so cx, cy are written unchanged and
  COLMAP's projections equal designer's ``uv_px``;
* rotation: images.txt stores world → camera in the computer-vision frame (x right,
  y down, z forward): R_colmap = diag(1, −1, −1) · Rᵀ, t = −R_colmap · (C − offset),
  quaternion Hamilton (QW, QX, QY, QZ), QW >= 0
  (:func:`designer.core.rotation.colmap_pose_from_photo`);
* units: metres; world axes X = Easting, Y = Northing, Z = height. By default the
  model is in WORLD coordinates; an optional ``offset_world`` (E0, N0, H0) is
  subtracted first and named in a comment at the top of images.txt, so a reader
  adds it back;
* camera model (one camera, CAMERA_ID 1, shared by all images):
  PINHOLE fx fy cx cy when there is no distortion; OPENCV fx fy cx cy k1 k2 p1 p2
  for Brown–Conrady with k3 = 0; FULL_OPENCV fx fy cx cy k1 k2 p1 p2 k3 k4 k5 k6
  with k4 = k5 = k6 = 0 (COLMAP's rational denominator) when k3 != 0;
  OPENCV_FISHEYE fx fy cx cy k1 k2 k3 k4 for the equidistant fisheye. COLMAP's
  k1 k2 p1 p2 k3 have OpenCV's meaning: no coefficient is swapped;
* numbers: exact shortest repr of each float64 (the double itself: ~1 nm at UTM size).

points3D.txt is written empty: the ground truth here is poses and intrinsics.
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from pathlib import Path

from designer.core.distortion import BrownConrady, FisheyeEquidistant
from designer.core.interior import InteriorOrientation
from designer.core.rotation import colmap_pose_from_photo
from designer.core.truth import CameraPose
from designer.export._text import (
    ExportError,
    check_offset,
    check_unique,
    fmt,
    write_texts,
)
from designer.export.colmap_read import camera_poses, read_images_text

CAMERA_ID = 1
FILES = ("cameras.txt", "images.txt", "points3D.txt")


def colmap_camera_model(interior: InteriorOrientation) -> tuple[str, list[float]]:
    """(COLMAP model name, its parameter list) for designer's interior orientation."""
    fx, fy, cx, cy = interior.fx_px, interior.fy_px, interior.cx_px, interior.cy_px
    d = interior.distortion
    if d is None or (isinstance(d, BrownConrady) and d.is_identity):
        return "PINHOLE", [fx, fy, cx, cy]
    if isinstance(d, BrownConrady):
        if d.k3 == 0.0:
            return "OPENCV", [fx, fy, cx, cy, d.k1, d.k2, d.p1, d.p2]
        return "FULL_OPENCV", [fx, fy, cx, cy, d.k1, d.k2, d.p1, d.p2, d.k3, 0.0, 0.0, 0.0]
    if isinstance(d, FisheyeEquidistant):
        return "OPENCV_FISHEYE", [fx, fy, cx, cy, d.k1, d.k2, d.k3, d.k4]
    raise ExportError(f"no COLMAP camera model for distortion {type(d).__name__}")


def colmap_cameras_text(interior: InteriorOrientation) -> str:
    """cameras.txt: one camera, ``CAMERA_ID MODEL WIDTH HEIGHT PARAMS...``."""
    model, params = colmap_camera_model(interior)
    W, H = interior.image_size_px
    return (
        "# Camera list with one line of data per camera:\n"
        "#   CAMERA_ID, MODEL, WIDTH, HEIGHT, PARAMS[]\n"
        "# Number of cameras: 1\n"
        f"{CAMERA_ID} {model} {W} {H} {' '.join(fmt(p) for p in params)}\n"
    )


def colmap_images_text(poses: Sequence[CameraPose], offset_world=None) -> str:
    """images.txt: ``IMAGE_ID QW QX QY QZ TX TY TZ CAMERA_ID NAME`` + an empty 2D line.

    IMAGE_IDs are 1, 2, … in the order of ``poses``. Coordinates are world minus
    ``offset_world`` (metres; default no offset).
    """
    check_unique((p.image_name for p in poses), "image name")
    offset = check_offset(offset_world)
    lines = [
        "# Image list with two lines of data per image:",
        "#   IMAGE_ID, QW, QX, QY, QZ, TX, TY, TZ, CAMERA_ID, NAME",
        "#   POINTS2D[] as (X, Y, POINT3D_ID)",
        f"# Number of images: {len(poses)}, mean observations per image: 0",
        "# designer: world frame X = Easting, Y = Northing, Z = height (m) minus offset "
        f"(E0, N0, H0) = ({fmt(offset[0])}, {fmt(offset[1])}, {fmt(offset[2])})",
    ]
    for image_id, pose in enumerate(poses, start=1):
        q, t = colmap_pose_from_photo(pose.R_cam_to_world, pose.C_world - offset)
        numbers = " ".join(fmt(v) for v in (*q, *t))
        lines.append(f"{image_id} {numbers} {CAMERA_ID} {pose.image_name}")
        lines.append("")  # no 2D points
    return "\n".join(lines) + "\n"


def colmap_points3d_text() -> str:
    """points3D.txt with no points (header only)."""
    return (
        "# 3D point list with one line of data per point:\n"
        "#   POINT3D_ID, X, Y, Z, R, G, B, ERROR, TRACK[] as (IMAGE_ID, POINT2D_IDX)\n"
        "# Number of points: 0, mean track length: 0\n"
    )


def colmap_texts(
    folder: str | os.PathLike,
    interior: InteriorOrientation,
    poses: Sequence[CameraPose],
    offset_world=None,
) -> dict[Path, str]:
    """{path: text} of the three model files in ``folder`` (nothing is written)."""
    folder = Path(folder)
    return {
        folder / "cameras.txt": colmap_cameras_text(interior),
        folder / "images.txt": colmap_images_text(poses, offset_world),
        folder / "points3D.txt": colmap_points3d_text(),
    }


def write_colmap_text_model(
    folder: str | os.PathLike,
    interior: InteriorOrientation,
    poses: Sequence[CameraPose],
    offset_world=None,
) -> Path:
    """Write cameras.txt, images.txt and points3D.txt into ``folder`` (created if needed).

    Each file is written atomically. Returns the folder.
    """
    texts = colmap_texts(folder, interior, poses, offset_world)
    write_texts(texts)
    return Path(folder)


def read_colmap_text_poses(folder: str | os.PathLike, offset_world=None) -> list[CameraPose]:
    """Camera poses from ``folder``/images.txt, in file order, ``offset_world`` added back.

    Parsed by :func:`designer.export.colmap_read.read_images_text` (COLMAP's rules:
    comments and blank lines skipped, each image's 2D-points line not parsed).
    """
    offset = check_offset(offset_world)
    path = Path(folder) / "images.txt"
    try:
        images = read_images_text(path)
    except ValueError as exc:
        raise ExportError(f"{path}: {exc}") from None
    return camera_poses(images, offset)
