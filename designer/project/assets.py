"""Small companion files of the templates, made in code: a cube mesh, a seamless texture."""

from __future__ import annotations

import struct
import zlib

import numpy as np


def cube_obj_bytes() -> bytes:
    """A unit cube as Wavefront OBJ: x, y in [−0.5, 0.5], z in [0, 1] (base on the ground).

    Faces are counter-clockwise seen from outside, so normals point outwards.
    """
    vertices = [(x, y, z) for z in (0, 1) for y in (-0.5, 0.5) for x in (-0.5, 0.5)]
    faces = [(1, 3, 4, 2), (5, 6, 8, 7), (1, 2, 6, 5), (3, 7, 8, 4), (1, 5, 7, 3),
             (2, 4, 8, 6)]
    lines = ["# unit cube, base centred on the origin; metres after the placement scale"]
    lines += [f"v {x:g} {y:g} {z:g}" for x, y, z in vertices]
    lines += ["f " + " ".join(str(i) for i in face) for face in faces]
    return ("\n".join(lines) + "\n").encode("ascii")


def seamless_texture_png(size_px: int = 512, seed: int = 0) -> bytes:
    """A tileable grass-and-soil texture (RGB PNG), periodic by construction.

    Filtered white noise in the Fourier domain (1/f spectrum) wraps around exactly,
    so the tiles join without seams.
    """
    rng = np.random.default_rng(seed)
    f = np.fft.fftfreq(size_px)
    radius = np.hypot(f[:, None], f[None, :])
    radius[0, 0] = 1.0
    spectrum = np.fft.fft2(rng.standard_normal((size_px, size_px))) / radius**1.2
    spectrum[0, 0] = 0.0
    field = np.real(np.fft.ifft2(spectrum))
    field = (field - field.min()) / (np.ptp(field) or 1.0)
    fine = rng.uniform(0.85, 1.15, (size_px, size_px))
    soil = np.array([110.0, 85.0, 55.0])
    grass = np.array([70.0, 125.0, 45.0])
    rgb = (soil + (grass - soil) * field[..., None]) * fine[..., None]
    return png_bytes(np.clip(np.rint(rgb), 0, 255).astype(np.uint8))


def png_bytes(rgb: np.ndarray) -> bytes:
    """Encode an (H, W, 3) uint8 array as an 8-bit RGB PNG (no OpenCV needed)."""
    h, w, _ = rgb.shape
    raw = b"".join(b"\x00" + np.ascontiguousarray(rgb[i]).tobytes() for i in range(h))

    def chunk(tag: bytes, data: bytes) -> bytes:
        crc = zlib.crc32(tag + data) & 0xFFFFFFFF
        return struct.pack(">I", len(data)) + tag + data + struct.pack(">I", crc)

    header = struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header)
            + chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))
