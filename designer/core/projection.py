"""Projection world → pixel, back-projection pixel → ray, and the ground a camera sees.

Frames (docs/conventions.md): world X east, Y north, Z up (metres, float64, UTM-sized
values are fine because camera-relative vectors are formed before anything else);
camera pose = perspective centre ``C_world`` and ``R_cam_to_world`` (photogrammetric
camera frame: x right, y image top, z backwards). Pixels are continuous, origin at the
top-left corner of the top-left pixel, u right, v down.

All functions are vectorised: N points, M cameras.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from designer.core.distortion import FisheyeEquidistant
from designer.core.interior import InteriorOrientation
from designer.core.rotation import R_CV_FROM_PHOTO

#: points are projected in chunks of this many so temporaries stay in cache
CHUNK_POINTS = 1 << 14


@dataclass(frozen=True)
class Projection:
    """Result of projecting N points into M cameras.

    Attributes:
        uv_px: (M, N, 2) pixel coordinates; NaN where ``in_front`` is False.
        in_front: (M, N) the point is in front of the camera (inside the lens model's
            field for a fisheye) and was projected.
        in_image: (M, N) projected and inside the image rectangle [0, W) × [0, H).
        depth_m: (M, N) distance along the viewing axis (CV z); negative behind.
    """

    uv_px: np.ndarray
    in_front: np.ndarray
    in_image: np.ndarray
    depth_m: np.ndarray


def R_cv_from_world(R_cam_to_world: np.ndarray) -> np.ndarray:
    """World → CV-camera rotation(s): diag(1, −1, −1) · Rᵀ, shape (..., 3, 3)."""
    R = np.asarray(R_cam_to_world, dtype=float)
    return R_CV_FROM_PHOTO @ np.swapaxes(R, -1, -2)


def project_points(
    points_world: np.ndarray,
    C_world: np.ndarray,
    R_cam_to_world: np.ndarray,
    interior: InteriorOrientation,
) -> Projection:
    """Project world points (N, 3) into cameras C (3,) or (M, 3), R (3, 3) or (M, 3, 3).

    Points behind a camera (or outside a fisheye's valid field) are flagged and get
    NaN pixel coordinates; they are never projected through the model.
    """
    P = np.asarray(points_world, dtype=float).reshape(-1, 3)
    C = np.asarray(C_world, dtype=float).reshape(-1, 3)
    R = np.asarray(R_cam_to_world, dtype=float).reshape(-1, 3, 3)
    if len(C) != len(R):
        raise ValueError(f"{len(C)} camera centres but {len(R)} rotations")
    M, N = len(C), len(P)
    uv = np.empty((M, N, 2))
    depth = np.empty((M, N))
    in_front = np.empty((M, N), dtype=bool)
    R_cv = R_cv_from_world(R)
    for m in range(M):
        for start in range(0, N, CHUNK_POINTS):
            stop = min(start + CHUNK_POINTS, N)
            _project_chunk(
                P[start:stop], C[m], R_cv[m], interior,
                uv[m, start:stop], depth[m, start:stop], in_front[m, start:stop],
            )
    W, H = interior.image_size_px
    with np.errstate(invalid="ignore"):
        in_image = (
            in_front
            & (uv[..., 0] >= 0) & (uv[..., 0] < W)
            & (uv[..., 1] >= 0) & (uv[..., 1] < H)
        )
    return Projection(uv_px=uv, in_front=in_front, in_image=in_image, depth_m=depth)


def project_pairwise(
    points_world: np.ndarray,
    C_world: np.ndarray,
    R_cam_to_world: np.ndarray,
    camera: np.ndarray,
    interior: InteriorOrientation,
) -> Projection:
    """Project each world point k (N, 3) into its own camera ``camera[k]`` of C (M, 3),
    R (M, 3, 3): :func:`project_points` of many cameras with a few points each in one
    pass. The result's arrays have no camera axis: ``uv_px`` (N, 2), the others (N,)."""
    P = np.asarray(points_world, dtype=float).reshape(-1, 3)
    C = np.asarray(C_world, dtype=float).reshape(-1, 3)
    R_cv = R_cv_from_world(np.asarray(R_cam_to_world, dtype=float).reshape(-1, 3, 3))
    cam = np.asarray(camera, dtype=np.intp).reshape(-1)
    if len(cam) != len(P):
        raise ValueError(f"{len(P)} points but {len(cam)} camera indices")
    N = len(P)
    uv = np.empty((N, 2))
    depth = np.empty(N)
    in_front = np.empty(N, dtype=bool)
    # camera by camera, each camera's points turned as project_points turns them (the same
    # product, so the same bits); the rest point by point in chunks
    order = np.argsort(cam, kind="stable")
    by_cam = cam[order]
    D = P[order] - C[by_cam]
    X = np.empty((3, N))
    cuts = np.flatnonzero(np.diff(by_cam)) + 1
    for a, b in zip(np.r_[0, cuts], np.r_[cuts, N], strict=True):
        if b > a:
            X[:, a:b] = R_cv[by_cam[a]] @ D[a:b].T
    for start in range(0, N, CHUNK_POINTS):
        sl = slice(start, min(start + CHUNK_POINTS, N))
        rows = order[sl]
        u, d, f = np.empty((sl.stop - start, 2)), np.empty(sl.stop - start), np.empty(
            sl.stop - start, dtype=bool)
        _camera_to_pixels(np.ascontiguousarray(X[:, sl]), interior, u, d, f)
        uv[rows], depth[rows], in_front[rows] = u, d, f
    W, H = interior.image_size_px
    with np.errstate(invalid="ignore"):
        in_image = (in_front & (uv[:, 0] >= 0) & (uv[:, 0] < W)
                    & (uv[:, 1] >= 0) & (uv[:, 1] < H))
    return Projection(uv_px=uv, in_front=in_front, in_image=in_image, depth_m=depth)


def _project_chunk(P, C, R_cv, interior, uv_out, depth_out, front_out) -> None:
    # Subtract the centre first, in float64: UTM-sized values cancel exactly here.
    # Rows of X (3, n) are contiguous, which keeps the element-wise work fast.
    _camera_to_pixels(R_cv @ (P - C).T, interior, uv_out, depth_out, front_out)


def _camera_to_pixels(X, interior, uv_out, depth_out, front_out) -> None:
    """Pixels of CV-camera-frame points X (3, n), written into the outputs (X is used up)."""
    z = X[2]
    depth_out[:] = z
    model = interior.distortion
    if isinstance(model, FisheyeEquidistant):
        with np.errstate(invalid="ignore", divide="ignore"):
            xy = model.distort_rays(X.T)
        theta = np.arctan2(np.hypot(X[0], X[1]), z)
        front = np.isfinite(xy[:, 0]) & (theta < model.max_monotone_theta())
        x, y = xy[:, 0], xy[:, 1]
    else:
        front = z > 0
        with np.errstate(invalid="ignore", divide="ignore"):
            inv_z = np.divide(1.0, z, where=front, out=np.full_like(z, np.nan))
        x = X[0]
        x *= inv_z
        y = X[1]
        y *= inv_z
        if model is not None and not model.is_identity:
            x, y = model.distort_xy(x, y)
    front_out[:] = front
    u, v = uv_out[:, 0], uv_out[:, 1]
    np.multiply(x, interior.fx_px, out=u)
    u += interior.cx_px
    np.multiply(y, interior.fy_px, out=v)
    v += interior.cy_px


def pixel_rays_world(
    uv_px: np.ndarray,
    R_cam_to_world: np.ndarray,
    interior: InteriorOrientation,
) -> np.ndarray:
    """Unit viewing rays in the world frame for pixels (N, 2) of one camera → (N, 3).

    The ray of pixel ``uv`` starts at the perspective centre C and points outwards
    into the scene. Raises NotInvertibleError where the distortion cannot be inverted.
    """
    rays_cv = interior.rays_cv(uv_px)
    R_world_from_cv = np.asarray(R_cam_to_world, dtype=float) @ R_CV_FROM_PHOTO
    return rays_cv @ R_world_from_cv.T


def image_corners_px(interior: InteriorOrientation) -> np.ndarray:
    """The four image corners (4, 2) in pixels: top-left, top-right, bottom-right, bottom-left."""
    W, H = interior.image_size_px
    return np.array([[0.0, 0.0], [W, 0.0], [W, H], [0.0, H]])


def edge_pixels(interior: InteriorOrientation, per_edge: int) -> np.ndarray:
    """``per_edge`` pixel positions evenly along each image edge, ends included (4·per_edge,
    2): the top edge left to right, the bottom edge, the left edge top to bottom, the
    right edge."""
    W, H = interior.image_size_px
    s = np.linspace(0.0, 1.0, per_edge)
    return np.concatenate([np.column_stack([s * W, np.zeros_like(s)]),
                           np.column_stack([s * W, np.full_like(s, H)]),
                           np.column_stack([np.zeros_like(s), s * H]),
                           np.column_stack([np.full_like(s, W), s * H])])


def ground_sample_distance_m(interior: InteriorOrientation, distance_m: float | np.ndarray):
    """Ground sample distance (m/px) at the principal point for a surface ``distance_m``
    in front of the camera, perpendicular to the viewing axis: distance · pitch / f.

    Equals QGroundControl's GSD = H · sw / (W · f) for a nadir camera at height H.
    """
    pitch_mm = interior.pixel_pitch_x_mm
    return np.asarray(distance_m, dtype=float) * pitch_mm / interior.focal_length_mm


def intersect_plane(
    C_world: np.ndarray, rays_world: np.ndarray, height_m: float
) -> np.ndarray:
    """Where rays from C (3,) hit the horizontal plane Z = height_m → (N, 3); NaN if never."""
    C = np.asarray(C_world, dtype=float)
    d = np.asarray(rays_world, dtype=float).reshape(-1, 3)
    with np.errstate(divide="ignore", invalid="ignore"):
        t = (height_m - C[2]) / d[:, 2]
    t = np.where(t > 0, t, np.nan)
    return C + t[:, None] * d


def footprint_on_plane(
    C_world: np.ndarray,
    R_cam_to_world: np.ndarray,
    interior: InteriorOrientation,
    height_m: float = 0.0,
) -> np.ndarray:
    """Ground footprint (4, 3) of the image corners on the plane Z = height_m.

    Corner order as :func:`image_corners_px`; NaN rows for corners above the horizon.
    """
    rays = pixel_rays_world(image_corners_px(interior), R_cam_to_world, interior)
    return intersect_plane(C_world, rays, height_m)
