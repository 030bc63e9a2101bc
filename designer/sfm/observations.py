"""The tie-point observations of a pycolmap reconstruction as arrays.

pycolmap hands out 2D points one Python object at a time (``image.points2D[i].xy``):
about 1 s for the 110,000 observations of the 60-image example survey, more than the
whole vectorised adjustment they feed. COLMAP's binary model holds them as packed
records, so the reconstruction is written once to a temporary folder (0.1 s) and read
back with numpy: ``images.bin`` for the observations (COLMAP's
src/colmap/scene/reconstruction_io.cc, little-endian: per image id u32, quaternion and
translation 7 f64, camera id u32, name NUL-terminated, the number of 2D points u64, then
x, y f64 and the point3D id u64 of each, 2⁶⁴ − 1 for none), ``points3D.bin`` for the
points (designer.export.colmap_read).
"""

from __future__ import annotations

import struct
import tempfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from designer.export.colmap_read import read_points3d

#: COLMAP's point3D id of a 2D point without a 3D point
NO_POINT3D = np.iinfo(np.uint64).max
_POINT2D = np.dtype([("x", "<f8"), ("y", "<f8"), ("point3D_id", "<u8")])


@dataclass(frozen=True)
class TieObservations:
    """Observations (image id, point3D id, xy px), image by image in the file's order and
    each image's 2D points in their order; and every point's id and position."""

    image_id: np.ndarray   # (n,) int64
    point3D_id: np.ndarray  # (n,) int64
    xy: np.ndarray          # (n, 2) px
    point_ids: np.ndarray   # (P,) int64
    point_xyz: np.ndarray   # (P, 3)


def tie_observations(rec) -> TieObservations:
    """Every observation of a 3D point in ``rec`` (module docstring)."""
    with tempfile.TemporaryDirectory(prefix="designer-observations-") as folder:
        rec.write_binary(folder)
        data = (Path(folder) / "images.bin").read_bytes()
        points = read_points3d(Path(folder) / "points3D.bin")
    image_ids, point_ids, xys = [], [], []
    (n_images,), pos = struct.unpack_from("<Q", data, 0), 8
    for _ in range(n_images):
        (image_id,) = struct.unpack_from("<I", data, pos)
        pos = data.index(b"\0", pos + 64) + 1  # past the pose, camera id and name
        (n2d,) = struct.unpack_from("<Q", data, pos)
        pos += 8
        p2d = np.frombuffer(data, _POINT2D, count=n2d, offset=pos)
        pos += _POINT2D.itemsize * n2d
        seen = p2d["point3D_id"] != NO_POINT3D
        image_ids.append(np.full(int(seen.sum()), image_id, np.int64))
        point_ids.append(p2d["point3D_id"][seen].astype(np.int64))
        xys.append(np.column_stack([p2d["x"][seen], p2d["y"][seen]]))
    if pos != len(data):
        raise ValueError(f"images.bin: {len(data) - pos} bytes left after {n_images} images")
    return TieObservations(np.concatenate(image_ids or [np.zeros(0, np.int64)]),
                           np.concatenate(point_ids or [np.zeros(0, np.int64)]),
                           np.concatenate(xys or [np.zeros((0, 2))]),
                           points.ids, points.xyz)
