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
from designer.core.projection import edge_pixels, project_pairwise
from designer.core.raycast import TerrainRaycaster
from designer.core.rotation import R_CV_FROM_PHOTO

#: rays per image edge used to bound a camera's footprint
BORDER_RAYS_PER_EDGE = 9
#: the footprint box is grown by this share of its size (bulging distorted edges)
BOX_GROWTH = 0.05
#: sight lines tested for occlusion in one vectorised batch
OCCLUSION_BATCH = 1 << 19
#: (camera, candidate point) pairs projected in one vectorised batch
PROJECTION_BATCH = 1 << 18
#: at most this many strips of points (:class:`_BoxIndex`)
MAX_STRIPS = 4096


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
    # (S, 3), the same for every camera
    rays_cv = interior.rays_cv(edge_pixels(interior, BORDER_RAYS_PER_EDGE))
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
    index = _BoxIndex(P[:, :2], boxes)
    W, H = interior.image_size_px
    # each camera's candidates: the points in its box (found strip by strip, _BoxIndex);
    # cameras are taken in batches of about PROJECTION_BATCH candidates, each batch
    # projected in one pass (each point into its own camera), in camera order and,
    # within a camera, in the order of the points' x
    run_cam, run_first, run_count = index.runs(boxes)
    per_camera = np.bincount(run_cam, weights=run_count, minlength=len(C)).astype(np.intp)
    ends = np.cumsum(per_camera)
    cams, pts, uvs, depths = [], [], [], []
    start = 0
    while start < len(C):
        stop = max(start + 1, int(np.searchsorted(
            ends, ends[start] - per_camera[start] + PROJECTION_BATCH, "right")))
        r0, r1 = np.searchsorted(run_cam, [start, stop])
        n_run = run_count[r0:r1]
        cam = np.repeat(run_cam[r0:r1], n_run)
        # each candidate's place in the index: its run's first + its rank in the run
        rank = np.arange(cam.size) - np.repeat(np.cumsum(n_run) - n_run, n_run)
        pt = index.order[np.repeat(run_first[r0:r1], n_run) + rank]
        box = boxes[cam]
        inside = ((P[pt, 0] >= box[:, 0]) & (P[pt, 0] <= box[:, 1])
                  & (P[pt, 1] >= box[:, 2]) & (P[pt, 1] <= box[:, 3]))
        cam, pt = cam[inside], pt[inside]
        start = stop
        if cam.size == 0:
            continue
        by_x = np.lexsort((index.x_rank[pt], cam))
        cam, pt = cam[by_x], pt[by_x]
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


class _BoxIndex:
    """Points (N, 2) sorted into strips along x and by y within each strip, so that the
    points inside a box (x0, x1, y0, y1) are a few runs of the sorted points (one per
    strip the box spans) instead of every point of its x range. Strips are about as wide
    as the typical box."""

    def __init__(self, xy: np.ndarray, boxes: np.ndarray) -> None:
        x, y = xy[:, 0], xy[:, 1]
        self.x_rank = np.empty(len(x), dtype=np.intp)
        self.x_rank[np.argsort(x, kind="stable")] = np.arange(len(x))
        self.x_min, x_span = float(x.min()), float(np.ptp(x))
        finite = np.isfinite(boxes).all(axis=1)
        width = float(np.median(boxes[finite, 1] - boxes[finite, 0])) if finite.any() else 0.0
        self.n_strips = int(np.clip(round(x_span / width), 1, MAX_STRIPS)) if width > 0 else 1
        self.width = max(x_span / self.n_strips, 1e-9)
        strip = self._strip(x)
        self.y_min, self.span = float(y.min()), float(np.ptp(y)) + 1.0
        self.order = np.lexsort((y, strip))
        # one sorted key: the strip, then y within it (y − y_min < span)
        self.key = strip[self.order] * self.span + (y[self.order] - self.y_min)

    def _strip(self, x) -> np.ndarray:
        with np.errstate(invalid="ignore"):
            s = np.floor((np.asarray(x, float) - self.x_min) / self.width)
        return np.clip(np.nan_to_num(s, nan=0.0), 0, self.n_strips - 1).astype(np.intp)

    def runs(self, boxes: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(camera, first, count) of the runs of ``order`` that hold every point inside
        each box (and a few outside: the caller tests the box), in camera order."""
        ok = ~np.isnan(boxes).any(axis=1)
        s0, s1 = self._strip(boxes[:, 0]), self._strip(boxes[:, 1])
        n = np.where(ok, s1 - s0 + 1, 0)
        cam = np.repeat(np.arange(len(boxes)), n)
        strip = np.repeat(s0, n) + np.arange(cam.size) - np.repeat(np.cumsum(n) - n, n)
        # the y range within the strip, kept inside it (an infinite box: the whole strip);
        # widened a little: the key's rounding never drops a point in the box
        pad = 1e-9 * self.span * (self.n_strips + 1)
        lo = np.clip(boxes[cam, 2] - self.y_min, -0.5, self.span - 0.5) - pad
        hi = np.clip(boxes[cam, 3] - self.y_min, -0.5, self.span - 0.5) + pad
        first = np.searchsorted(self.key, strip * self.span + lo, "left")
        last = np.searchsorted(self.key, strip * self.span + hi, "right")
        return cam, first, np.maximum(last - first, 0)


def _no_pairs() -> VisiblePairs:
    empty = np.zeros(0, dtype=np.intp)
    return VisiblePairs(empty, empty, np.zeros((0, 2)), np.zeros(0))
