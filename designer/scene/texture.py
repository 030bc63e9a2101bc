"""Ground textures: seamless procedural grass/soil, validation checkerboards, image files.

Images are numpy arrays ``(H, W, 3)`` uint8 in sRGB, channels **RGB** (OpenCV's BGR is
converted at the file boundary), row 0 at the top. Texture coordinates follow
:mod:`designer.scene.mesh`: (u, v) = (0, 0) is the bottom-left of the image, u east,
v north, so a texture on the terrain reads as a north-up map.

Procedural textures are synthesised on a periodic domain (spectrally filtered noise
through the FFT), so a texture tiles without seams: the step across a tile border is
statistically the same as between any two neighbouring texels. Their luminance has a
1/f amplitude spectrum — the same contrast per octave — plus blob layers at fixed texel
scales, so SIFT-like detectors find features at every scale down to a few texels.
"""

from __future__ import annotations

import os
from pathlib import Path

import cv2
import numpy as np
import scipy.fft

from designer.atomic import write_bytes_atomic
from designer.errors import DesignerError

TEXTURE_KINDS = ("grass", "soil")


def texel_ground_size_m(
    texture_size_px: int | tuple[int, int],
    terrain_extent_m: tuple[float, float, float, float],
    tiles: tuple[float, float] = (1, 1),
) -> tuple[float, float]:
    """Ground size of one texel (sx east, sy north) in metres.

    ``texture_size_px`` is ``(width_px, height_px)`` or one number for a square texture;
    ``terrain_extent_m`` is ``(x_min, x_max, y_min, y_max)`` (``Heightfield.extent_m``);
    the texture repeats ``tiles = (nx, ny)`` times across the extent (east, north).
    Keep the texel at or below half the ground sample distance of the survey, or the
    renderer blurs the texture below what the camera resolves.
    """
    width_px, height_px = _size_wh(texture_size_px)
    x_min, x_max, y_min, y_max = (float(c) for c in terrain_extent_m)
    nx, ny = float(tiles[0]), float(tiles[1])
    if not (x_max > x_min and y_max > y_min):
        raise DesignerError(f"terrain extent {terrain_extent_m} is empty; need x_max > x_min "
                            "and y_max > y_min")
    if not (nx > 0 and ny > 0):
        raise DesignerError(f"texture tiles must be > 0, got {tiles}")
    return (x_max - x_min) / (nx * width_px), (y_max - y_min) / (ny * height_px)


def _size_wh(size_px: int | tuple[int, int]) -> tuple[int, int]:
    w, h = (size_px, size_px) if np.ndim(size_px) == 0 else size_px
    if int(w) != w or int(h) != h or w < 1 or h < 1:
        raise DesignerError(f"texture size must be whole pixels >= 1, got {size_px}")
    return int(w), int(h)


# --------------------------------------------------------------------------- procedural
def procedural_texture(
    size_px: int | tuple[int, int], seed: int, kind: str = "grass"
) -> np.ndarray:
    """A seamless, seeded ground texture ``(H, W, 3)`` uint8 sRGB (RGB order).

    ``size_px`` is ``(width_px, height_px)`` or one number (at least 16; powers of two
    are fastest). ``kind`` is ``"grass"`` or ``"soil"``. Colour patches span about a
    quarter of the texture; luminance detail is 1/f noise from that scale down to one
    texel, plus blob layers at wavelengths of 12 and 4 texels (grass tufts with soil
    between them, or soil clods and pebbles). The same seed, size and kind give the same
    image (numpy's PCG64 stream; FFT rounding can move a channel by one level across
    platforms).
    """
    if kind not in TEXTURE_KINDS:
        raise DesignerError(f"unknown texture kind '{kind}'; use one of {', '.join(TEXTURE_KINDS)}")
    width, height = _size_wh(size_px)
    if min(width, height) < 16:
        raise DesignerError(f"procedural texture must be at least 16 x 16 px, got {size_px}")
    rng = np.random.default_rng(seed)
    f = _radial_frequency(height, width)
    white_a = _white_spectrum(rng, height, width)
    white_b = _white_spectrum(rng, height, width)
    grain = rng.standard_normal((height, width), dtype=np.float32)

    f_patch = 4.0 / max(width, height)  # patches ~ a quarter of the texture
    fractal = _field(white_a / np.sqrt(f * f + f_patch * f_patch), height, width)
    patches = _field(white_a * np.exp(-(f / f_patch) ** 2), height, width)
    clumps = _field(white_b * _octave_band(f, 1.0 / 12.0), height, width)
    specks = _field(white_b * _octave_band(f, 1.0 / 4.0), height, width)

    compose = _grass if kind == "grass" else _soil
    out = np.empty((height, width, 3), dtype=np.uint8)
    for channel, value in enumerate(compose(fractal, patches, clumps, specks, grain)):
        # Channel by channel in float32: the (H, W, 3) float intermediate would cost
        # more time in memory traffic than the FFTs.
        out[:, :, channel] = np.clip(value * np.float32(255.0) + np.float32(0.5), 0, 255)
    return out


def _radial_frequency(height: int, width: int) -> np.ndarray:
    """|f| in cycles per texel on the rfft2 grid, float32 (height, width // 2 + 1)."""
    fy = np.fft.fftfreq(height).astype(np.float32)[:, None]
    fx = np.fft.rfftfreq(width).astype(np.float32)[None, :]
    return np.sqrt(fx * fx + fy * fy)


def _white_spectrum(rng: np.random.Generator, height: int, width: int) -> np.ndarray:
    shape = (height, width // 2 + 1)
    spec = np.empty(shape, dtype=np.complex64)
    spec.real = rng.standard_normal(shape, dtype=np.float32)
    spec.imag = rng.standard_normal(shape, dtype=np.float32)
    spec[0, 0] = 0.0  # zero mean
    return spec


def _octave_band(f: np.ndarray, f_centre: float) -> np.ndarray:
    """Log-Gaussian band-pass, one octave wide (standard deviation), centred on f_centre."""
    with np.errstate(divide="ignore"):
        octaves = np.log2(np.where(f > 0, f, 1e-12) / f_centre)
    return np.exp(-0.5 * octaves * octaves).astype(np.float32)


def _field(spectrum: np.ndarray, height: int, width: int) -> np.ndarray:
    """Periodic real field of zero mean and unit standard deviation (float32)."""
    field = scipy.fft.irfft2(spectrum, s=(height, width), workers=-1)
    # The mean is zero (no DC term), so the RMS of a regular subsample estimates the
    # standard deviation; the full-size reduction would cost as much as the FFT.
    rms = float(np.sqrt(np.mean(np.square(field[::3, ::3], dtype=np.float64))))
    return field / np.float32(rms) if rms > 0 else field


def _smoothstep(x: np.ndarray, lo: float, hi: float) -> np.ndarray:
    t = np.clip((x - np.float32(lo)) * np.float32(1.0 / (hi - lo)), 0.0, 1.0)
    return t * t * (np.float32(3.0) - np.float32(2.0) * t)


def _lerp(a: float, b: float, t: np.ndarray) -> np.ndarray:
    return np.float32(a) + np.float32(b - a) * t


def _grass(fractal, patches, clumps, specks, grain):
    """R, G, B planes (float32, 0..1) of grass: lush/dry patches, soil between tufts."""
    lush, dry, soil = (0.20, 0.34, 0.09), (0.46, 0.47, 0.20), (0.30, 0.23, 0.15)
    t_dry = _smoothstep(patches, -1.2, 1.8)
    # Bare soil shows between the tufts where the clump field is low.
    t_soil = np.float32(0.8) * _smoothstep(-clumps, 0.9, 1.6)
    shade = np.exp(np.float32(0.30) * fractal + np.float32(0.22) * np.tanh(np.float32(1.5) * clumps)
                   + np.float32(0.12) * specks + np.float32(0.10) * grain)
    for c in range(3):
        base = _lerp(lush[c], dry[c], t_dry)
        yield (base + (np.float32(soil[c]) - base) * t_soil) * shade


def _soil(fractal, patches, clumps, specks, grain):
    """R, G, B planes (float32, 0..1) of bare soil with light pebbles."""
    dark, light, stone = (0.34, 0.26, 0.18), (0.50, 0.40, 0.28), (0.64, 0.61, 0.56)
    t_light = _smoothstep(patches, -1.5, 1.5)
    shade = np.exp(np.float32(0.32) * fractal + np.float32(0.20) * np.tanh(np.float32(1.5) * clumps)
                   + np.float32(0.10) * grain)
    # Pebbles: the peaks of the small-scale field, lit from the north-west.
    t_pebble = _smoothstep(specks + np.float32(0.4) * clumps, 1.3, 1.7)
    relief = np.roll(specks, (1, 1), axis=(0, 1)) - specks
    stone_shade = np.exp(np.float32(0.25) * relief + np.float32(0.05) * grain)
    for c in range(3):
        ground = _lerp(dark[c], light[c], t_light) * shade
        yield ground + (np.float32(stone[c]) * stone_shade - ground) * t_pebble


def checkerboard_texture(
    n_squares: int | tuple[int, int], texels_per_square: int
) -> np.ndarray:
    """An exact black (0) / white (255) checkerboard ``(H, W, 3)`` uint8.

    ``n_squares`` is ``(columns, rows)`` or one number; the top-left square is black and
    square (row r, column c) is white when r + c is odd. It tiles seamlessly when both
    counts are even.
    """
    cols, rows = _size_wh(n_squares)
    t = int(texels_per_square)
    if t != texels_per_square or t < 1:
        raise DesignerError(f"texels_per_square must be a whole number >= 1, got "
                            f"{texels_per_square}")
    r = np.arange(rows * t) // t
    c = np.arange(cols * t) // t
    white = ((r[:, None] + c[None, :]) % 2).astype(np.uint8) * 255
    return np.repeat(white[:, :, None], 3, axis=2)


# --------------------------------------------------------------------------- files
def load_texture(path: str | os.PathLike) -> np.ndarray:
    """Read an image file as ``(H, W, 3)`` uint8 RGB.

    Grey images are replicated to three channels, an alpha channel is dropped and
    16-bit images are scaled to 8 bits (÷ 257). Missing, empty or unreadable files raise
    :class:`DesignerError` naming the file.
    """
    path = Path(path)
    if not path.is_file():
        raise DesignerError(f"texture file {path} does not exist; check the texture path")
    data = np.fromfile(path, dtype=np.uint8)  # imdecode copes with non-ASCII paths
    if data.size == 0:
        raise DesignerError(f"texture file {path} is empty; export the texture again")
    img = cv2.imdecode(data, cv2.IMREAD_UNCHANGED)
    if img is None or img.size == 0:
        raise DesignerError(f"texture file {path} is not an image OpenCV can read; "
                            "use PNG, JPEG or TIFF")
    if img.dtype == np.uint16:
        img = ((img.astype(np.uint32) + 128) // 257).astype(np.uint8)
    elif img.dtype != np.uint8:
        raise DesignerError(f"texture file {path} has {img.dtype} pixels; "
                            "save it as 8- or 16-bit")
    if img.ndim == 2:
        return np.ascontiguousarray(np.repeat(img[:, :, None], 3, axis=2))
    if img.shape[2] == 1:
        return np.ascontiguousarray(np.repeat(img, 3, axis=2))
    return np.ascontiguousarray(cv2.cvtColor(img[:, :, :3], cv2.COLOR_BGR2RGB))


def write_texture_png(img: np.ndarray, path: str | os.PathLike) -> None:
    """Write an ``(H, W, 3)`` RGB or ``(H, W)`` grey uint8 image as PNG, atomically."""
    img = np.asarray(img)
    if img.dtype != np.uint8 or not (img.ndim == 2 or (img.ndim == 3 and img.shape[2] == 3)):
        raise DesignerError(f"texture must be (H, W, 3) or (H, W) uint8, got {img.shape} "
                            f"{img.dtype}")
    bgr = img if img.ndim == 2 else cv2.cvtColor(img, cv2.COLOR_RGB2BGR)
    ok, buf = cv2.imencode(".png", bgr)
    if not ok:
        raise DesignerError(f"could not encode the texture for {path} as PNG")
    write_bytes_atomic(path, buf.tobytes())
