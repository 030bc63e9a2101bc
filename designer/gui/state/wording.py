"""Messages as the window's user reads them (Qt-free).

Validation issues are worded from their structured fields (code, element, attribute,
value, limits; :class:`designer.project.problems.Issue`) and the declarations' labels,
never by reading their message: :func:`issue_text`, :func:`problem_text`; a schema
problem about the file's structure from the element it is about and the elements its
sentence names (``Problem.element``, ``Problem.named``): :func:`untagged`. A library
error that carries its fields (:class:`designer.errors.ParameterError`: parameter, value,
what it must be) is worded from them: :func:`error_text`. Errors raised by the library as
plain text name its parameters (``size_x_m``) and print numbers the way Python does
(``5.40595e+06``); :func:`humanize` shows such a field as the panel labels it and numbers
in fixed point with sensible decimals.
"""

from __future__ import annotations

import math
import re
from dataclasses import replace

from designer.errors import ParameterError
from designer.gui.state.field_places import (
    declaration_at,
    element_title,
    panel_for_element,
    panel_for_object,
)
from designer.project import model as m
from designer.project.declare import Declared, attributes, declared, declared_elements
from designer.project.problems import Issue, Problem

#: parameters of the library's plain errors that no declaration labels (or that several
#: declarations label differently) → what the panels call them
LIBRARY_NAMES = {
    "size_x_m": "terrain width (X)",
    "size_y_m": "terrain length (Y)",
    "spacing_m": "grid spacing",
    "min_spacing_m": "min spacing",
    "margin_m": "margin",
    "front_overlap": "front overlap",
    "side_overlap": "side overlap",
    "tilt_deg": "forward tilt",
    "n_check": "number of check points",
    "cell_m": "coverage grid cell",
    "size_m": "target size",
    "front_overlap_fraction": "front overlap",
    "side_overlap_fraction": "side overlap",
    "oversample": "distortion oversampling",
    "displacement_px": "motion blur displacement",
}


def _declared_labels() -> dict[str, str]:
    """Field name → its declaration's label, for every declared field that has a label
    and the same one in every declaration (``focal_length_mm`` → ``focal length``)."""
    from designer.project import model as m

    labels: dict[str, set[str]] = {}
    for cls in declared_elements(m.Project):
        for _, d in attributes(cls):
            if d.attr.label is not None:
                labels.setdefault(d.name, set()).add(d.attr.label)
    return {name: next(iter(found)) for name, found in labels.items() if len(found) == 1}


#: parameter and field names → what the panels call them: the declarations' labels, and
#: the library's own parameters
FIELD_NAMES = {**_declared_labels(), **LIBRARY_NAMES}
#: the switch that gives the flight its time line, as the window shows it
_TIME_LINE_ON = ("switch on the time line in the Flight panel "
                 "(“the photos have times”)")


def _either(names) -> str:
    """``car, person or box``."""
    names = [n.replace("-", " ") for n in names]
    return ", ".join(names[:-1]) + f" or {names[-1]}" if len(names) > 1 else names[0]


#: (issue code, element) → what the window says for a validation issue whose fix, in the
#: project file's terms, is an element to add: the panel and control that do it. Filled
#: in from the issue's fields: {obj} the model object, {value} the attribute's value.
DIRECTIONS: dict[tuple[str, str], str] = {
    ("needs-time-line", "rolling-shutter"):
        "a camera reads its rows out over {value:g} s, but the flight has no time line to "
        f"move the camera along; {_TIME_LINE_ON}, or set the readout to 0 s in the Camera "
        "panel",
    ("needs-time-line", "sun-over-time"):
        "the sun follows each photo's time, but the flight has no time line; "
        f"{_TIME_LINE_ON}, or give the sun by its direction or a moment and place in the "
        "Lighting panel",
    ("needs-time-line", "object"):
        "moving object '{obj.id}' is posed at each photo's time, but the flight has no "
        f"time line; {_TIME_LINE_ON}, or remove the moving objects in the Moving objects "
        "panel",
    ("needs-time-line", "output"):
        "EXIF metadata holds each photo's time, but the flight has no time line; "
        f"{_TIME_LINE_ON}",
    ("needs-time-line", "photo"):
        "photo '{obj.name}' has a time, but the flight has no time line; "
        f"{_TIME_LINE_ON}",
    ("no-photos", "trajectory"):
        "no photos: add a grid flight in the Flight panel, or import a flight (File menu)",
    ("shape-or-mesh", "object"):
        f"moving object '{{obj.id}}' needs either a shape ({_either(m.MOVING_SHAPES)}) or a "
        "mesh file, not both; choose one in the Moving objects panel",
    ("shape-or-mesh", "plants"):
        f"a plant group needs either a kind ({_either(m.PLANT_KINDS)}) or a mesh file, "
        "not both; choose one in the Vegetation panel",
    ("needs-ridge", "building"):
        "a {value} roof needs a ridge height; set the ridge above the walls in the "
        "Buildings panel",
    ("pitched-roof-shape", "footprint"):
        "building '{obj.id}': a {obj.roof} roof is built on a rectangular footprint (four "
        "corners at right angles), which this one is not; choose a flat roof in the "
        "Buildings panel",
    ("no-survey", "target"):
        "GCP '{obj.id}' has no surveyed position and no survey is simulated for it; tick "
        "“add survey error” in the GCPs panel",
    ("variation-on-orthophoto", "variation"):
        "an orthophoto does not repeat: the texture variation applies to tiled textures "
        "only; untick “non-repeating variation” in the Texture panel",
    ("no-plants", "vegetation"):
        "the vegetation has no plant group; add grass, shrubs or trees in the Vegetation "
        "panel, or untick “plants on the terrain”",
    ("distortion-and-rolling-shutter", "rolling-shutter"):
        "camera '{value}' has a lens distortion and a rolling shutter, which designer does "
        "not render exactly; set the distortion to none or the readout to 0 s in the Camera "
        "panel",
    ("colour", "object"):
        "moving object '{obj.id}': its colour must be three numbers from 0 to 1 (linear "
        "red, green, blue), e.g. 0.8 0.1 0.1",
    ("colour", "plants"):
        "a plant group's colour must be three numbers from 0 to 1 (linear red, green, "
        "blue), e.g. 0.1 0.3 0.05",
    ("surroundings-need-height-field", "surroundings"):
        "surroundings “auto” continue a height-field terrain (flat, procedural or DEM); a "
        "mesh terrain cannot be continued: choose surroundings “none” in the Terrain "
        "panel, or import the terrain as a DEM",
}
#: issue codes whose fix is done in another panel than the one of their element
CODE_PANELS = {"scale-not-whole": "Render"}
_UNITS = {"m": "m", "mm": "mm", "px": "px", "deg": "°", "percent": "%"}
_IDENT = re.compile(r"(?<![\w./\\-])[a-z][a-z0-9]*(?:_[a-z0-9]+)+(?![\w./\\-])")
_SCI = re.compile(r"(?<![\w.])[-+]?\d+(?:\.\d+)?[eE][-+]?\d+\b")
#: what an id (the schema's d:Identifier) may be, as the window says it
_NAME_RULE = "use only letters, digits, _ . + - and begin with a letter or digit"
#: what a switch (xs:boolean) takes, as the window shows it
_TRUE_OR_FALSE = "true or false (the box ticked or not)"
_NON_FINITE = {"nan", "inf", "+inf", "-inf", "infinity", "-infinity", "+infinity"}
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


def _parameter_label(name: str) -> str:
    """A library parameter as the panels label it; one no panel labels as its words
    (``relief_m`` → ``relief``: the unit follows the value)."""
    if name in FIELD_NAMES:
        return FIELD_NAMES[name]
    words = name.split("_")
    return " ".join(words[:-1] if len(words) > 1 and words[-1] in _UNITS else words)


def error_text(error: BaseException) -> str:
    """A library error as the window says it: a :class:`~designer.errors.ParameterError`
    from its fields (the parameter as the panels label it, its value in fixed point with
    its unit, what it must be: ``terrain width (X) 100 m must be a whole number of 3 m
    grid cells; …``), any other as its message with :func:`humanize`."""
    if not (isinstance(error, ParameterError) and error.name and error.must):
        return humanize(str(error))
    value = error.value
    if isinstance(value, bool) or not isinstance(value, int | float):
        shown = f"“{value}”"
    else:
        unit = f" {_UNITS.get(error.unit, error.unit)}" if error.unit else ""
        shown = (_value_text(float(value)) if isinstance(value, float) else f"{value}") + unit
    return f"{_parameter_label(error.name)} {shown} must be {error.must}"


def _declaration(issue: Issue) -> Declared | None:
    """The declaration of the attribute an issue is about, from its object's class (an
    issue the schema found, which has no object: from its element and attribute)."""
    if issue.obj is None:
        return declaration_at(issue.tag, issue.attr, issue.parent)
    for _, d in attributes(type(issue.obj)):
        if d.xml == issue.attr and d.attr.child == issue.key:
            return d
    return None


def _value_text(value: object) -> str:
    if isinstance(value, float) and math.isfinite(value):
        return fixed(value)
    if isinstance(value, float) and math.isinf(value):
        return "infinity" if value > 0 else "minus infinity"
    return "not a number" if isinstance(value, float) else f"{value}"


def _unit(d: Declared | None) -> str:
    """`` mm``, `` °``: a declared field's unit as the panel shows it (or "")."""
    if d is None or not d.attr.unit:
        return ""
    return " " + _UNITS.get(d.attr.unit, d.attr.unit)


def _range_words(d: Declared | None, limits: tuple[float | None, float | None]) -> str:
    """``from 0 to 0.5 s``, ``greater than 0 m``, ``at most 100 %``: the limits in fixed
    point, open or closed as the declaration says."""
    low, high = limits
    low_open = d is not None and d.attr.low_open
    high_open = d is not None and d.attr.high_open
    unit = _unit(d)
    if low is None and high is None:
        return "a finite number"
    if low is not None and high is not None and not (low_open or high_open):
        return f"from {fixed(low)} to {fixed(high)}{unit}"
    words = []
    if low is not None:
        words.append(("greater than " if low_open else "at least ") + fixed(low))
    if high is not None:
        words.append(("below " if high_open else "at most ") + fixed(high))
    return " and ".join(words) + unit


def _wanted(d: Declared) -> str | None:
    """What a declared field takes, as the window says it: ``a number greater than 0 and
    at most 1000 mm``, ``true or false``, ``one of grass, gravel``; None when its
    declaration says too little."""
    if d.choices:
        return f"one of {', '.join(d.choices)}"
    if d.base in (int, float):
        number = "a whole number" if d.base is int else "a number"
        return f"{number} {_range_words(d, (d.attr.low, d.attr.high))}"
    if d.base is bool:
        return _TRUE_OR_FALSE
    if d.attr.xsd == "d:Identifier":
        return f"a name ({_NAME_RULE})"
    return None


def _labelled(cls: type, name: str) -> str:
    return next(d.label for d in declared(cls) if d.name == name)


def _not_square_text(cam: m.Camera) -> str:
    """Pixels that are not square, with the camera's sizes as the Camera panel labels
    them and the sensor height that makes them square."""
    W, H = cam.image_width_px, cam.image_height_px
    pitch_x, pitch_y = cam.sensor_width_mm / W, cam.sensor_height_mm / H
    sw, sh = _labelled(m.Camera, "sensor_width_mm"), _labelled(m.Camera, "sensor_height_mm")
    iw, ih = _labelled(m.Camera, "image_width_px"), _labelled(m.Camera, "image_height_px")
    return (f"pixels are not square: a {fixed(cam.sensor_width_mm)} × "
            f"{fixed(cam.sensor_height_mm)} mm sensor over {W} × {H} px gives "
            f"{fixed(pitch_x * 1000, 4)} × {fixed(pitch_y * 1000, 4)} µm pixels; make "
            f"{sw} / {iw} equal {sh} / {ih} (e.g. {sh} "
            f"{fixed(cam.sensor_width_mm * H / W, 4)} mm), or give a pixel aspect")


def _folds_text(cam: m.Camera) -> str:
    """A lens distortion that folds inside the image, with its coefficients as the Camera
    panel labels them."""
    dist = cam.distortion
    given = ", ".join(f"{d.label} {fixed(getattr(dist, d.name), 6)}" for d in declared(type(dist))
                      if isinstance(getattr(dist, d.name), float) and getattr(dist, d.name))
    return (f"camera '{cam.id}': the lens distortion ({given}) folds inside the image: "
            "pixels near its corners have no one undistorted ray; reduce the coefficients "
            "in the Camera panel, or the image size or field of view")


def _unknown_text(issue: Issue) -> str:
    """An attribute the element does not take, with the settings it does take as their
    panel labels them (the nearest to what was written first offered)."""
    import difflib

    def label(name: str) -> str:
        d = declaration_at(issue.tag, name, issue.parent)
        return d.label if d is not None else name.replace("-", " ")

    allowed = list(issue.choices or ())
    close = difflib.get_close_matches(str(issue.value), allowed, n=1)
    mean = f" (did you mean {label(close[0])}?)" if close else ""
    here = (f" (the settings here: {', '.join(label(a) for a in allowed)})" if allowed
            else " (nothing is set here)")
    return f"unknown setting “{issue.value}”{mean}; remove it{here}"


def issue_text(issue: Issue) -> str:
    """A validation issue as the window says it, from its structured fields: a range or
    choice with the field as its panel labels it (the declaration's ``label``) and
    numbers in fixed point; a value that is not a number with the number the field
    takes, not true or false likewise, an id that is not a name with the names it takes;
    a field missing with what it takes; an unknown attribute with the settings there are;
    a fix done in a panel (:data:`DIRECTIONS`) as that panel and control; any other issue
    as its message, numbers in fixed point."""
    direction = DIRECTIONS.get((issue.code, issue.tag))
    if direction is not None:
        return direction.format(obj=issue.obj, value=issue.value)
    if issue.code == "unknown-attribute":
        return _unknown_text(issue)
    d = _declaration(issue)
    label = d.label if d is not None else (issue.attr or issue.tag).replace("-", " ")
    if issue.code == "outside-extent":
        what, x, y = issue.value
        where = f"{what} at X {fixed(x)}, Y {fixed(y)} lies outside the terrain extent"
        if isinstance(issue.obj, m.PathPoint):  # paths are edited in the project file
            return (f"{where}, where the object has no ground to stand on; move the point "
                    "inside the extent in the project file, or enlarge the terrain in the "
                    "Terrain panel")
        return f"{where}; move it inside, or enlarge the terrain in the Terrain panel"
    if issue.code == "order" and issue.attr and issue.attr.startswith("min-"):
        upper = _declaration(replace(issue, attr="max-" + issue.attr[4:]))
        low, high = issue.value
        other = upper.label if upper is not None else "the upper bound"
        return (f"{label} {fixed(low)} must be below {other} {fixed(high)}{_unit(d)}; swap or "
                "correct them")
    if issue.code == "grid-cells":
        side, size, spacing = issue.value
        return (f"the terrain's {side} {fixed(size)} m is not a whole number of "
                f"{fixed(spacing)} m grid cells; choose a {label} that divides it")
    if issue.code == "grid-nodes":
        spacing, width, length = issue.value
        return (f"a {fixed(spacing)} m grid over {fixed(width)} × {fixed(length)} m has more "
                f"than {issue.limits[1]:,.0f} nodes; choose a coarser {label} or a smaller "
                "terrain")
    if issue.code == "texels":
        tile, texel, texels = issue.value
        fewest, most = issue.limits
        if texels > most:
            return (f"a {fixed(tile)} m tile of {fixed(texel)} m texels needs {texels:,.0f} "
                    f"texels per side, more than {most:,.0f}; choose a larger {label} or "
                    "more tiling repeats")
        return (f"a {fixed(tile)} m tile of {fixed(texel)} m texels has only {fixed(texels)} "
                f"texels per side, fewer than {fewest:,.0f}; choose a smaller {label}")
    if issue.code == "within" and issue.limits is not None:
        return f"{label} {_value_text(issue.value)} must be {_range_words(d, issue.limits)}"
    if issue.code == "sun-below-horizon":
        return (f"the sun is {fixed(abs(issue.value), 1)}° below the horizon at that moment "
                "and place; choose a moment in daylight, or give the sun by its direction, "
                "in the Lighting panel")
    if issue.code == "ridge-direction":
        return (f"{label} {fixed(issue.value, 1)}° runs along no side the roof can take "
                f"({' or '.join(issue.choices)}°); give one of those in the project file, or "
                "leave it out")
    if issue.code == "dem-coverage":
        x0, x1, y0, y1 = issue.value
        return (f"the DEM covers X {fixed(x0)} to {fixed(x1)}, Y {fixed(y0)} to {fixed(y1)}, "
                "not the whole terrain extent; shrink the terrain in the Terrain panel, or "
                "use a larger DEM")
    if issue.code == "readout-not-shorter":
        camera, readout, interval = issue.value
        return (f"camera '{camera}': the {label} {fixed(readout)} s is not shorter than the "
                f"{_labelled(m.TimeLine, 'trigger_interval_s')} {fixed(interval)} s; a "
                "frame must be read before the next is taken: shorten the readout in the "
                "Camera panel")
    if issue.code == "name-vs-format":
        return (f"photo '{issue.obj.name}' is not named as a {issue.value} image; choose the "
                f"format its name says in the Render panel, or name it with "
                f"{' or '.join(issue.choices)}")
    if issue.code == "flat-roof-ridge":
        return (f"a flat roof has no {label}; clear it, or choose a gable or hip roof in the "
                "Buildings panel")
    if issue.code == "pixels-not-square":
        return _not_square_text(issue.obj)
    if issue.code == "too-many-plants":
        return (f"the plant groups' densities give about {issue.value:,.0f} plants on the "
                f"terrain, more than {issue.limits[1]:,.0f}; lower their density in the "
                "Vegetation panel")
    if issue.code == "lens-folds":
        return _folds_text(issue.obj)
    if issue.code == "stations-too-low":
        return f"{issue.value.sentence()}; {issue.value.panel_fix()}"
    if issue.code == "scale-not-whole" and d is not None:
        size = getattr(issue.obj, d.name)
        return (f"camera '{issue.obj.id}': {d.label} {size} px × resolution scale "
                f"{fixed(issue.value)} = {fixed(size * issue.value)} px is not a whole number "
                "of pixels; choose a resolution scale that divides the image size (e.g. 0.5 "
                "or 0.25) in the Render panel")
    if issue.code == "missing-attribute":
        wanted = _wanted(d) if d is not None else None
        return f"{label} is missing" + (f"; give {wanted}" if wanted else "")
    if issue.code == "type" and d is not None and d.base is bool:
        return f"{label} “{issue.value}” is neither true nor false; give {_TRUE_OR_FALSE}"
    if issue.code == "range" and issue.limits is not None:
        # the declared limits are the file's; the schema names only the one passed
        limits = (d.attr.low, d.attr.high) if d is not None else issue.limits
        return f"{label} {_value_text(issue.value)} must be {_range_words(d, limits)}"
    if issue.code == "type" and d is not None and d.base in (int, float):
        number = "a whole number" if d.base is int else "a number"
        finite = "a finite number" if str(issue.value).strip().lower() in _NON_FINITE \
            else number
        return (f"{label} “{issue.value}” is not {finite}; give {number} "
                f"{_range_words(d, (d.attr.low, d.attr.high))}")
    if issue.code == "type" and d is not None and d.attr.xsd == "xs:dateTime":
        return (f"{label} “{issue.value}” is not a date and time; write it as ISO 8601 "
                "with a time zone, e.g. 2024-06-21T10:30:00+02:00")
    if issue.code == "pattern" and d is not None and d.attr.xsd == "d:Identifier":
        if not str(issue.value):
            return f"{label} is empty: give a name ({_NAME_RULE})"
        return f"{label} “{issue.value}” is not a name: {_NAME_RULE}"
    if issue.code == "choice" and issue.choices:
        return (f"{label} “{issue.value}” is not one of {', '.join(issue.choices)}; choose "
                "one of them")
    return humanize(issue.message)


def _panel(issue: Issue) -> str | None:
    """The panel that edits the element an issue is about (its model object's, or for
    an issue the schema found, its element's inside its parent; :data:`CODE_PANELS`
    where the fix is done elsewhere), or None."""
    if issue.code in CODE_PANELS:
        return CODE_PANELS[issue.code]
    if issue.obj is None:
        return panel_for_element(issue.tag, issue.parent)
    return panel_for_object(issue.obj, issue.tag)


def _place(issue: Issue) -> str | None:
    """Where the window puts what an issue is about: its panel, or where no panel edits
    it the element's title (``project origin``, ``object placement``)."""
    return _panel(issue) or element_title(issue.tag, issue.parent, issue.obj)


def field_place(issue: Issue) -> str | None:
    """``Camera › sensor width``: the panel and the field, as the window labels them, of
    the value an issue is about (None when it is not one declared value)."""
    panel, d = _panel(issue), _declaration(issue)
    return None if panel is None or d is None else f"{panel} › {d.label}"


def untagged(problem: Problem, source: str) -> str:
    """A schema error about the file's structure (an element unknown, missing, out of
    order: only a hand-edited file has them) without XML's angle brackets, from the
    problem's fields: the place in the file leads (the sentence names the element), the
    elements the sentence names are quoted (“camera”)."""
    sentence = problem.sentence
    for name in problem.named:
        sentence = sentence.replace(f"<{name}>", f"“{name}”")
    return Problem(sentence, problem.line, problem.column).format(source)


def problem_text(problem: Problem | str, source: str) -> str:
    """A problem as a line of the window's Problems list: ``FILE:LINE:COL:`` (the place)
    and, for a value out of range or not among its choices, the panel and field as the
    window labels them (``Camera › sensor width 13200 mm must be …``); for another
    validation issue the panel that fixes it (or the element's title where no panel
    edits it) and :func:`issue_text`; a problem without an issue (a schema error, a
    message) as its text with field names as labelled and numbers in fixed point."""
    if isinstance(problem, str):
        return humanize(problem)
    if problem.words is not None:  # the file as a whole: no line, no element
        return f"{source}: {problem.words}"
    if problem.issue is None:
        return humanize(untagged(problem, source))
    place = _place(problem.issue)
    text = issue_text(problem.issue)  # a value's starts with the field's label
    worded = f"{place} › {text}" if place else text
    return Problem(worded, problem.line, problem.column).format(source)


def issue_line(issue: Issue) -> str:
    """An issue found in the window's own model (no place in a file): the panel that
    fixes it and :func:`issue_text` (``Flight › 12 of 60 camera stations …``)."""
    place = _place(issue)
    text = issue_text(issue)
    return f"{place} › {text}" if place else text


def point_text(xyz) -> str:
    """A world point as every readout of the window gives it: ``E 511995.497  N
    5400012.250  H 123.456 m`` (metres to the millimetre, no digit grouping: as typed and
    as the files write them)."""
    x, y, z = (float(v) for v in xyz)
    return f"E {x:.3f}  N {y:.3f}  H {z:.3f} m"


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
    """Where a render-time estimate comes from (a ``render_time.model.RenderSpeed``): it says
    'uncalibrated' while the figures are the reference machine's, not this one's."""
    return speed.describe()


def count(n: int, noun: str, plural: str | None = None) -> str:
    """'1 image', '3 images', '0 GCPs': the number with its noun in the right number
    (``plural`` for nouns not made plural with an 's')."""
    return f"{n} {noun if n == 1 else (plural or noun + 's')}"
