"""COLMAP dense-workspace arrays: depth and normal maps, and normals from a depth map.

COLMAP stores a map as the text header ``width&height&channels&`` followed by
little-endian float32 values, channel after channel, each row-major (so a (H, W, C)
array is written as its (C, H, W) transpose). Depth is metres along the camera's z axis
(0 = no depth); normals are unit vectors in the computer-vision camera frame (x right,
y down, z forward) pointing towards the camera. The files live in
``stereo/depth_maps/NAME.geometric.bin`` and ``stereo/normal_maps/NAME.geometric.bin``
of the workspace ``pycolmap.undistort_images`` writes.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from designer.atomic import atomic_path


def write_colmap_array(path: str | os.PathLike, array: np.ndarray) -> None:
    """Write ``array`` (H, W) or (H, W, C) as a COLMAP float32 map, atomically."""
    a = np.asarray(array, dtype="<f4")
    if a.ndim == 2:
        a = a[:, :, None]
    h, w, c = a.shape
    with atomic_path(path) as tmp, open(tmp, "wb") as fh:
        fh.write(f"{w}&{h}&{c}&".encode("ascii"))
        fh.write(np.ascontiguousarray(a.transpose(2, 0, 1)).tobytes())


def read_colmap_array(path: str | os.PathLike) -> np.ndarray:
    """Read a COLMAP map as (H, W) for one channel, else (H, W, C), float32."""
    data = Path(path).read_bytes()
    fields, pos = [], 0
    for _ in range(3):
        end = data.index(b"&", pos)
        fields.append(int(data[pos:end]))
        pos = end + 1
    w, h, c = fields
    a = np.frombuffer(data, dtype="<f4", offset=pos, count=w * h * c).reshape(c, h, w)
    a = a.transpose(1, 2, 0)
    return a[:, :, 0].copy() if c == 1 else a.copy()


def normals_from_depth(depth_m: np.ndarray, K: np.ndarray, step_px: int = 2) -> np.ndarray:
    """Unit normals (H, W, 3) float32 in the camera frame from a depth map (H, W).

    Each pixel is back-projected (COLMAP pixel centres, ``K`` (3, 3)); the normal is the
    cross product of central differences ``step_px`` pixels apart, turned to face the
    camera. Zero where the depth or any of the four neighbours used is missing.
    """
    h, w = depth_m.shape
    jj, ii = np.meshgrid(np.arange(w) + 0.5, np.arange(h) + 0.5)
    Kinv = np.linalg.inv(K)
    rays = np.stack([Kinv[0, 0] * jj + Kinv[0, 1] * ii + Kinv[0, 2],
                     Kinv[1, 1] * ii + Kinv[1, 2], np.ones_like(jj)], axis=-1)
    X = rays * depth_m[:, :, None].astype(np.float64)
    s = step_px
    normals = np.zeros((h, w, 3), dtype=np.float64)
    du = X[s:-s, 2 * s:] - X[s:-s, :-2 * s]
    dv = X[2 * s:, s:-s] - X[:-2 * s, s:-s]
    n = np.cross(du, dv)
    centre = X[s:-s, s:-s]
    flip = np.sum(n * centre, axis=-1) > 0
    n[flip] *= -1
    norm = np.linalg.norm(n, axis=-1)
    ok = (depth_m[s:-s, s:-s] > 0) & (depth_m[s:-s, 2 * s:] > 0) \
        & (depth_m[s:-s, :-2 * s] > 0) & (depth_m[2 * s:, s:-s] > 0) \
        & (depth_m[:-2 * s, s:-s] > 0) & (norm > 0)
    inner = np.where(ok[:, :, None], n / np.where(norm > 0, norm, 1.0)[:, :, None], 0.0)
    normals[s:-s, s:-s] = inner
    return normals.astype(np.float32)
