"""A synthetic rolling-shutter block: a nadir grid flight as a pycolmap reconstruction.

For the benchmark of the rolling-shutter adjustment (``designer bench
rolling-adjustment``) and its tests: no render, no feature matching. Strips are flown
north, south, north, … at ``speed`` m/s, one photo a second; every photo's rows are
read out top to bottom in ``readout_s``; tie points are scattered over the block and
observed where a rolling-shutter camera sees them (the row's delay solved by fixed-point
iteration), with Gaussian pixel noise. The reconstruction starts from perturbed poses
(centres a few cm, attitudes a few 0.01°) and points (5 cm), as after SfM and
georeferencing; the true centres are returned as position priors would give them.
Local frame, metres.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from designer.bench.synthetic_block import add_noisy_image, add_tracks
from designer.sfm.rolling_adjustment import RollingShutterImage

#: CV-frame cam_from_world rotation of a nadir camera with the image top north
FLIP = np.diag([1.0, -1.0, -1.0])


@dataclass(frozen=True)
class BlockSpec:
    """The block: strips × photos per strip, points, camera (px), flight (m, m/s, s)."""

    strips: int = 3
    per_strip: int = 8
    points: int = 1500
    width_px: int = 400
    height_px: int = 300
    focal_px: float = 500.0
    height_m: float = 40.0
    strip_spacing_m: float = 20.0
    speed_m_s: float = 8.0
    readout_s: float = 0.02
    noise_px: float = 0.2


#: about the example survey's adjustment: 60 images, 20,000 points, 110,000 observations
EXAMPLE_SIZE = BlockSpec(strips=5, per_strip=12, points=20000, width_px=600, height_px=400)


def rolling_uv(X: np.ndarray, C: np.ndarray, vel: np.ndarray, spec: BlockSpec) -> np.ndarray:
    """Rolling-shutter pixels (N, 2) of points X (N, 3) in a nadir camera whose first row
    is exposed at centre C, moving at ``vel`` (m/s)."""
    v = np.full(len(X), spec.height_px / 2)
    for _ in range(30):
        delay = (v - 0.5) / spec.height_px * spec.readout_s
        p = (X - C - delay[:, None] * vel) @ FLIP.T
        u = spec.focal_px * p[:, 0] / p[:, 2] + spec.width_px / 2
        v = spec.focal_px * p[:, 1] / p[:, 2] + spec.height_px / 2
    return np.stack([u, v], axis=1)


def rolling_block(spec: BlockSpec = BlockSpec(), seed: int = 0):
    """(reconstruction, true points by point id, true centres by image name, shutters by
    image name) of the block ``spec`` (module docstring)."""
    import pycolmap

    rng = np.random.default_rng(seed)
    W, H, F = spec.width_px, spec.height_px, spec.focal_px
    half_y = (spec.per_strip - 1) / 2 * spec.speed_m_s
    foot_x = spec.height_m * W / F / 2
    foot_y = spec.height_m * H / F / 2
    x_max = (spec.strips - 1) * spec.strip_spacing_m
    pts = np.column_stack([rng.uniform(-foot_x, x_max + foot_x, spec.points),
                           rng.uniform(-half_y - foot_y, half_y + foot_y, spec.points),
                           rng.uniform(-3, 3, spec.points)])
    rec = pycolmap.Reconstruction()
    rec.add_camera_with_trivial_rig(pycolmap.Camera(
        model="FULL_OPENCV", width=W, height=H, params=[F, F, W / 2, H / 2] + [0.0] * 8,
        camera_id=1))
    obs: dict[int, list] = {}
    true_C, shutters = {}, {}
    k = 0
    for strip in range(spec.strips):
        sign = 1.0 if strip % 2 == 0 else -1.0
        for i in range(spec.per_strip):
            C = np.array([strip * spec.strip_spacing_m,
                          sign * (i - (spec.per_strip - 1) / 2) * spec.speed_m_s,
                          spec.height_m])
            vel = np.array([0.0, sign * spec.speed_m_s, 0.0])
            name = f"IMG_{k:04d}.png"
            uv = rolling_uv(pts, C, vel, spec)
            inside = (uv[:, 0] > 1) & (uv[:, 0] < W - 1) & (uv[:, 1] > 1) & (uv[:, 1] < H - 1)
            ids = np.flatnonzero(inside)
            add_noisy_image(rec, rng, k + 1, name, uv[ids], ids, spec.noise_px, C, FLIP, obs)
            true_C[name] = C
            # a turn of 10 s between strips: each strip is a leg of its own
            shutters[name] = RollingShutterImage(spec.readout_s, "top-to-bottom",
                                                 k * 1.0 + strip * 10.0)
            k += 1
    return rec, add_tracks(rec, obs, pts, rng), true_C, shutters


def copy_of(rec):
    """An independent copy of a reconstruction (each solver adjusts its own)."""
    import pycolmap

    return pycolmap.Reconstruction(rec)


def block_counts(rec) -> tuple[int, int, int]:
    """(registered images, points, observations) of a reconstruction."""
    return (rec.num_reg_images(), rec.num_points3D(),
            sum(pt.track.length() for pt in rec.points3D.values()))
