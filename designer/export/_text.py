"""Shared helpers of the exporters: number formatting, name checks, atomic writes.

Numbers are written with :func:`fmt`, Python's ``repr`` of the float64: the shortest
decimal string that reads back to the identical double. That is exact at any
coordinate size (a UTM northing keeps ~1e-9 m), uses '.' as the decimal mark and
never a thousands separator.
"""

from __future__ import annotations

import math
import os
from collections.abc import Iterable, Mapping
from pathlib import Path

import numpy as np

from designer.atomic import write_text_atomic
from designer.errors import DesignerError


class ExportError(DesignerError, ValueError):
    """Data that cannot be written to an exchange format (message names the fix)."""


def fmt(value: float) -> str:
    """Exact decimal text of a finite float (shortest round-trip repr); '-0.0' → '0.0'."""
    x = float(value)
    if not math.isfinite(x):
        raise ExportError(f"cannot write the non-finite number {x!r}; every value must be finite")
    return repr(x + 0.0)  # + 0.0 turns -0.0 into 0.0


#: characters no identifier may contain: the formats split on whitespace (COLMAP, ODM)
#: or commas (CSV), and quotes would need escaping some readers do not undo
_FORBIDDEN = set(',"\'')


def check_name(name: object, what: str) -> str:
    """An image name or GCP id as a non-empty string without whitespace, commas or quotes."""
    if not isinstance(name, str) or not name:
        raise ExportError(f"{what} {name!r} must be a non-empty string")
    bad = sorted({c for c in name if c.isspace() or c in _FORBIDDEN})
    if bad:
        raise ExportError(
            f"{what} {name!r} contains {', '.join(repr(c) for c in bad)}; COLMAP and "
            f"OpenDroneMap split lines on whitespace and CSV on commas: rename it"
        )
    if name.startswith("#"):
        raise ExportError(f"{what} {name!r} starts with '#', which readers take as a comment")
    return name


def check_unique(names: Iterable[str], what: str) -> None:
    seen: set[str] = set()
    for n in names:
        if n in seen:
            raise ExportError(f"{what} {n!r} occurs more than once; names must be unique")
        seen.add(n)


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
