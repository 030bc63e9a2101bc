"""Stereo pairs for dense matching: choosing neighbours, rectifying, semi-global matching.

Frames: a *local* world frame (world − origin, metres, X east, Y north, Z up) and the
computer-vision camera frame (x right, y down, z forward). A :class:`View` holds
``cam_from_local`` as COLMAP does. Pixel coordinates are COLMAP's continuous ones (origin
at the top-left corner of the top-left pixel); array index (row i, column j) is the pixel
whose centre is (j + 0.5, i + 0.5). Everything here is float64 numpy or OpenCV's uint8 and
16-bit fixed-point disparity; depths are returned as float32 metres (local scale).

Rectification uses the known poses directly (Fusiello, Trucco & Verri 2000): both
cameras are rotated to one orientation whose x axis is the baseline, so the epipolar
lines are image rows for any baseline direction. (OpenCV's ``stereoRectify`` switches to
vertical disparities when the baseline is mostly along the image's y axis, which
``StereoSGBM`` cannot match; across-strip neighbours of a nadir survey are such pairs.)
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

#: rectified images larger than this factor times the original side are not matched
MAX_RECTIFIED_GROWTH = 2.5


@dataclass(frozen=True, eq=False)
class View:
    """One undistorted pinhole image: ``K`` (3, 3) in COLMAP pixels, ``R`` (3, 3) and
    ``t`` (3,) map local-frame points to the camera frame: x_cam = R · X + t."""

    name: str
    K: np.ndarray
    R: np.ndarray
    t: np.ndarray
    width_px: int
    height_px: int

    @property
    def C_local(self) -> np.ndarray:
        return -self.R.T @ self.t


@dataclass(frozen=True, eq=False)
class RectifiedPair:
    """A rectified pair: ``R_rect`` (3, 3) maps local-frame directions to the common
    rectified frame; the reference camera sits at the rectified origin and the other at
    +``baseline_m`` along x. ``K_ref`` / ``K_src`` differ only in cx; ``size_px`` is
    (width, height) of both rectified images."""

    R_rect: np.ndarray
    K_ref: np.ndarray
    K_src: np.ndarray
    baseline_m: float
    size_px: tuple[int, int]


#: a disparity search leaving fewer matchable columns of the rectified pair is skipped
MIN_MATCHED_COLUMNS = 16


def choose_pairs(views: list[View], shared_points: np.ndarray, depth_m: np.ndarray, *,
                 n_neighbours: int = 2, min_angle_deg: float = 3.0,
                 max_angle_deg: float = 40.0, min_shared: int = 20) -> list[list[int]]:
    """For each view, up to ``n_neighbours`` source views to match it with.

    ``shared_points`` (V, V) counts the sparse points two views both observe and
    ``depth_m`` (V,) is each view's median depth of its sparse points. A candidate must
    share ``min_shared`` points and see them under a baseline angle (baseline / depth)
    between ``min_angle_deg`` and ``max_angle_deg``. Candidates are scored by shared
    points times the sine of that angle (overlap and depth precision both count); after
    the best one, a candidate whose baseline direction in the image differs by less
    than 30° from one already chosen is taken only when no other is left, so a view is
    matched along different epipolar directions (along and across the flight strip).
    """
    n = len(views)
    C = np.array([v.C_local for v in views])
    chosen: list[list[int]] = []
    for i in range(n):
        baseline = np.linalg.norm(C - C[i], axis=1)
        angle = np.degrees(np.arctan2(baseline, max(float(depth_m[i]), 1e-9)))
        ok = (shared_points[i] >= min_shared) & (angle >= min_angle_deg) \
            & (angle <= max_angle_deg)
        ok[i] = False
        candidates = np.flatnonzero(ok)
        score = shared_points[i, candidates] * np.sin(np.radians(angle[candidates]))
        candidates = candidates[np.argsort(-score, kind="stable")]
        # baseline direction in the reference image plane, modulo 180°
        d_cam = (views[i].R @ (C[candidates] - C[i]).T).T
        direction = np.arctan2(d_cam[:, 1], d_cam[:, 0]) % np.pi
        picked: list[int] = []
        spare: list[int] = []
        for k in range(len(candidates)):
            if len(picked) == n_neighbours:
                break
            gap = [abs((direction[k] - direction[m] + np.pi / 2) % np.pi - np.pi / 2)
                   for m in picked]
            if all(g >= np.radians(30.0) for g in gap):
                picked.append(k)
            else:
                spare.append(k)
        picked += spare[:n_neighbours - len(picked)]
        chosen.append([int(candidates[k]) for k in picked])
    return chosen


def rectify(ref: View, src: View) -> RectifiedPair | None:
    """The common rectification of ``ref`` and ``src`` (None if it would blow up the
    images: strongly converging views)."""
    baseline = src.C_local - ref.C_local
    B = float(np.linalg.norm(baseline))
    if B <= 0:
        return None
    x = baseline / B
    z_old = ref.R[2] + src.R[2]
    y = np.cross(z_old, x)
    if np.linalg.norm(y) < 1e-6:
        return None  # baseline along the viewing direction: no stereo
    y /= np.linalg.norm(y)
    z = np.cross(x, y)
    R_rect = np.vstack([x, y, z])
    f = 0.5 * (ref.K[0, 0] + ref.K[1, 1] + src.K[0, 0] + src.K[1, 1]) / 2.0
    boxes = []
    for v in (ref, src):
        corners = np.array([[0, 0, 1], [v.width_px, 0, 1], [0, v.height_px, 1],
                            [v.width_px, v.height_px, 1]], dtype=float)
        rays = (R_rect @ v.R.T @ np.linalg.solve(v.K, corners.T)).T
        if (rays[:, 2] <= 0.1 * np.linalg.norm(rays, axis=1)).any():
            return None
        xy = f * rays[:, :2] / rays[:, 2:]
        boxes.append((xy.min(axis=0), xy.max(axis=0)))
    # rows both images cover; each image keeps its own column range (cx)
    y_lo = max(boxes[0][0][1], boxes[1][0][1])
    y_hi = min(boxes[0][1][1], boxes[1][1][1])
    width = int(np.ceil(max(b[1][0] - b[0][0] for b in boxes)))
    height = int(np.ceil(y_hi - y_lo))
    if height < 16 or width > MAX_RECTIFIED_GROWTH * max(ref.width_px, ref.height_px) \
            or height > MAX_RECTIFIED_GROWTH * max(ref.width_px, ref.height_px):
        return None
    Ks = []
    for lo, _ in boxes:
        Ks.append(np.array([[f, 0.0, -lo[0]], [0.0, f, -y_lo], [0.0, 0.0, 1.0]]))
    return RectifiedPair(R_rect, Ks[0], Ks[1], B, (width, height))


def warp_to_rectified(image: np.ndarray, view: View, K_rect: np.ndarray, R_rect: np.ndarray,
                      size_px: tuple[int, int]) -> np.ndarray:
    """``image`` (H, W[, 3]) of ``view`` resampled into the rectified frame (bilinear)."""
    import cv2

    H = view.K @ view.R @ R_rect.T @ np.linalg.inv(K_rect)  # rectified px -> original px
    # COLMAP pixels (corner origin) to OpenCV's (centre origin) on both sides
    shift = np.array([[1.0, 0, -0.5], [0, 1.0, -0.5], [0, 0, 1.0]])
    unshift = np.array([[1.0, 0, 0.5], [0, 1.0, 0.5], [0, 0, 1.0]])
    M = shift @ H @ unshift
    return cv2.warpPerspective(image, M, size_px, flags=cv2.INTER_LINEAR | cv2.WARP_INVERSE_MAP,
                               borderMode=cv2.BORDER_CONSTANT, borderValue=0)


def disparity_range(pair: RectifiedPair, points_local: np.ndarray, ref: View,
                    margin: float = 0.15) -> tuple[int, int] | None:
    """(minDisparity, numDisparities) covering the depths of ``points_local`` (N, 3),
    the sparse points the reference view sees (1-99 % quantiles of those within a
    factor of two of the median depth), widened by ``margin`` of their depth range on
    each side; None when there are too few points, or when the search leaves fewer than
    :data:`MIN_MATCHED_COLUMNS` columns of the rectified image to match."""
    if len(points_local) < 5:
        return None
    Z = (pair.R_rect @ (points_local - ref.C_local).T)[2]
    Z = Z[Z > 0]
    # badly conditioned sparse points (tiny triangulation angles) lie far off; a survey
    # image's depths stay within a factor of two of the median
    median = np.median(Z) if len(Z) else 0.0
    Z = Z[(Z > 0.5 * median) & (Z < 2.0 * median)]
    if len(Z) < 5:
        return None
    z_lo, z_hi = np.quantile(Z, [0.01, 0.99])
    pad = margin * (z_hi - z_lo) + 0.02 * z_lo
    z_lo, z_hi = max(z_lo - pad, 1e-3), z_hi + pad
    fB = pair.K_ref[0, 0] * pair.baseline_m
    dcx = pair.K_ref[0, 2] - pair.K_src[0, 2]
    d_min = int(np.floor(fB / z_hi + dcx)) - 2
    d_max = int(np.ceil(fB / z_lo + dcx)) + 2
    num = max(int(np.ceil((d_max - d_min) / 16.0)) * 16, 16)
    # SGBM matches only the columns x with x - d inside the image for every d searched:
    # a search wider than the rectified image (strongly converging oblique pairs) leaves
    # none, and OpenCV then fails allocating a negative size
    if pair.size_px[0] + min(d_min, 0) - max(d_min + num, 0) < MIN_MATCHED_COLUMNS:
        return None
    return d_min, num


def sgbm_depth(ref_gray: np.ndarray, src_gray: np.ndarray, ref: View, src: View,
               pair: RectifiedPair, disparities: tuple[int, int], *,
               block_size: int = 5) -> np.ndarray:
    """Depth map (H, W) float32 of the reference view, metres along its z axis, from
    semi-global matching of the rectified pair; 0 where there is no valid disparity.

    The disparity is sampled back at each reference pixel's rectified position
    (bilinear, only where all four neighbours are valid), so the depth map has the
    reference image's own geometry."""
    import cv2

    left = warp_to_rectified(ref_gray, ref, pair.K_ref, pair.R_rect, pair.size_px)
    right = warp_to_rectified(src_gray, src, pair.K_src, pair.R_rect, pair.size_px)
    min_disp, num_disp = disparities
    sgbm = cv2.StereoSGBM_create(
        minDisparity=min_disp, numDisparities=num_disp, blockSize=block_size,
        P1=8 * block_size**2, P2=32 * block_size**2, disp12MaxDiff=1,
        uniquenessRatio=10, speckleWindowSize=100, speckleRange=2,
        mode=cv2.STEREO_SGBM_MODE_SGBM_3WAY)
    disp16 = sgbm.compute(left, right)
    invalid = disp16 < min_disp * 16  # OpenCV marks unmatched pixels (min_disp - 1) * 16
    disp = disp16.astype(np.float32) / 16.0
    # Warp borders are no texture: drop matches whose block touches one in either image.
    kernel = np.ones((block_size, block_size), np.uint8)
    left_in = cv2.erode(warp_to_rectified(np.full(ref_gray.shape[:2], 255, np.uint8), ref,
                                          pair.K_ref, pair.R_rect, pair.size_px), kernel)
    right_in = cv2.erode(warp_to_rectified(np.full(src_gray.shape[:2], 255, np.uint8), src,
                                           pair.K_src, pair.R_rect, pair.size_px), kernel)
    rows, cols = np.indices(disp.shape)
    x_src = np.clip(np.rint(cols - disp).astype(np.int64), 0, disp.shape[1] - 1)
    invalid |= (left_in < 255) | (right_in[rows, x_src] < 255)
    disp[invalid] = 0.0

    h, w = ref_gray.shape[:2]
    jj, ii = np.meshgrid(np.arange(w) + 0.5, np.arange(h) + 0.5)
    pix = np.stack([jj.ravel(), ii.ravel(), np.ones(h * w)])
    rays_rect = pair.R_rect @ ref.R.T @ np.linalg.solve(ref.K, pix)  # ref z = 1
    uv = (pair.K_ref @ rays_rect)
    map_x = (uv[0] / uv[2] - 0.5).reshape(h, w).astype(np.float32)
    map_y = (uv[1] / uv[2] - 0.5).reshape(h, w).astype(np.float32)
    d = cv2.remap(disp, map_x, map_y, cv2.INTER_LINEAR, borderValue=0)
    bad = cv2.remap(invalid.astype(np.float32), map_x, map_y, cv2.INTER_LINEAR,
                    borderMode=cv2.BORDER_CONSTANT, borderValue=1.0)
    dcx = pair.K_ref[0, 2] - pair.K_src[0, 2]
    fB = pair.K_ref[0, 0] * pair.baseline_m
    denom = d - dcx
    ok = (bad == 0) & (denom > 1e-3)
    Z_rect = np.where(ok, fB / np.where(ok, denom, 1.0), 0.0)
    depth = Z_rect / rays_rect[2].reshape(h, w)  # rectified z to reference z
    return np.where(ok & (depth > 0), depth, 0.0).astype(np.float32)


def combine_depths(depths: list[np.ndarray], rel_tol: float = 0.01) -> np.ndarray:
    """One depth map from several of the same view: the mean where all valid ones agree
    within ``rel_tol`` of the depth, the single value where only one is valid, 0 where
    they disagree or none is valid."""
    stack = np.stack(depths).astype(np.float64)
    valid = stack > 0
    n = valid.sum(axis=0)
    total = np.where(valid, stack, 0.0).sum(axis=0)
    mean = np.where(n > 0, total / np.maximum(n, 1), 0.0)
    hi = np.where(valid, stack, -np.inf).max(axis=0)
    lo = np.where(valid, stack, np.inf).min(axis=0)
    agree = (n == 1) | ((n > 1) & (hi - lo <= rel_tol * mean))
    return np.where(agree & (n > 0), mean, 0.0).astype(np.float32)
