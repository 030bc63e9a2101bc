"""Image pairs: which images are matched (designer reconstruct, and the pairs.txt of a
render's COLMAP ground truth).

Pairs come from where the cameras are believed to be in flight (GNSS/RTK positions and
the attitude the autopilot flew), as survey software uses image geotags:

* ``footprint`` — the images whose predicted ground footprints (image corners cast on
  a horizontal plane at the ground height) overlap; a repeating texture cannot then
  produce matches between images of different places;
* ``position`` — each image with its :data:`PAIR_NEIGHBOURS` nearest camera centres;
* ``exhaustive`` — every pair (cost grows with the square of the image count).

All geometry here is in the local frame (world − offset), so the float32 polygons of
OpenCV only see numbers of hundreds of metres.
"""

from __future__ import annotations

import numpy as np

#: neighbours each image is matched with by ``position`` pairing
PAIR_NEIGHBOURS = 12
#: footprints overlapping by at least this fraction of the smaller one are paired
MIN_FOOTPRINT_OVERLAP = 0.05


def footprint_xy(C_local: np.ndarray, R_cam_from_world: np.ndarray, K: tuple,
                 size_px: tuple[int, int], ground_z_local: float) -> np.ndarray:
    """(4, 2) ground points (local m) of the image corners on the plane Z = ground.

    ``R_cam_from_world`` is COLMAP's (CV camera frame); ``K`` = (fx, fy, cx, cy) px.
    Rays that miss the plane (at or above the horizon) are cut at 20 × the height.
    """
    fx, fy, cx, cy = K
    W, H = size_px
    corners = np.array([[0, 0], [W, 0], [W, H], [0, H]], float)
    rays_cam = np.column_stack([(corners[:, 0] - cx) / fx, (corners[:, 1] - cy) / fy,
                                np.ones(4)])
    rays = rays_cam @ np.asarray(R_cam_from_world)  # = (R^T · d) for each row
    height = max(float(C_local[2] - ground_z_local), 1.0)
    far = 20.0 * height
    out = []
    for d in rays:
        d = d / np.linalg.norm(d)
        s = (ground_z_local - C_local[2]) / d[2] if d[2] < -1e-6 else np.inf
        s = min(s, far) if s > 0 else far
        out.append(C_local[:2] + s * d[:2])
    return np.array(out)


def footprint_pairs(names: list[str], footprints: list[np.ndarray],
                    min_overlap: float = MIN_FOOTPRINT_OVERLAP,
                    k: int = PAIR_NEIGHBOURS) -> list[tuple[str, str]]:
    """Pairs of images whose footprints overlap by ``min_overlap`` of the smaller one,
    each image keeping only its ``k`` most overlapping partners (a pair stays if either
    image keeps it).

    Footprints rule out pairs of different places (a repeating texture makes COLMAP
    verify those); the cap keeps the matching cost near linear in the image count when
    footprints are large against the flight (a small area flown high: nearly every pair
    overlaps a little, and matching all of them costs as much as exhaustive matching).
    """
    import cv2

    polys = [cv2.convexHull(np.asarray(f, np.float32)) for f in footprints]
    areas = [float(cv2.contourArea(p)) for p in polys]
    lo = np.array([f.min(axis=0) for f in footprints])
    hi = np.array([f.max(axis=0) for f in footprints])
    n = len(names)
    share = np.zeros((n, n))
    for i in range(n):
        for j in range(i + 1, n):
            if np.any(lo[i] > hi[j]) or np.any(lo[j] > hi[i]):
                continue
            area, _ = cv2.intersectConvexConvex(polys[i], polys[j])
            share[i, j] = share[j, i] = area / max(min(areas[i], areas[j]), 1e-9)
    keep = set()
    for i in range(n):
        partners = [j for j in np.argsort(-share[i], kind="stable")[:k]
                    if share[i, j] >= min_overlap and j != i]
        keep.update((min(i, int(j)), max(i, int(j))) for j in partners)
    return [(names[i], names[j]) for i, j in sorted(keep)]


def neighbour_pairs(names: list[str], C: np.ndarray,
                    k: int = PAIR_NEIGHBOURS) -> list[tuple[str, str]]:
    """Each image with its ``k`` nearest cameras (by centre), no duplicates."""
    C = np.asarray(C, float)
    d2 = ((C[:, None, :] - C[None, :, :]) ** 2).sum(axis=-1)
    k = min(k, len(names) - 1)
    pairs = set()
    for i in range(len(names)):
        for j in np.argsort(d2[i])[1:k + 1]:
            pairs.add((min(i, int(j)), max(i, int(j))))
    return [(names[i], names[j]) for i, j in sorted(pairs)]


def exhaustive_pairs(names: list[str]) -> list[tuple[str, str]]:
    return [(a, b) for i, a in enumerate(names) for b in names[i + 1:]]
