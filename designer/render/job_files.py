"""Writing a render job's files beside job.json: PNG images and NumPy archives, each
atomically (a job folder never holds a half-written file)."""

from __future__ import annotations

from pathlib import Path

import cv2
import numpy as np

from designer.atomic import atomic_path


def write_png(path: Path, image: np.ndarray, fast: bool = False) -> None:
    """Write a PNG atomically; ``fast``: uncompressed (a large job image of noisy texels,
    which zlib shrinks by 10 % in three times the time). A ``.tif`` path is written as an
    uncompressed TIFF (the same pixels; 70 times faster than a PNG for a 8800² bake)."""
    if Path(path).suffix.lower() in (".tif", ".tiff"):
        params = [cv2.IMWRITE_TIFF_COMPRESSION, 1]
    else:
        params = [cv2.IMWRITE_PNG_COMPRESSION, 0] if fast else []
    with atomic_path(path) as tmp:
        if not cv2.imwrite(str(tmp), image, params):
            raise OSError(f"could not write {path}")


def save_npz(path: Path, **arrays) -> None:
    with atomic_path(path) as tmp, open(tmp, "wb") as f:
        np.savez(f, **arrays)
