"""Seeded value noise fixed to the world: a point's value depends only on the seed, the
settings and the point, never on which other points are asked for or on an extent.

Octave k is value noise on a square lattice of spacing ``wavelength_m / 2^k``, shifted by
a random offset of its own (and, for terrain, turned by a random angle so no lattice axis
shows), with uniform lattice values in [-1, 1] from a SplitMix64 hash of (seed, stream,
octave, lattice index) and quintic interpolation between them. Coordinates are world
metres (X east, Y north) in float64: at a UTM northing of 10^7 m their spacing is 2·10^-9
m, far below any lattice spacing.

Used by the procedural terrain (:func:`designer.scene.terrain.procedural_terrain`) and the
texture variation (:mod:`designer.scene.texture_variation`), so that growing or cropping
a terrain, or rendering surroundings around it, keeps every hill and every colour patch
where it was.
"""

from __future__ import annotations

import math

import numpy as np

#: standard deviation of one octave of value noise (uniform lattice values in [-1, 1],
#: quintic interpolation), measured over 10^6 points
OCTAVE_RMS = 0.453


def octave_sum(seed: int, stream: int, wavelength_m: float, octaves: int,
               x_m: np.ndarray, y_m: np.ndarray, *, persistence: float = 0.5,
               rotate: bool = False) -> tuple[np.ndarray, float]:
    """Sum of ``octaves`` value-noise octaves at world (x, y) metres, and its expected
    standard deviation.

    Octave k has lattice spacing ``wavelength_m / 2^k`` and amplitude ``persistence^k``;
    ``rotate`` turns each octave's lattice by its own random angle. The sum has zero mean.
    """
    x = np.asarray(x_m, dtype=np.float64)
    y = np.asarray(y_m, dtype=np.float64)
    total = np.zeros(np.broadcast(x, y).shape)
    power = 0.0
    one = np.uint64(1)
    for k in range(octaves):
        spacing = wavelength_m / 2**k
        draw = np.random.default_rng([seed, stream, k])
        offset = draw.uniform(0.0, spacing, 2)
        if rotate:
            angle = draw.uniform(0.0, 2.0 * math.pi)
            c, s = math.cos(angle), math.sin(angle)
            # a fixed turn of world coordinates: float64 keeps ~1e-9 m at 10^7 m
            u, v = c * x - s * y, s * x + c * y
        else:
            u, v = x, y
        gx, gy = (u + offset[0]) / spacing, (v + offset[1]) / spacing
        ix, iy = np.floor(gx), np.floor(gy)
        fx, fy = _quintic(gx - ix), _quintic(gy - iy)
        key = _splitmix64(np.uint64(seed) * np.uint64(1 << 8) + np.uint64(16 * stream + k))
        ix, iy = ix.astype(np.int64).view(np.uint64), iy.astype(np.int64).view(np.uint64)

        def lattice(i, j, key=key):
            return _unit(_splitmix64(_splitmix64(key + i) + j))

        v00, v10 = lattice(ix, iy), lattice(ix + one, iy)
        v01, v11 = lattice(ix, iy + one), lattice(ix + one, iy + one)
        top = v00 + (v10 - v00) * fx
        bottom = v01 + (v11 - v01) * fx
        amplitude = persistence**k
        total += amplitude * (top + (bottom - top) * fy)
        power += amplitude * amplitude
    return total, OCTAVE_RMS * math.sqrt(power)


def _splitmix64(z):
    """SplitMix64 finaliser on uint64 (wrapping arithmetic)."""
    with np.errstate(over="ignore"):
        z = np.asarray(z, dtype=np.uint64) + np.uint64(0x9E3779B97F4A7C15)
        z = (z ^ (z >> np.uint64(30))) * np.uint64(0xBF58476D1CE4E5B9)
        z = (z ^ (z >> np.uint64(27))) * np.uint64(0x94D049BB133111EB)
        return z ^ (z >> np.uint64(31))


def _unit(h: np.ndarray) -> np.ndarray:
    """uint64 hash → float64 uniform in [-1, 1)."""
    return (h >> np.uint64(11)).astype(np.float64) * (2.0 / 2.0**53) - 1.0


def _quintic(t: np.ndarray) -> np.ndarray:
    return t * t * t * (t * (t * 6.0 - 15.0) + 10.0)
