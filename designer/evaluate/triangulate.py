"""Triangulate GCPs from a reconstruction's cameras and the GCPs' image observations.

The reconstruction is a COLMAP model (text or binary; poses world → camera in the CV
frame, pixel origin at the top-left corner like designer's ``uv_px``). Each observation
is undistorted with the image's camera model into a normalised CV ray, the point is
found by linear least squares (DLT over all rays), then refined by Gauss–Newton on the
normalised reprojection error. Coordinates are shifted to the mean camera centre first,
so UTM-sized models keep full precision. A GCP needs at least two observing images that
the model registered.
"""

from __future__ import annotations

import os
from collections.abc import Sequence

import numpy as np

from designer.core.distortion import BrownConrady, FisheyeEquidistant
from designer.core.truth import GcpObservation
from designer.errors import DesignerError
from designer.export.colmap_read import (
    ColmapCamera,
    model_offset_world,
    read_cameras,
    read_images,
)


def normalised_rays(camera: ColmapCamera, uv_px: np.ndarray) -> np.ndarray:
    """Undistorted normalised CV coordinates (N, 2) (x/z, y/z) of pixels ``uv_px`` (N, 2)."""
    p = camera.params
    model = camera.model
    if model in ("SIMPLE_PINHOLE", "SIMPLE_RADIAL", "RADIAL"):
        fx = fy = p[0]
        cx, cy = p[1], p[2]
        k = p[3:]
        dist = BrownConrady(k1=k[0] if k else 0.0, k2=k[1] if len(k) > 1 else 0.0)
    elif model in ("PINHOLE", "OPENCV", "FULL_OPENCV", "OPENCV_FISHEYE"):
        fx, fy, cx, cy = p[:4]
        k = p[4:]
        if model == "OPENCV":
            dist = BrownConrady(k1=k[0], k2=k[1], p1=k[2], p2=k[3])
        elif model == "FULL_OPENCV":
            if any(k[5:8]):
                raise DesignerError(f"camera {camera.camera_id}: FULL_OPENCV with k4..k6 "
                                    "(rational model) is not supported")
            dist = BrownConrady(k1=k[0], k2=k[1], p1=k[2], p2=k[3], k3=k[4])
        elif model == "OPENCV_FISHEYE":
            dist = FisheyeEquidistant(k1=k[0], k2=k[1], k3=k[2], k4=k[3])
        else:
            dist = None
    else:
        raise DesignerError(f"camera {camera.camera_id}: COLMAP model {model} is not "
                            "supported for triangulation")
    uv = np.asarray(uv_px, dtype=np.float64).reshape(-1, 2)
    xy = np.column_stack([(uv[:, 0] - cx) / fx, (uv[:, 1] - cy) / fy])
    if dist is not None and not dist.is_identity:
        xy = dist.undistort(xy)
    return xy


def triangulate_point(R_world_to_cv: np.ndarray, t: np.ndarray, xy: np.ndarray,
                      iterations: int = 10) -> np.ndarray:
    """Point (3,) seen at normalised coordinates ``xy`` (K, 2) by cameras x = R·X + t."""
    rows = []
    for R, tt, (x, y) in zip(R_world_to_cv, t, xy, strict=True):
        P = np.hstack([R, tt[:, None]])
        rows += [x * P[2] - P[0], y * P[2] - P[1]]
    _, _, vt = np.linalg.svd(np.array(rows))
    X = vt[-1, :3] / vt[-1, 3]
    for _ in range(iterations):  # Gauss–Newton on the normalised reprojection error
        c = np.einsum("kij,j->ki", R_world_to_cv, X) + t
        r = (c[:, :2] / c[:, 2:3] - xy).ravel()
        J = np.empty((2 * len(c), 3))
        J[0::2] = (R_world_to_cv[:, 0] - (c[:, 0] / c[:, 2])[:, None] * R_world_to_cv[:, 2]) \
            / c[:, 2:3]
        J[1::2] = (R_world_to_cv[:, 1] - (c[:, 1] / c[:, 2])[:, None] * R_world_to_cv[:, 2]) \
            / c[:, 2:3]
        step = np.linalg.lstsq(J, -r, rcond=None)[0]
        X = X + step
        if np.linalg.norm(step) < 1e-12 * max(1.0, np.linalg.norm(X)):
            break
    return X


def triangulate_gcps(
    model_folder: str | os.PathLike,
    observations: Sequence[GcpObservation],
    *,
    offset_world=None,
) -> dict[str, np.ndarray]:
    """{gcp_id: (X, Y, Z) world} for every GCP observed in >= 2 registered images.

    ``offset_world`` (E0, N0, H0) is added to the model's coordinates (for models built
    in local coordinates); default: the offset.json beside the model, else none.
    """
    from designer.core.rotation import rotation_from_quaternion

    cameras = read_cameras(model_folder)
    images = {im.name: im for im in read_images(model_folder)}
    if not images:
        raise DesignerError(f"COLMAP model {model_folder} has no registered images")
    offset = (model_offset_world(model_folder) if offset_world is None
              else np.asarray(offset_world, np.float64))
    R_all = {name: rotation_from_quaternion(im.q_wxyz) for name, im in images.items()}
    # centre of the cameras: x = R·X + t = R·(X − c) + (t + R·c)
    centres = np.array([-(R_all[n].T @ im.t) for n, im in images.items()])
    c0 = centres.mean(axis=0)
    by_gcp: dict[str, list[GcpObservation]] = {}
    for o in observations:
        if o.image_name in images:
            by_gcp.setdefault(o.gcp_id, []).append(o)
    out: dict[str, np.ndarray] = {}
    for gcp_id, obs in by_gcp.items():
        if len(obs) < 2:
            continue
        Rs, ts, xys = [], [], []
        for o in obs:
            im = images[o.image_name]
            R = R_all[o.image_name]
            Rs.append(R)
            ts.append(im.t + R @ c0)
            xys.append(normalised_rays(cameras[im.camera_id], o.uv_px[None])[0])
        X = triangulate_point(np.array(Rs), np.array(ts), np.array(xys))
        out[gcp_id] = X + c0 + offset
    return out
