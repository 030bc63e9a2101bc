"""Drifting cloud shadows: a seeded field of clouds over the ground, moved by the wind.

The field f(x, y) is three octaves of value noise (lattice cells of ``size_m``,
``size_m / 2`` and ``size_m / 4`` with weights 1, 1/2, 1/4) with lattice values drawn
from a hash of the integer cell and the seed: deterministic, defined everywhere, not
periodic. The ground is in shadow where f exceeds the threshold that leaves the share
``cover`` of a large area (64 × 64 cells) in shadow. The hard mask (anti-aliased with
2 × 2 samples per texel) is blurred by a Gaussian whose 10 %–90 % edge width is
``softness_m``; the attenuation of the direct sun is ``1 − depth · shadow``.

At time t the field is sampled at (x, y) − w · t, w the wind velocity (towards
``wind_direction_deg``, clockwise from grid north): the shadows drift with the wind.
Coordinates are local metres (world − project origin), X east, Y north. The clouds'
height is not modelled: a shadow lies where its cloud's field says, whatever the sun's
direction.
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np

#: 10 %–90 % width of a Gaussian-blurred step = 2 · 1.2816 σ
EDGE_WIDTH_PER_SIGMA = 2.0 * 1.2815516
OCTAVES = ((1.0, 1.0), (0.5, 0.5), (0.25, 0.25))  # (cell size / size_m, weight)


def wind_shift_m(clouds, time_s: float) -> tuple[float, float]:
    """(east, north) distance in metres the shadows have drifted after ``time_s``."""
    az = math.radians(clouds.wind_direction_deg)
    d = clouds.wind_speed_m_s * time_s
    return d * math.sin(az), d * math.cos(az)


def _lattice(i: np.ndarray, j: np.ndarray, seed: int, octave: int) -> np.ndarray:
    """Uniform [0, 1) values of integer lattice points (splitmix64 of cell and seed)."""
    with np.errstate(over="ignore"):
        h = (i.astype(np.int64).view(np.uint64) * np.uint64(0x9E3779B97F4A7C15)
             ^ j.astype(np.int64).view(np.uint64) * np.uint64(0xC2B2AE3D27D4EB4F)
             ^ np.uint64((seed * 1000003 + octave * 7919) & 0xFFFFFFFFFFFFFFFF))
        h = (h ^ (h >> np.uint64(30))) * np.uint64(0xBF58476D1CE4E5B9)
        h = (h ^ (h >> np.uint64(27))) * np.uint64(0x94D049BB133111EB)
        h = h ^ (h >> np.uint64(31))
    return (h >> np.uint64(11)).astype(np.float64) / float(1 << 53)


def cloud_field(x_m: np.ndarray, y_m: np.ndarray, size_m: float, seed: int) -> np.ndarray:
    """The field f at local points (any shape), roughly in [0, 1]."""
    x = np.asarray(x_m, np.float64)
    y = np.asarray(y_m, np.float64)
    out = np.zeros(np.broadcast(x, y).shape)
    for octave, (scale, weight) in enumerate(OCTAVES):
        cell = size_m * scale
        u, v = x / cell, y / cell
        i0, j0 = np.floor(u), np.floor(v)
        fu, fv = u - i0, v - j0
        su, sv = fu * fu * (3 - 2 * fu), fv * fv * (3 - 2 * fv)
        i0, j0 = i0.astype(np.int64), j0.astype(np.int64)
        a = _lattice(i0, j0, seed, octave)
        b = _lattice(i0 + 1, j0, seed, octave)
        c = _lattice(i0, j0 + 1, seed, octave)
        d = _lattice(i0 + 1, j0 + 1, seed, octave)
        out += weight * ((a * (1 - su) + b * su) * (1 - sv) + (c * (1 - su) + d * su) * sv)
    return out / sum(w for _, w in OCTAVES)


@lru_cache(maxsize=64)
def cover_threshold(cover: float, seed: int) -> float:
    """Field value above which a share ``cover`` of a 64 × 64-cell area is shadowed."""
    if cover <= 0:
        return math.inf
    if cover >= 1:
        return -math.inf
    n = 512
    g = (np.arange(n) + 0.5) * (64.0 / n)
    X, Y = np.meshgrid(g, g)
    f = cloud_field(X, Y, 1.0, seed)
    return float(np.quantile(f, 1.0 - cover))


def shadow_share(clouds, x_m: np.ndarray, y_m: np.ndarray, time_s: float) -> np.ndarray:
    """Cloud shadow share (H, W) in [0, 1] on the regular grid of texel centres
    ``x_m`` (W,) × ``y_m`` (H,) (local metres, equal steps), with soft edges."""
    import cv2

    x_m, y_m = np.asarray(x_m, np.float64), np.asarray(y_m, np.float64)
    dx = abs(x_m[1] - x_m[0]) if len(x_m) > 1 else 1.0
    dy = abs(y_m[1] - y_m[0]) if len(y_m) > 1 else 1.0
    sigma_m = clouds.softness_m / EDGE_WIDTH_PER_SIGMA
    pad_x = math.ceil(4 * sigma_m / dx) + 1 if sigma_m > 0 else 0
    pad_y = math.ceil(4 * sigma_m / dy) + 1 if sigma_m > 0 else 0
    sx = np.sign(x_m[-1] - x_m[0]) or 1.0
    sy = np.sign(y_m[-1] - y_m[0]) or 1.0
    xs = np.concatenate([x_m[0] - sx * dx * np.arange(pad_x, 0, -1), x_m,
                         x_m[-1] + sx * dx * np.arange(1, pad_x + 1)])
    ys = np.concatenate([y_m[0] - sy * dy * np.arange(pad_y, 0, -1), y_m,
                         y_m[-1] + sy * dy * np.arange(1, pad_y + 1)])
    east, north = wind_shift_m(clouds, time_s)
    threshold = cover_threshold(float(clouds.cover), int(clouds.seed))
    mask = np.zeros((len(ys), len(xs)))
    for ox in (-0.25, 0.25):  # 2 × 2 samples per texel: edges to a quarter texel
        for oy in (-0.25, 0.25):
            X, Y = np.meshgrid(xs + ox * dx - east, ys + oy * dy - north)
            mask += cloud_field(X, Y, clouds.size_m, clouds.seed) > threshold
    mask = (mask / 4.0).astype(np.float32)
    if sigma_m > 0:
        mask = cv2.GaussianBlur(mask, (2 * pad_x + 1, 2 * pad_y + 1), sigmaX=sigma_m / dx,
                                sigmaY=sigma_m / dy, borderType=cv2.BORDER_REPLICATE)
    return mask[pad_y:pad_y + len(y_m), pad_x:pad_x + len(x_m)]


def attenuation(clouds, x_m, y_m, time_s: float) -> np.ndarray:
    """Factor (H, W) on the direct sun, ``1 − depth · shadow`` in [1 − depth, 1]."""
    return 1.0 - clouds.depth * shadow_share(clouds, x_m, y_m, time_s)
