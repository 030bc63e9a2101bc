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

from designer.core.compiled import cterrain

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
    x, y = np.broadcast_arrays(np.asarray(x_m, dtype=np.float64),
                               np.asarray(y_m, dtype=np.float64))
    shape = x.shape
    keys = np.empty(octaves, dtype=np.uint64)
    spacing, amplitude = np.empty(octaves), np.empty(octaves)
    offset, turn = np.zeros((octaves, 2)), np.zeros((octaves, 2))
    power = 0.0
    for k in range(octaves):
        spacing[k] = wavelength_m / 2**k
        draw = np.random.default_rng([seed, stream, k])
        offset[k] = draw.uniform(0.0, spacing[k], 2)
        if rotate:
            angle = draw.uniform(0.0, 2.0 * math.pi)
            # a fixed turn of world coordinates: float64 keeps ~1e-9 m at 10^7 m
            turn[k] = math.cos(angle), math.sin(angle)
        keys[k] = _splitmix64(np.uint64(seed) * np.uint64(1 << 8) + np.uint64(16 * stream + k))
        amplitude[k] = persistence**k
        power += amplitude[k] * amplitude[k]
    # per point, octave by octave (compiled, designer/core/csrc/terrain.c): (u, v) the point
    # turned, g = ((u, v) + offset) / spacing, the four lattice values around g (a hash of
    # the key and the lattice index, uniform in [-1, 1)) blended by the quintic of g's
    # fraction, times the amplitude
    total = np.zeros(shape)
    if total.size:
        cterrain().octave_sum(np.ascontiguousarray(x).ravel(), np.ascontiguousarray(y).ravel(),
                              total.size, keys, spacing, offset, turn, amplitude, octaves,
                              bool(rotate), total.reshape(-1))
    return total, OCTAVE_RMS * math.sqrt(power)


def _splitmix64(z):
    """SplitMix64 finaliser on uint64 (wrapping arithmetic)."""
    with np.errstate(over="ignore"):
        z = np.asarray(z, dtype=np.uint64) + np.uint64(0x9E3779B97F4A7C15)
        z = (z ^ (z >> np.uint64(30))) * np.uint64(0xBF58476D1CE4E5B9)
        z = (z ^ (z >> np.uint64(27))) * np.uint64(0x94D049BB133111EB)
        return z ^ (z >> np.uint64(31))
