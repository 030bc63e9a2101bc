"""Facade and roof textures of the buildings: seamless, seeded, detailed enough for SIFT.

Images are ``(H, W, 3)`` uint8 sRGB (RGB order) covering ``TILE_M`` × ``TILE_M`` metres
of wall or roof, repeated over it (:mod:`designer.scene.texture` conventions):

* facade — plaster with 1/f stains, weathering streaks and faint brick courses every
  0.25 m;
* roof — rows of 0.25 m × 0.25 m tiles, every other row offset by half a tile, each
  tile its own shade, with a dark gap under each row and moss / dirt blotches.

Both have contrast at every scale from a few texels to metres, so a detector finds
features on walls and roofs at the usual survey GSDs (1–5 cm).
"""

from __future__ import annotations

import numpy as np

from designer.scene.texture import _field, _octave_band, _radial_frequency, _white_spectrum

#: metres of wall or roof one texture image covers
TILE_M = 4.0
#: texture side (px): TILE_M / TEXTURE_PX = 7.8 mm per texel
TEXTURE_PX = 512
#: brick course and roof tile size (m); TEXTURE_PX * size / TILE_M must be a whole number
COURSE_M = 0.25


def _fields(rng: np.random.Generator, n: int):
    f = _radial_frequency(n, n)
    a, b = _white_spectrum(rng, n, n), _white_spectrum(rng, n, n)
    fractal = _field(a / np.sqrt(f * f + (4.0 / n) ** 2), n, n)
    blots = _field(b * _octave_band(f, 1.0 / 24.0), n, n)
    fine = _field(b * _octave_band(f, 1.0 / 4.0), n, n)
    return fractal, blots, fine


def _to_uint8(planes) -> np.ndarray:
    out = np.stack([np.clip(p * 255.0 + 0.5, 0, 255) for p in planes], axis=-1)
    return out.astype(np.uint8)


def facade_texture(seed: int = 0, size_px: int = TEXTURE_PX) -> np.ndarray:
    """Plaster facade (module docstring), ``(size_px, size_px, 3)`` uint8 sRGB."""
    rng = np.random.default_rng(seed)
    n = size_px
    fractal, blots, fine = _fields(rng, n)
    course = n * COURSE_M / TILE_M
    row = np.arange(n, dtype=np.float32)[:, None]
    joint = (np.mod(row, course) < 1.5).astype(np.float32)
    streak = _field(_white_spectrum(rng, n, n) * _octave_band(_radial_frequency(n, n),
                                                              1.0 / 48.0), n, n)
    streak = np.repeat(streak.mean(axis=0, keepdims=True), n, axis=0)  # vertical runs
    shade = np.exp(0.22 * fractal + 0.16 * np.tanh(blots) + 0.06 * fine + 0.08 * streak
                   - 0.12 * joint)
    base = (0.80, 0.72, 0.60)
    return _to_uint8([c * shade for c in base])


def roof_texture(seed: int = 0, size_px: int = TEXTURE_PX) -> np.ndarray:
    """Roof tiles (module docstring), ``(size_px, size_px, 3)`` uint8 sRGB; rows run
    along the image's u axis (along the eaves)."""
    rng = np.random.default_rng(seed + 1)
    n = size_px
    fractal, blots, fine = _fields(rng, n)
    tile = round(n * COURSE_M / TILE_M)
    rows = n // tile
    tone = rng.uniform(0.72, 1.25, size=(rows, rows)).astype(np.float32)
    hue = rng.uniform(-0.06, 0.06, size=(rows, rows)).astype(np.float32)
    v, u = np.mgrid[0:n, 0:n]
    r = v // tile
    c = ((u + (r % 2) * (tile // 2)) // tile) % rows
    t, h = tone[r, c], hue[r, c]
    within = (v % tile) / tile  # 0 at a row's top edge
    gap = (within > 0.9).astype(np.float32)  # the shadow under the next row's overlap
    curve = 1.0 + 0.10 * np.cos(2 * np.pi * ((u + (r % 2) * (tile // 2)) % tile) / tile)
    moss = np.clip(blots - 1.0, 0.0, None)
    shade = t * curve * np.exp(0.15 * fractal + 0.05 * fine) * (1.0 - 0.55 * gap)
    base = np.array([0.58, 0.27, 0.17], np.float32)
    planes = [(base[0] + h) * shade * (1 - 0.3 * moss), (base[1] + 0.3 * h) * shade
              * (1 + 0.25 * moss), base[2] * shade * (1 - 0.1 * moss)]
    return _to_uint8(planes)
