"""Errors of flight files: one line naming the file, the place in it and the fix."""

from __future__ import annotations

import math

from designer.errors import DesignerError


class FlightFileError(DesignerError):
    """A flight file (plan, KML, WPML, geo.txt, CSV, image) that cannot be used."""


def fail(source: str, place: str, message: str, fix: str) -> FlightFileError:
    """``FlightFileError('SOURCE: PLACE: MESSAGE; FIX')`` to raise."""
    where = f"{source}: {place}" if place else source
    return FlightFileError(f"{where}: {message}; {fix}")


def number(value, source: str, place: str, what: str) -> float:
    """A finite float from a file value, or a FlightFileError naming it."""
    try:
        out = float(value)
    except (TypeError, ValueError):
        raise fail(source, place, f"{what} {value!r} is not a number",
                   "write a decimal number with '.' as separator") from None
    if not math.isfinite(out):
        raise fail(source, place, f"{what} {value!r} is not finite", "write a finite number")
    return out
