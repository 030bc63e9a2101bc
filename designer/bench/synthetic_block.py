"""What the benchmarks' synthetic blocks share (``designer bench doming``'s flat block,
the rolling-shutter block of designer.bench.synthetic_rolling): an image added to a
pycolmap reconstruction with noisy observations and a slightly wrong pose, as after SfM
and georeferencing, and the tracks of the points seen by three or more images.

The random draws are made in a fixed order (pixel noise, centre, attitude; then a
point's position per track), so a block is the same for the same seed."""

from __future__ import annotations

import numpy as np

#: how far the starting poses and points are off: centre and point σ (m), attitude σ (rad)
START_CENTRE_SIGMA_M = 0.05
START_ANGLE_SIGMA_RAD = 3e-4
START_POINT_SIGMA_M = 0.05


def add_noisy_image(rec, rng: np.random.Generator, image_id: int, name: str, uv: np.ndarray,
                    ids: np.ndarray, noise_px: float, C: np.ndarray, R_cam_from_world,
                    obs: dict[int, list]) -> None:
    """Add image ``image_id`` (camera 1) named ``name`` to ``rec``: the pixels ``uv``
    (N, 2) of the points ``ids`` (N,) with Gaussian noise of σ ``noise_px``, posed at the
    true centre ``C`` (3,) and CV-frame rotation ``R_cam_from_world`` (3, 3), each off by
    the START_* σ; each observation is appended to ``obs`` (point index → [(image id,
    point2D index)])."""
    import pycolmap

    uv = uv + rng.normal(0.0, noise_px, (len(ids), 2))
    image = pycolmap.Image(name=name, camera_id=1, image_id=image_id)
    image.points2D = pycolmap.Point2DList([pycolmap.Point2D(q) for q in uv])
    C0 = C + rng.normal(0.0, START_CENTRE_SIGMA_M, 3)
    R0 = pycolmap.Rotation3d(rng.normal(0.0, START_ANGLE_SIGMA_RAD, 3)).matrix() @ R_cam_from_world
    rec.add_image_with_trivial_frame(image, pycolmap.Rigid3d(pycolmap.Rotation3d(R0), -R0 @ C0))
    for j, p in enumerate(ids):
        obs.setdefault(int(p), []).append((image_id, j))


def add_tracks(rec, obs: dict, pts: np.ndarray, rng: np.random.Generator) -> dict:
    """Every point seen in 3 or more images (``obs``: point index → [(image id, point2D
    index)]) added to ``rec`` at its true position ``pts`` off by START_POINT_SIGMA_M
    (drawn from ``rng``); point id → true position."""
    import pycolmap

    true_pts = {}
    for p, track in obs.items():
        if len(track) < 3:
            continue
        t = pycolmap.Track()
        for image_id, j in track:
            t.add_element(image_id, j)
        true_pts[rec.add_point3D(pts[p] + rng.normal(0.0, START_POINT_SIGMA_M, 3), t)] = pts[p]
    return true_pts
