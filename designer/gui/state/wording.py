"""Messages as the window's user reads them (Qt-free).

Errors raised by the library name its parameters (``size_x_m``) and print numbers the
way Python does (``5.40595e+06``); the window shows the field as the panel labels it
and numbers in fixed point with sensible decimals.
"""

from __future__ import annotations

import re

#: library parameter names → what the panels call them
FIELD_NAMES = {
    "size_x_m": "terrain width (X)",
    "size_y_m": "terrain length (Y)",
    "spacing_m": "grid spacing",
    "grid_spacing_m": "grid spacing",
    "min_spacing_m": "min spacing",
    "margin_m": "margin",
    "gsd_m": "ground sample distance",
    "altitude_agl_m": "height above ground",
    "front_overlap": "front overlap",
    "side_overlap": "side overlap",
    "grid_angle_deg": "line azimuth",
    "tilt_deg": "forward tilt",
    "n_check": "number of check points",
    "cell_m": "coverage grid cell",
    "focal_length_mm": "focal length",
    "sensor_width_mm": "sensor width",
    "sensor_height_mm": "sensor height",
    "image_width_px": "image width",
    "image_height_px": "image height",
    "texel_size_m": "texel size",
    "size_m": "target size",
}
#: directions in the project file's terms (as designer validate words them for someone
#: editing the XML) → the panel and control that do it in the window
_TIME_LINE_ON = ("switch on the time line in the Flight panel "
                 "(“the photos have times”)")
PANEL_DIRECTIONS = (
    (re.compile(r"the trajectory has no <time-line>(?: to move the camera along)?; add a "
                r"<time-line> to <trajectory> or set readout-s 0"),
     f"the flight has no time line to move the camera along; {_TIME_LINE_ON}, or set the "
     "readout to 0 s in the Camera panel"),
    (re.compile(r"the trajectory has no <time-line>; add one or give the sun as <sun> or "
                r"<sun-position>"),
     f"the flight has no time line; {_TIME_LINE_ON}, or give the sun by its direction or "
     "a moment and place in the Lighting panel"),
    (re.compile(r"the trajectory has no <time-line>; add one or remove <moving-objects>"),
     f"the flight has no time line; {_TIME_LINE_ON}, or remove the moving objects in the "
     "Moving objects panel"),
    (re.compile(r"the trajectory has no <time-line>; add one or write metadata none"),
     f"the flight has no time line; {_TIME_LINE_ON}"),
    (re.compile(r"the trajectory has no <time-line>; add one or remove time-s"),
     f"the flight has no time line; {_TIME_LINE_ON}"),
    (re.compile(r"sun-over-time needs a <time-line> with a UTC takeoff-utc, e\.g\. \S+"),
     f"the sun follows the flight's time line, which is off; {_TIME_LINE_ON}"),
    (re.compile(r"no photos: add <exterior-orientations> with <photo> elements or a "
                r"<flight-plan>"),
     "no photos: add a grid flight in the Flight panel, or import a flight (File menu)"),
    (re.compile(r'declare <surroundings mode="auto"/> in <terrain> or enlarge the terrain'),
     "choose surroundings “auto” in the Terrain panel, or enlarge the terrain"),
    (re.compile(r'mode="auto" continues a height-field terrain \(flat, procedural or DEM\); '
                r'a mesh terrain cannot be continued: use mode="none" or a DEM'),
     "surroundings “auto” continue a height-field terrain (flat, procedural or DEM); a "
     "mesh terrain cannot be continued: choose surroundings “none” in the Terrain panel, "
     "or import the terrain as a DEM"),
)
_UNITS = {"m": "m", "mm": "mm", "px": "px", "deg": "°", "percent": "%"}
_IDENT = re.compile(r"(?<![\w./\\-])[a-z][a-z0-9]*(?:_[a-z0-9]+)+(?![\w./\\-])")
_SCI = re.compile(r"(?<![\w.])[-+]?\d+(?:\.\d+)?[eE][-+]?\d+\b")
_LONG = re.compile(r"(?<![\w.])([-+]?\d+\.\d{4,})\b")


def fixed(value: float, decimals: int | None = None) -> str:
    """A number in fixed point: 3 decimals (mm) for metre-sized values and up, more
    significant digits for small ones; trailing zeros dropped."""
    if decimals is None:
        a = abs(value)
        decimals = 3 if a >= 1 or a == 0 else min(9, 3 - int(f"{a:e}".split("e")[1]))
    text = f"{value:.{decimals}f}"
    if "." in text:
        text = text.rstrip("0").rstrip(".")
    return "0" if text in ("-0", "") else text


def field_name(ident: str) -> str:
    """``size_x_m`` → ``terrain width (X)``; an unknown ``foo_bar_m`` → ``foo bar (m)``."""
    if ident in FIELD_NAMES:
        return FIELD_NAMES[ident]
    words = ident.split("_")
    unit = _UNITS.get(words[-1]) if len(words) > 1 else None
    if unit is not None:
        words = words[:-1]
    return " ".join(words) + (f" ({unit})" if unit else "")


def _maybe_field(ident: str) -> str:
    """Only names of parameters (known, or ending in a unit) are renamed."""
    if ident in FIELD_NAMES or ident.rsplit("_", 1)[-1] in _UNITS:
        return field_name(ident)
    return ident


def humanize(message: str) -> str:
    """A library message with field names as labelled and numbers in fixed point."""
    message = _IDENT.sub(lambda mt: _maybe_field(mt.group(0)), message)
    message = _SCI.sub(lambda mt: fixed(float(mt.group(0))), message)
    return _LONG.sub(lambda mt: fixed(float(mt.group(1))), message)


def panel_directions(message: str) -> str:
    """A library message with its directions for editing the project file replaced by
    the panel and control that do it in the window (:data:`PANEL_DIRECTIONS`)."""
    for pattern, direction in PANEL_DIRECTIONS:
        message = pattern.sub(direction, message)
    return message


def duration(seconds: float) -> str:
    """A time as a person reads it: '0.4 s', '12 s', '3.6 min', '2.4 h'. Short times are
    given in seconds (one decimal below 10 s), never as '0.0 min' or '0 s'."""
    import math

    if not math.isfinite(seconds):
        return "–"
    if seconds < 0.05:
        return "< 0.1 s"
    if seconds < 9.95:
        return f"{seconds:.1f} s"
    if seconds < 90:
        return f"{round(seconds)} s"
    if seconds < 5400:
        return f"{seconds / 60:.1f} min"
    return f"{seconds / 3600:.1f} h"


def estimate_basis(speed) -> str:
    """Where a render-time estimate comes from (a ``render_cost.RenderSpeed``): it says
    'uncalibrated' while the figures are the reference machine's, not this one's."""
    return speed.describe()


def count(n: int, noun: str, plural: str | None = None) -> str:
    """'1 image', '3 images', '0 GCPs': the number with its noun in the right number
    (``plural`` for nouns not made plural with an 's')."""
    return f"{n} {noun if n == 1 else (plural or noun + 's')}"
