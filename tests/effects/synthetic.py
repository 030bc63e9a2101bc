"""Synthetic, analytic "renders" for the effect tests: no Blender needed.

A pattern is a function of CV-frame viewing rays (N, 3) → values (N,). A render
is area-sampled like Cycles with a one-pixel box filter: pixel (i, j) covers
[i, i+1) × [j, j+1) in continuous coordinates; pixels whose corners and centre disagree
are supersampled ``ss`` × ``ss``, the others take that common value.
"""

from __future__ import annotations

import math

import cv2
import numpy as np

from designer.core.distortion import BrownConrady, FisheyeEquidistant
from designer.core.interior import InteriorOrientation

DARK, BRIGHT = 0.1, 0.9


def rays(interior: InteriorOrientation, u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """CV-frame rays (N, 3) through continuous pixel positions u, v (any shape)."""
    if interior.distortion is not None:
        return interior.rays_cv(np.column_stack([np.ravel(u), np.ravel(v)]))
    x = (u - interior.cx_px) / interior.fx_px
    y = (v - interior.cy_px) / interior.fy_px
    return np.stack([x, y, np.ones_like(x)], axis=-1).reshape(-1, 3)


def area_sampled(interior: InteriorOrientation, pattern, ss: int = 8) -> np.ndarray:
    """(H, W) float64 image of ``pattern`` seen by the camera ``interior``: a pinhole
    render, or with distortion the reference a perfect distorted render would give."""
    W, H = interior.image_size_px
    out = np.empty((H, W))
    for top in range(0, H, 256):
        rows = min(256, H - top)
        v, u = np.mgrid[top:top + rows + 1, 0:W + 1].astype(float)
        corners = pattern(rays(interior, u, v)).reshape(rows + 1, W + 1)
        centre = pattern(rays(interior, u[:-1, :-1] + 0.5, v[:-1, :-1] + 0.5)
                         ).reshape(rows, W)
        block = centre.copy()
        mixed = ((corners[:-1, :-1] != centre) | (corners[1:, :-1] != centre)
                 | (corners[:-1, 1:] != centre) | (corners[1:, 1:] != centre))
        jj, ii = np.nonzero(mixed)
        if jj.size:
            off = (np.arange(ss) + 0.5) / ss
            ou, ov = np.meshgrid(off, off)
            su = ii[:, None] + ou.ravel()[None, :]
            sv = top + jj[:, None] + ov.ravel()[None, :]
            block[jj, ii] = pattern(rays(interior, su, sv)).reshape(-1, ss * ss).mean(1)
        out[top:top + rows] = block
    return out


def _two_tone(parity: np.ndarray) -> np.ndarray:
    return np.where(parity % 2 == 0, DARK, BRIGHT)


class PlanarChecker:
    """A checkerboard of ``square_m`` squares on a plane through ``origin`` (CV camera
    frame, m), spanned by orthonormal ``e1``, ``e2``."""

    def __init__(self, origin, e1, e2, square_m):
        self.origin = np.asarray(origin, float)
        self.e1, self.e2 = np.asarray(e1, float), np.asarray(e2, float)
        self.normal = np.cross(self.e1, self.e2)
        self.square = square_m

    def __call__(self, rays):
        t = (self.origin @ self.normal) / (rays @ self.normal)
        d = rays * t[:, None] - self.origin
        s, q = d @ self.e1 / self.square, d @ self.e2 / self.square
        return _two_tone(np.floor(s).astype(np.int64) + np.floor(q).astype(np.int64))

    def corners(self, n):
        i, j = np.meshgrid(np.arange(-n, n + 1), np.arange(-n, n + 1))
        i, j = i.ravel()[:, None], j.ravel()[:, None]
        return self.origin + self.square * (i * self.e1 + j * self.e2)


class AngularChecker:
    """A checkerboard on the sphere of view directions, in azimuthal-equidistant
    coordinates (a, b) = θ·(cos φ, sin φ), rotated by ``angle_deg`` and shifted: squares
    stay the same size in an equidistant fisheye image right out to its edge."""

    def __init__(self, square_rad, angle_deg, shift):
        self.square = square_rad
        c, s = math.cos(math.radians(angle_deg)), math.sin(math.radians(angle_deg))
        self.rot = np.array([[c, -s], [s, c]])
        self.shift = np.asarray(shift, float)

    def _ab(self, rays):
        r = np.hypot(rays[:, 0], rays[:, 1])
        theta = np.arctan2(r, rays[:, 2])
        scale = np.divide(theta, r, out=np.ones_like(r), where=r > 0)
        return (rays[:, :2] * scale[:, None]) @ self.rot.T / self.square + self.shift

    def __call__(self, rays):
        ab = np.floor(self._ab(rays)).astype(np.int64)
        return _two_tone(ab[:, 0] + ab[:, 1])

    def corners(self, n):
        i, j = np.meshgrid(np.arange(-n, n + 1), np.arange(-n, n + 1))
        ab = (np.column_stack([i.ravel(), j.ravel()]) - self.shift) @ self.rot * self.square
        theta = np.hypot(ab[:, 0], ab[:, 1])
        scale = np.divide(np.sin(theta), theta, out=np.ones_like(theta), where=theta > 0)
        return np.column_stack([ab * scale[:, None], np.cos(theta)])


def project_opencv(interior: InteriorOrientation, points_cv: np.ndarray) -> np.ndarray:
    """OpenCV's projection of camera-frame points with K in designer's pixel convention,
    so the result is in designer's continuous coordinates (N, 2)."""
    K = interior.K_px
    lens = interior.distortion
    pts = np.ascontiguousarray(points_cv, dtype=np.float64)
    zero = np.zeros(3)
    if isinstance(lens, FisheyeEquidistant):
        D = np.array([lens.k1, lens.k2, lens.k3, lens.k4])
        uv, _ = cv2.fisheye.projectPoints(pts.reshape(1, -1, 3), zero, zero, K, D)
    else:
        lens = lens or BrownConrady()
        dist = np.array([lens.k1, lens.k2, lens.p1, lens.p2, lens.k3])
        uv, _ = cv2.projectPoints(pts.reshape(-1, 1, 3), zero, zero, K, dist)
    return uv.reshape(-1, 2)


def refine_corners(image, expected_px, neighbours_px, rng, win=5, border=12, min_square=14):
    """cornerSubPix from a start ±0.5 px off the expected corners (designer px).

    Only corners at least ``border`` px inside the image whose neighbouring corners are
    at least ``min_square`` px away are used. Returns (found_px, expected_px), both in
    designer's convention (detected OpenCV positions + 0.5).
    """
    H, W = image.shape
    ok = np.isfinite(expected_px).all(1) & np.isfinite(neighbours_px).all((1, 2))
    ok &= (expected_px[:, 0] > border) & (expected_px[:, 0] < W - border)
    ok &= (expected_px[:, 1] > border) & (expected_px[:, 1] < H - border)
    with np.errstate(invalid="ignore"):
        spacing = np.linalg.norm(neighbours_px - expected_px[:, None], axis=2).min(1)
    ok &= spacing >= min_square
    expected = expected_px[ok]
    start = expected - 0.5 + rng.uniform(-0.5, 0.5, expected.shape)
    criteria = (cv2.TERM_CRITERIA_COUNT | cv2.TERM_CRITERIA_EPS, 200, 1e-6)
    found = cv2.cornerSubPix(image.astype(np.float32), start.astype(np.float32).reshape(-1, 1, 2),
                             (win, win), (-1, -1), criteria)
    return found.reshape(-1, 2).astype(np.float64) + 0.5, expected
