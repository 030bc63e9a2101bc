"""Shared helpers of the exporters: number formatting, name checks, atomic writes.

Numbers are written with :func:`fmt`, Python's ``repr`` of the float64: the shortest
decimal string that reads back to the identical double. That is exact at any
coordinate size (a UTM northing keeps ~1e-9 m), uses '.' as the decimal mark and
never a thousands separator.
"""

from __future__ import annotations

import math
import os
from collections.abc import Mapping
from pathlib import Path

import numpy as np

from designer.atomic import write_text_atomic
from designer.core.truth import check_name, check_unique  # noqa: F401 (used by exporters)
from designer.errors import InvalidDataError


class ExportError(InvalidDataError):
    """Data that cannot be written to an exchange format (message names the fix)."""


def fmt(value: float) -> str:
    """Exact decimal text of a finite float (shortest round-trip repr); '-0.0' → '0.0'."""
    x = float(value)
    if not math.isfinite(x):
        raise ExportError(f"cannot write the non-finite number {x!r}; every value must be finite")
    return repr(x + 0.0)  # + 0.0 turns -0.0 into 0.0


def check_crs(crs: object) -> str:
    """The CRS string as one non-empty line (the formats put it on a line of its own)."""
    if not isinstance(crs, str) or not crs.strip() or "\n" in crs or "\r" in crs:
        raise ExportError(f"crs {crs!r} must be a non-empty single line, e.g. 'EPSG:32632'")
    return crs.strip()


def check_offset(offset_world) -> np.ndarray:
    """An optional world offset (3,) in metres as float64, zeros if None."""
    if offset_world is None:
        return np.zeros(3)
    off = np.asarray(offset_world, dtype=np.float64)
    if off.shape != (3,) or not np.isfinite(off).all():
        raise ExportError(f"offset_world must be three finite numbers (E, N, H), got {off!r}")
    return off


def write_texts(files: Mapping[str | os.PathLike, str]) -> None:
    """Write each file atomically (temporary file beside it, then a rename).

    All text is produced before this is called, so invalid data never leaves a file
    behind; an I/O failure leaves each file either complete or untouched.
    """
    for path, text in files.items():
        path = Path(path)
        path.parent.mkdir(parents=True, exist_ok=True)
        write_text_atomic(path, text)
