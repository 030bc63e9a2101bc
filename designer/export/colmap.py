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
* units: metres; world axes X = Easting, Y = Northing, Z = height, minus an offset
  (E0, N0, H0). COLMAP's sparse stages compute in float64, but its dense stage
  (image_undistorter, patch_match_stereo) keeps poses in float32, whose spacing at a
  northing of 5·10⁶ m is 0.5 m: a model in full UTM coordinates moves camera centres
  by up to 0.25 m there. The ground truth is therefore LOCAL by default
  (:func:`colmap_offset_world`: ``local`` = the mean camera centre rounded to whole
  metres, the frame ``designer reconstruct`` also works in; ``none`` = world
  coordinates; or explicit E, N, H). The offset is named in a comment at the top of
  images.txt and written beside the model in ``offset.json`` (:data:`OFFSET_FILE`;
  :func:`designer.export.colmap_read.model_offset_world` reads it), so a reader adds
  it back;
* IMAGE_IDs: 1, 2, … in the byte order of the image names. COLMAP 3.8's
  point_triangulator pairs the model's images with the database's by IMAGE_ID
  (Reconstruction::Load from the DatabaseCache; it stops with "Check failed:
  existing_image.Name() == image.second.Name()" on a mismatch). feature_extractor
  reads a folder in sorted-name order (ImageReader sorts the file list:
  src/base/image_reader.cc) and numbers each image when its extraction finishes: with
  ``--SiftExtraction.num_threads 1`` that is the sorted-name order, so a known-pose
  model triangulates without editing (several threads may finish out of order). Lines
  stay in pose (flight) order;
* cameras: one camera, CAMERA_ID 1, shared by all images; a multi-camera rig
  (:class:`designer.core.truth.CameraSet`) has one line per physical camera, CAMERA_IDs
  1, 2, … in the set's order (a comment names each designer camera id), and each image
  refers to its own camera's CAMERA_ID;
* camera model:
  PINHOLE fx fy cx cy when there is no distortion; OPENCV fx fy cx cy k1 k2 p1 p2
  for Brown–Conrady with k3 = 0; FULL_OPENCV fx fy cx cy k1 k2 p1 p2 k3 k4 k5 k6
  with k4 = k5 = k6 = 0 (COLMAP's rational denominator) when k3 != 0;
  OPENCV_FISHEYE fx fy cx cy k1 k2 k3 k4 for the equidistant fisheye. COLMAP's
  k1 k2 p1 p2 k3 have OpenCV's meaning: no coefficient is swapped;
* numbers: exact shortest repr of each float64 (the double itself: ~1 nm at UTM size).

points3D.txt is written empty: the ground truth here is poses and intrinsics.

``offset.json`` (UTF-8 JSON object): ``offset_world_m`` [E0, N0, H0] (metres, exact
doubles), ``choice`` (``local``, ``none`` or ``explicit``), ``crs`` (when known) and
``meaning``: world = model coordinates + offset_world_m.
"""

from __future__ import annotations

import json
import os
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from designer.core.distortion import BrownConrady, FisheyeEquidistant
from designer.core.interior import InteriorOrientation
from designer.core.rotation import colmap_pose_from_photo
from designer.core.truth import CameraPose, CameraSet
from designer.export._text import (
    ExportError,
    check_offset,
    check_unique,
    fmt,
    write_texts,
)
from designer.export.colmap_read import (
    OFFSET_FILE,
    camera_poses,
    model_offset_world,
    read_images_text,
)

CAMERA_ID = 1
FILES = ("cameras.txt", "images.txt", "points3D.txt")
#: the choices of ``--colmap-offset`` besides explicit ``E,N,H``
OFFSET_CHOICES = ("local", "none")


def colmap_offset_world(choice, poses: Sequence[CameraPose]) -> np.ndarray:
    """The offset (E0, N0, H0) in metres subtracted from the COLMAP model's coordinates.

    ``choice``: ``"local"`` (the mean camera centre rounded to whole metres: cameras
    within a few km of 0, where float32 keeps 0.1 mm), ``"none"`` (zeros: world
    coordinates), three numbers or the text ``"E,N,H"``.
    """
    if isinstance(choice, str):
        text = choice.strip()
        if text == "local":
            if not poses:
                return np.zeros(3)
            return np.round(np.mean([p.C_world for p in poses], axis=0)) + 0.0
        if text == "none":
            return np.zeros(3)
        parts = text.split(",")
        try:
            values = [float(v) for v in parts]
        except ValueError:
            values = []
        if len(values) != 3:
            raise ExportError(f"COLMAP offset (--colmap-offset) {choice!r}: give 'local', "
                              "'none' or three numbers E,N,H in metres, e.g. "
                              "500000,5000000,0")
        choice = values
    return check_offset(choice)


def offset_choice_name(choice) -> str:
    """'local', 'none' or 'explicit' for a ``choice`` of :func:`colmap_offset_world`."""
    if isinstance(choice, str) and choice.strip() in OFFSET_CHOICES:
        return choice.strip()
    return "explicit"


def colmap_offset_json(offset_world, choice: str = "explicit", crs: str | None = None) -> str:
    """Text of ``offset.json`` (see the module doc)."""
    offset = check_offset(offset_world)
    data = {"offset_world_m": [float(v) for v in offset], "choice": choice}
    if crs:
        data["crs"] = crs
    data["meaning"] = ("world = model + offset_world_m; world X = Easting, Y = Northing, "
                       "Z = height, metres")
    return json.dumps(data, indent=1) + "\n"


def image_ids_by_name(names: Sequence[str]) -> dict[str, int]:
    """{name: IMAGE_ID}: 1, 2, … in the byte order of the UTF-8 names (COLMAP's order)."""
    ordered = sorted(names, key=lambda n: n.encode("utf-8"))
    return {name: i for i, name in enumerate(ordered, start=1)}


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


def colmap_camera_ids(cameras: CameraSet) -> dict[str, int]:
    """{designer camera id: COLMAP CAMERA_ID}: 1, 2, … in the camera set's order."""
    return {camera_id: k for k, camera_id in enumerate(cameras.interiors, start=1)}


def colmap_cameras_text(interior: InteriorOrientation | CameraSet) -> str:
    """cameras.txt: ``CAMERA_ID MODEL WIDTH HEIGHT PARAMS...``, one camera or one line per
    camera of a :class:`CameraSet`."""
    if isinstance(interior, CameraSet):
        numbers = colmap_camera_ids(interior)
        lines = ["# Camera list with one line of data per camera:",
                 "#   CAMERA_ID, MODEL, WIDTH, HEIGHT, PARAMS[]",
                 f"# Number of cameras: {len(numbers)}",
                 "# designer cameras: " + ", ".join(f"{k} = {c}" for c, k in numbers.items())]
        for camera_id, k in numbers.items():
            model, params = colmap_camera_model(interior.interiors[camera_id])
            W, H = interior.interiors[camera_id].image_size_px
            lines.append(f"{k} {model} {W} {H} {' '.join(fmt(p) for p in params)}")
        return "\n".join(lines) + "\n"
    model, params = colmap_camera_model(interior)
    W, H = interior.image_size_px
    return (
        "# Camera list with one line of data per camera:\n"
        "#   CAMERA_ID, MODEL, WIDTH, HEIGHT, PARAMS[]\n"
        "# Number of cameras: 1\n"
        f"{CAMERA_ID} {model} {W} {H} {' '.join(fmt(p) for p in params)}\n"
    )


def colmap_images_text(poses: Sequence[CameraPose], offset_world=None,
                       cameras: CameraSet | None = None) -> str:
    """images.txt: ``IMAGE_ID QW QX QY QZ TX TY TZ CAMERA_ID NAME`` + an empty 2D line.

    IMAGE_IDs are 1, 2, … in sorted-name order (:func:`image_ids_by_name`); lines
    follow ``poses``. Coordinates are world minus ``offset_world`` (metres; default no
    offset). CAMERA_ID is 1, or with ``cameras`` the image's own camera's
    (:func:`colmap_camera_ids`).
    """
    numbers = None
    if cameras is not None:
        cameras.covers(p.image_name for p in poses)
        numbers = colmap_camera_ids(cameras)
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
    ids = image_ids_by_name([p.image_name for p in poses])
    for pose in poses:
        image_id = ids[pose.image_name]
        q, t = colmap_pose_from_photo(pose.R_cam_to_world, pose.C_world - offset)
        values = " ".join(fmt(v) for v in (*q, *t))
        camera = CAMERA_ID if numbers is None else numbers[cameras.camera_of(pose.image_name)]
        lines.append(f"{image_id} {values} {camera} {pose.image_name}")
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
    interior: InteriorOrientation | CameraSet,
    poses: Sequence[CameraPose],
    offset_world=None,
    choice: str = "explicit",
    crs: str | None = None,
) -> dict[Path, str]:
    """{path: text} of the three model files and offset.json in ``folder`` (nothing is
    written); ``choice`` and ``crs`` are recorded in offset.json."""
    folder = Path(folder)
    if offset_world is None and choice == "explicit":
        choice = "none"
    return {
        folder / "cameras.txt": colmap_cameras_text(interior),
        folder / "images.txt": colmap_images_text(
            poses, offset_world, interior if isinstance(interior, CameraSet) else None),
        folder / "points3D.txt": colmap_points3d_text(),
        folder / OFFSET_FILE: colmap_offset_json(offset_world, choice, crs),
    }


def write_colmap_text_model(
    folder: str | os.PathLike,
    interior: InteriorOrientation | CameraSet,
    poses: Sequence[CameraPose],
    offset_world=None,
) -> Path:
    """Write cameras.txt, images.txt, points3D.txt and offset.json into ``folder``
    (created if needed).

    Each file is written atomically. Returns the folder.
    """
    texts = colmap_texts(folder, interior, poses, offset_world)
    write_texts(texts)
    return Path(folder)


def read_colmap_text_poses(folder: str | os.PathLike, offset_world=None) -> list[CameraPose]:
    """Camera poses from ``folder``/images.txt, in file order, ``offset_world`` added back
    (default: the one in ``folder``/offset.json, zeros without that file).

    Parsed by :func:`designer.export.colmap_read.read_images_text` (COLMAP's rules:
    comments and blank lines skipped, each image's 2D-points line not parsed).
    """
    offset = (model_offset_world(folder) if offset_world is None
              else check_offset(offset_world))
    path = Path(folder) / "images.txt"
    try:
        images = read_images_text(path)
    except ValueError as exc:
        raise ExportError(f"{path}: {exc}") from None
    return camera_poses(images, offset)
