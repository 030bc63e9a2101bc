"""Read a COLMAP sparse model — text (``*.txt``) or binary (``*.bin``) — into plain arrays.

The one COLMAP reader: the round trip of :mod:`designer.export.colmap` and the
accuracy assessment (:mod:`designer.evaluate`) both read through it.

Conventions at this boundary (COLMAP doc/format.rst, "Output Format"; the binary layout
of COLMAP's src/colmap/scene/reconstruction_io.cc, little-endian):

* images store world → camera in the computer-vision frame, ``q`` Hamilton (w, x, y, z)
  and ``t``; :func:`designer.core.rotation.photo_pose_from_colmap` turns them into
  designer's (R_cam_to_world, C);
* pixel coordinates have their origin at the top-left corner of the top-left pixel, as
  designer's, so ``cx, cy`` need no shift;
* coordinates are whatever the model was built in: add ``offset_world`` (E0, N0, H0)
  when the model is in local coordinates; designer's own models name it in
  ``offset.json`` beside the model files (:func:`model_offset_world`).

Camera parameters are kept as COLMAP lists them (``ColmapCamera.params``); the 2-D
points of each image are skipped.
"""

from __future__ import annotations

import os
import struct
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from designer.core.rotation import photo_pose_from_colmap
from designer.core.truth import CameraPose
from designer.errors import DesignerError

#: the file beside a designer COLMAP model that names its offset (designer.export.colmap)
OFFSET_FILE = "offset.json"

#: COLMAP camera model ids (binary files) → (name, number of parameters)
CAMERA_MODELS = {
    0: ("SIMPLE_PINHOLE", 3), 1: ("PINHOLE", 4), 2: ("SIMPLE_RADIAL", 4), 3: ("RADIAL", 5),
    4: ("OPENCV", 8), 5: ("OPENCV_FISHEYE", 8), 6: ("FULL_OPENCV", 12), 7: ("FOV", 5),
    8: ("SIMPLE_RADIAL_FISHEYE", 4), 9: ("RADIAL_FISHEYE", 5), 10: ("THIN_PRISM_FISHEYE", 12),
}


@dataclass(frozen=True)
class ColmapCamera:
    camera_id: int
    model: str
    width: int
    height: int
    params: tuple[float, ...]


@dataclass(frozen=True)
class ColmapImage:
    image_id: int
    name: str
    q_wxyz: np.ndarray
    t: np.ndarray
    camera_id: int


@dataclass(frozen=True)
class ColmapPoints:
    """3-D points: ids (N,), xyz (N, 3) float64, rgb (N, 3) uint8, reprojection error (N,)."""

    ids: np.ndarray
    xyz: np.ndarray
    rgb: np.ndarray
    error: np.ndarray


def model_files(folder: str | os.PathLike) -> tuple[Path, str] | None:
    """(folder, ".bin" or ".txt") if ``folder`` holds a COLMAP model, else None."""
    folder = Path(folder)
    for ext in (".bin", ".txt"):
        if all((folder / f"{n}{ext}").is_file() for n in ("cameras", "images")):
            return folder, ext
    return None


def model_offset_world(folder: str | os.PathLike) -> np.ndarray:
    """The offset (E0, N0, H0, metres) written beside a model in ``offset.json``: world =
    model + offset. Zeros when the folder has no such file."""
    import json

    path = Path(folder) / OFFSET_FILE
    if not path.is_file():
        return np.zeros(3)
    try:
        offset = np.asarray(json.loads(path.read_text(encoding="utf-8"))["offset_world_m"],
                            dtype=np.float64)
    except (ValueError, KeyError, TypeError) as exc:
        raise DesignerError(f"{path}: not a designer offset file ({exc}); it needs "
                            '{"offset_world_m": [E, N, H]}') from None
    if offset.shape != (3,) or not np.isfinite(offset).all():
        raise DesignerError(f"{path}: offset_world_m must be three finite numbers (E, N, H)")
    return offset


def _require(folder: str | os.PathLike) -> tuple[Path, str]:
    found = model_files(folder)
    if found is None:
        raise DesignerError(f"{folder} is not a COLMAP model: it needs cameras and images "
                            "(.txt or .bin)")
    return found


def _data_lines(path: Path):
    with open(path, encoding="utf-8") as fh:
        for line in fh:
            line = line.strip()
            if line and not line.startswith("#"):
                yield line


def _fail(path: Path, detail: str) -> DesignerError:
    return DesignerError(f"{path} cannot be read as a COLMAP model file ({detail})")


def read_cameras(folder: str | os.PathLike) -> dict[int, ColmapCamera]:
    folder, ext = _require(folder)
    path = folder / f"cameras{ext}"
    out: dict[int, ColmapCamera] = {}
    try:
        if ext == ".txt":
            for line in _data_lines(path):
                p = line.split()
                out[int(p[0])] = ColmapCamera(int(p[0]), p[1], int(p[2]), int(p[3]),
                                              tuple(float(v) for v in p[4:]))
            return out
        data = path.read_bytes()
        (n,), pos = struct.unpack_from("<Q", data, 0), 8
        for _ in range(n):
            cam_id, model_id, w, h = struct.unpack_from("<iiQQ", data, pos)
            pos += 24
            name, n_params = CAMERA_MODELS[model_id]
            params = struct.unpack_from(f"<{n_params}d", data, pos)
            pos += 8 * n_params
            out[cam_id] = ColmapCamera(cam_id, name, int(w), int(h), tuple(params))
    except (ValueError, IndexError, KeyError, struct.error) as exc:
        raise _fail(path, str(exc) or type(exc).__name__) from None
    return out


def read_images(folder: str | os.PathLike) -> list[ColmapImage]:
    """Images in file order (text) or id order (binary)."""
    folder, ext = _require(folder)
    path = folder / f"images{ext}"
    out: list[ColmapImage] = []
    try:
        if ext == ".txt":
            return read_images_text(path)
        data = path.read_bytes()
        (n,), pos = struct.unpack_from("<Q", data, 0), 8
        for _ in range(n):
            image_id, *qt, cam_id = struct.unpack_from("<i7di", data, pos)
            pos += 64
            end = data.index(b"\0", pos)
            name = data[pos:end].decode("utf-8")
            pos = end + 1
            (n2d,) = struct.unpack_from("<Q", data, pos)
            pos += 8 + 24 * n2d  # x, y (double), point3D id (int64)
            out.append(ColmapImage(image_id, name, np.array(qt[:4]), np.array(qt[4:]), cam_id))
    except (ValueError, IndexError, UnicodeDecodeError, struct.error) as exc:
        raise _fail(path, str(exc) or type(exc).__name__) from None
    return sorted(out, key=lambda im: im.image_id)


def read_images_text(path: str | os.PathLike) -> list[ColmapImage]:
    """Images of one ``images.txt``, in file order (ValueError on a malformed line).

    Follows COLMAP's reader: blank and '#' lines are skipped before an image line;
    the line right after each image line holds its 2D points and is not parsed.
    """
    lines = Path(path).read_text(encoding="utf-8").splitlines()
    out: list[ColmapImage] = []
    i = 0
    while i < len(lines):
        line = lines[i].strip()
        i += 1
        if not line or line.startswith("#"):
            continue
        p = line.split()
        if len(p) < 10:
            raise ValueError(f"malformed image line {line!r}")
        out.append(ColmapImage(int(p[0]), p[9], np.array([float(v) for v in p[1:5]]),
                               np.array([float(v) for v in p[5:8]]), int(p[8])))
        i += 1  # the POINTS2D line
    return out


def camera_poses(images: list[ColmapImage], offset_world: np.ndarray) -> list[CameraPose]:
    """designer's poses (R_cam_to_world, C_world) of COLMAP images, ``offset_world`` (3,)
    in metres added back to every centre."""
    poses = []
    for im in images:
        R, C = photo_pose_from_colmap(im.q_wxyz, im.t)
        poses.append(CameraPose(im.name, C + offset_world, R))
    return poses


def read_points3d(path: str | os.PathLike) -> ColmapPoints:
    """Points of ``points3D.txt`` / ``points3D.bin`` (or of the model folder holding one)."""
    path = Path(path)
    if path.is_dir():
        folder, ext = _require(path) if model_files(path) else (path, "")
        candidates = [folder / f"points3D{e}" for e in ((ext,) if ext else (".bin", ".txt"))]
        found = [c for c in candidates if c.is_file()]
        if not found:
            raise DesignerError(f"{path} holds no points3D.bin or points3D.txt")
        path = found[0]
    try:
        if path.suffix == ".txt":
            return _points_text(path)
        return _points_binary(path)
    except (ValueError, IndexError, struct.error) as exc:
        raise _fail(path, str(exc).splitlines()[0] if str(exc) else type(exc).__name__) \
            from None


def _points_text(path: Path) -> ColmapPoints:
    rows = [line.split()[:8] for line in _data_lines(path)]
    if not rows:
        return ColmapPoints(np.zeros(0, np.int64), np.zeros((0, 3)), np.zeros((0, 3), np.uint8),
                            np.zeros(0))
    arr = np.array(rows, dtype=np.float64)
    return ColmapPoints(arr[:, 0].astype(np.int64), arr[:, 1:4], arr[:, 4:7].astype(np.uint8),
                        arr[:, 7])


def _points_binary(path: Path) -> ColmapPoints:
    data = path.read_bytes()
    (n,) = struct.unpack_from("<Q", data, 0)
    # record: id u64, xyz 3 f64, rgb 3 u8, error f64, track length u64, track 8 bytes each
    offsets = np.empty(n, np.int64)
    pos, unpack = 8, struct.Struct("<Q").unpack_from
    for i in range(n):  # records have variable length (the track): find where each starts
        offsets[i] = pos
        pos += 51 + 8 * unpack(data, pos + 43)[0]
    if pos != len(data):
        raise ValueError(f"{len(data) - pos} bytes left after {n} points")
    raw = np.frombuffer(data, np.uint8)

    def field(start: int, size: int, dtype: str) -> np.ndarray:
        return raw[offsets[:, None] + np.arange(start, start + size)].copy().view(dtype)

    return ColmapPoints(field(0, 8, "<u8")[:, 0].astype(np.int64),
                        field(8, 24, "<f8").reshape(n, 3), field(32, 3, "u1").reshape(n, 3),
                        field(35, 8, "<f8")[:, 0])
