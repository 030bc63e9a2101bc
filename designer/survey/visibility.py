"""Which cameras see which ground points: in the image and not hidden by the terrain.

World frame X east, Y north, Z up (metres); cameras as ``C_world`` (M, 3) and
``R_cam_to_world`` (M, 3, 3) (docs/conventions.md). A point is *seen* by a camera when
:func:`designer.core.projection.project_points` puts it inside the image (at least
``border_px`` from every edge) and :meth:`TerrainRaycaster.occluded` finds the sight
line clear: the ray from the camera meets the terrain no closer than the point minus
``tol_m``.

Each camera only projects the points inside a box around its ground footprint, found
by casting rays through the image border onto the planes of the terrain's lowest
point and of the lower of its highest point and the camera; this box holds every
terrain point the camera can see, so the culling changes nothing but the run time.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from designer.core.interior import InteriorOrientation
from designer.core.projection import project_pairwise
from designer.core.rotation import R_CV_FROM_PHOTO
from designer.survey.raycast import TerrainRaycaster

#: rays per image edge used to bound a camera's footprint
BORDER_RAYS_PER_EDGE = 9
#: the footprint box is grown by this share of its size (bulging distorted edges)
BOX_GROWTH = 0.05
#: sight lines tested for occlusion in one vectorised batch
OCCLUSION_BATCH = 1 << 19
#: (camera, candidate point) pairs projected in one vectorised batch
PROJECTION_BATCH = 1 << 18


@dataclass(frozen=True)
class VisiblePairs:
    """Every (camera, point) pair where the camera sees the point, camera-major order.

    Attributes:
        camera: (K,) camera indices.
        point: (K,) point indices.
        uv_px: (K, 2) pixel coordinates of the point in that camera.
        depth_m: (K,) distance along the camera's viewing axis (m).
    """

    camera: np.ndarray
    point: np.ndarray
    uv_px: np.ndarray
    depth_m: np.ndarray

    def counts(self, n_points: int) -> np.ndarray:
        """Number of cameras seeing each point, (n_points,)."""
        return np.bincount(self.point, minlength=n_points)


def footprint_boxes(
    C_world: np.ndarray,
    R_cam_to_world: np.ndarray,
    interior: InteriorOrientation,
    z_min_m: float,
    z_max_m: float,
) -> np.ndarray:
    """(M, 4) boxes (x_min, x_max, y_min, y_max) holding all points a camera can see
    with heights in [z_min_m, z_max_m]; infinite for a camera that sees the horizon."""
    C = np.asarray(C_world, dtype=float).reshape(-1, 3)
    R = np.asarray(R_cam_to_world, dtype=float).reshape(-1, 3, 3)
    W, H = interior.image_size_px
    s = np.linspace(0.0, 1.0, BORDER_RAYS_PER_EDGE)
    uv = np.vstack([np.column_stack([s * W, np.zeros_like(s)]),
                    np.column_stack([s * W, np.full_like(s, H)]),
                    np.column_stack([np.zeros_like(s), s * H]),
                    np.column_stack([np.full_like(s, W), s * H])])
    rays_cv = interior.rays_cv(uv)  # (S, 3), the same for every camera
    rays = np.einsum("mij,sj->msi", R @ R_CV_FROM_PHOTO, rays_cv)  # (M, S, 3) world
    down = np.all(rays[:, :, 2] < -1e-9, axis=1)
    boxes = np.tile([-np.inf, np.inf, -np.inf, np.inf], (len(C), 1))
    if not down.any():
        return boxes
    Cd, rd = C[down], rays[down]
    pts = []
    for z in (np.minimum(z_max_m, Cd[:, 2]), np.full(len(Cd), z_min_m)):
        t = np.maximum((z - Cd[:, 2])[:, None] / rd[:, :, 2], 0.0)
        pts.append(Cd[:, None, :2] + t[:, :, None] * rd[:, :, :2])
    p = np.concatenate(pts, axis=1)  # (m, 2S, 2)
    lo, hi = p.min(axis=1), p.max(axis=1)
    grow = BOX_GROWTH * (hi - lo) + 1e-6 * (1 + np.abs(lo))
    boxes[down] = np.column_stack([lo[:, 0] - grow[:, 0], hi[:, 0] + grow[:, 0],
                                   lo[:, 1] - grow[:, 1], hi[:, 1] + grow[:, 1]])
    return boxes


def visible_pairs(
    points_world: np.ndarray,
    C_world: np.ndarray,
    R_cam_to_world: np.ndarray,
    interior: InteriorOrientation,
    raycaster: TerrainRaycaster | None,
    *,
    tol_m: float = 0.01,
    border_px: float = 0.0,
) -> VisiblePairs:
    """All (camera, point) pairs where the camera sees the point (module docstring).

    points_world: (N, 3) world points (on or above the terrain). With
    ``raycaster=None`` nothing is occluded (in-image test only).
    """
    P = np.asarray(points_world, dtype=float).reshape(-1, 3)
    C = np.asarray(C_world, dtype=float).reshape(-1, 3)
    R = np.asarray(R_cam_to_world, dtype=float).reshape(-1, 3, 3)
    if len(P) == 0 or len(C) == 0:
        return _no_pairs()
    z_lo = float(P[:, 2].min(initial=np.inf))
    z_hi = float(P[:, 2].max(initial=-np.inf))
    if raycaster is not None:
        z_lo, z_hi = min(z_lo, raycaster.z_min_m), max(z_hi, raycaster.z_max_m)
    boxes = footprint_boxes(C, R, interior, z_lo, z_hi)
    order = np.argsort(P[:, 0], kind="stable")
    xs = P[order, 0]
    W, H = interior.image_size_px
    # each camera's candidates: the points in its box, from the run of points sorted by
    # x that the box's x range spans; cameras are taken in batches of about
    # PROJECTION_BATCH candidates, each batch projected in one pass (each point into its
    # own camera), in camera order and, within a camera, in x order
    first = np.searchsorted(xs, boxes[:, 0], "left")
    runs = np.maximum(np.searchsorted(xs, boxes[:, 1], "right") - first, 0)
    ends = np.cumsum(runs)
    cams, pts, uvs, depths = [], [], [], []
    start = 0
    while start < len(C):
        stop = max(start + 1, int(np.searchsorted(
            ends, ends[start] - runs[start] + PROJECTION_BATCH, "right")))
        n_run = runs[start:stop]
        cam = np.repeat(np.arange(start, stop), n_run)
        # position in the x-sorted run of each candidate: its camera's first + its rank
        rank = np.arange(cam.size) - np.repeat(np.cumsum(n_run) - n_run, n_run)
        pt = order[first[cam] + rank]
        box = boxes[cam]
        inside = (P[pt, 1] >= box[:, 2]) & (P[pt, 1] <= box[:, 3])
        cam, pt = cam[inside], pt[inside]
        start = stop
        if cam.size == 0:
            continue
        proj = project_pairwise(P[pt], C, R, cam, interior)
        uv, ok = proj.uv_px, proj.in_image
        if border_px > 0:
            ok &= ((uv[:, 0] >= border_px) & (uv[:, 0] <= W - border_px)
                   & (uv[:, 1] >= border_px) & (uv[:, 1] <= H - border_px))
        cams.append(cam[ok])
        pts.append(pt[ok])
        uvs.append(uv[ok])
        depths.append(proj.depth_m[ok])
    if not cams:
        return _no_pairs()
    cam, pt = np.concatenate(cams), np.concatenate(pts)
    uv, depth = np.concatenate(uvs), np.concatenate(depths)
    if raycaster is not None and cam.size:
        hidden = np.zeros(cam.size, dtype=bool)
        for start in range(0, cam.size, OCCLUSION_BATCH):
            sl = slice(start, start + OCCLUSION_BATCH)
            hidden[sl] = raycaster.occluded(P[pt[sl]], C[cam[sl]], tol_m=tol_m)
        keep = ~hidden
        cam, pt, uv, depth = cam[keep], pt[keep], uv[keep], depth[keep]
    return VisiblePairs(camera=cam, point=pt, uv_px=uv, depth_m=depth)


def _no_pairs() -> VisiblePairs:
    empty = np.zeros(0, dtype=np.intp)
    return VisiblePairs(empty, empty, np.zeros((0, 2)), np.zeros(0))
