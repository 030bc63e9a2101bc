"""Problems found in a project file, with the place in the file they refer to.

Every problem is printed as ``FILE:LINE:COLUMN: <element>: what is wrong; the fix``,
one per line, all of them, so an editor can jump to each.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field

from designer.errors import DesignerError


@dataclass(frozen=True)
class Problem:
    """One located problem: ``message`` already starts with ``<element>:``; ``issue``, the
    semantic :class:`Issue` it was located from, or for a schema error about one value
    (out of range, not one of the choices) an :class:`Issue` without a model object,
    carries its structured fields for programs that word it their own way (the GUI);
    None for a syntax error or any other schema error."""

    message: str
    line: int = 1
    column: int = 1
    issue: Issue | None = field(default=None, compare=False, repr=False)
    #: for a problem of the file as a whole (missing, not XML, not a designer project, of
    #: another version): what the window says, naming no element of the file and its fix
    #: in the window's terms; None: the window words it from ``issue`` or ``message``
    words: str | None = field(default=None, compare=False, repr=False)
    #: the element the problem is about, as ``message`` begins with it (``<element>: ``);
    #: None where the message leads with no element of the file
    element: str | None = field(default=None, compare=False, repr=False)
    #: the elements the sentence after ``<element>: `` names, each written ``<name>``
    #: there: a program quotes them its own way without reading the message
    named: tuple[str, ...] = field(default=(), compare=False, repr=False)

    @classmethod
    def about(cls, element: str, sentence: str, line: int = 1, column: int = 1, *,
              named: tuple[str, ...] = (), issue: Issue | None = None,
              words: str | None = None) -> Problem:
        """The problem ``<element>: sentence`` with its element and the elements the
        sentence names (``named``) as fields."""
        return cls(f"<{element}>: {sentence}", line, column, issue, words, element,
                   tuple(named))

    @property
    def sentence(self) -> str:
        """What is wrong and its fix: ``message`` after its leading ``<element>: ``."""
        if self.element is None:
            return self.message
        return self.message.removeprefix(f"<{self.element}>: ")

    def format(self, source: str) -> str:
        """``FILE:LINE:COLUMN: message`` on one line (line breaks in values are escaped)."""
        message = self.message.translate(_ESCAPES)
        return f"{source}:{self.line}:{self.column}: {message}"


_ESCAPES = {ord("\n"): "\\n", ord("\r"): "\\r", ord("\t"): "\\t"}


class ProjectError(DesignerError):
    """A project file that cannot be used; ``str()`` lists every problem, one a line."""

    def __init__(self, source: str, problems: list[Problem]) -> None:
        self.source = str(source)
        self.problems = list(problems)
        super().__init__(str(self))

    @property
    def lines(self) -> list[str]:
        return [p.format(self.source) for p in self.problems]

    def __str__(self) -> str:
        return "\n".join(self.lines)


@dataclass(frozen=True)
class Issue:
    """A semantic problem about a model object, before it is given a place in the file.

    ``obj`` is the model object (its element's line is looked up in a
    :class:`SourceMap`), ``tag`` the element named in the message, ``attr`` the
    attribute that holds the wrong value (for the column), ``key`` how the reader
    registered the element when it differs from ``tag`` (e.g. ``"vertex:3"``).

    The structured fields say the same as ``message`` for a program to word its own
    way, so that no one parses the message: ``code``, what kind of problem it is (one of
    :data:`CODES`; "" for one that only its message describes), ``value`` the wrong value
    of ``attr``, ``limits`` the (lowest, highest) it may have (None: unbounded on that
    side) and ``choices`` the values it may take. An issue found by the schema has no
    model object (``obj`` None) and names the element around ``tag`` in ``parent``.
    """

    obj: object
    tag: str
    message: str
    attr: str | None = None
    key: str | None = None
    code: str = ""
    value: object = None
    limits: tuple[float | None, float | None] | None = None
    choices: tuple[str, ...] | None = None
    parent: str | None = None


#: the kinds of problem an :class:`Issue` names in its ``code``
CODES = {
    "range": "a declared attribute outside its range (``value``, ``limits``)",
    "choice": "a declared attribute that is none of its choices (``value``, ``choices``)",
    "type": "a value that is not of its schema type, e.g. not a number, not true or false "
            "(``value``: the text as written)",
    "pattern": "a text value that does not match its schema pattern, e.g. an id that is "
               "not a name (``value``: the text as written)",
    "missing-attribute": "a required attribute (``attr``) is not written",
    "unknown-attribute": "an attribute (``attr``) the element does not take (``choices``: "
                         "the attributes it takes)",
    "needs-time-line": "the element (``tag``) needs the flight's <time-line>, which the "
                       "trajectory lacks",
    "no-photos": "the trajectory has neither photos nor a flight plan",
    "surroundings-need-height-field": "surroundings mode auto over a mesh terrain",
    "shape-or-mesh": "a moving object or a plant group with both or neither of a built-in "
                     "shape or kind (``attr``) and a mesh file",
    "needs-ridge": "a pitched roof (``value``: its shape) without a ridge height",
    "scale-not-whole": "the camera's image size (``attr``) times the render's resolution "
                       "scale (``value``) is not a whole number of pixels",
    "outside-extent": "a place outside the terrain extent (``value``: what it is, as "
                      "\"GCP 'A'\" or \"vertex 2 of the survey area\", then its X and Y)",
    "order": "a lower bound (``attr``, its name beginning with min-) not below its upper "
             "bound (the same name with max-; ``value``: the two values)",
    "grid-cells": "a terrain side that is not a whole number of grid cells (``value``: "
                  "the side's name, its length and the grid spacing, m)",
    "grid-nodes": "a terrain grid of too many nodes (``value``: the spacing, width and "
                  "length, m; ``limits``: the most nodes)",
    "texels": "a texture tile of too many or too few texels per side (``value``: the "
              "tile's side and the texel, m, and the texels; ``limits``: the fewest and most)",
    "flat-roof-ridge": "a ridge (``attr``) given to a flat roof",
    "pixels-not-square": "sensor and image sizes whose pixels are not square, without a "
                         "pixel aspect",
    "too-many-plants": "vegetation whose densities give too many plants (``value``: about "
                       "how many; ``limits``: the most)",
    "lens-folds": "a lens distortion that folds inside the image (its element's object: "
                  "the camera)",
    "within": "a value (``value``) outside limits other fields set (``limits``, open or "
              "closed as the attribute's declaration says)",
    "sun-below-horizon": "a sun computed for a moment and place where it is below the "
                         "horizon (``value``: its elevation, deg)",
    "ridge-direction": "a ridge direction (``value``) along no side of the footprint, or "
                       "along the shorter side of a hip roof (``choices``: the directions it "
                       "may take, deg)",
    "pitched-roof-shape": "a gable or hip roof on a footprint that is not a rectangle",
    "no-survey": "a GCP with neither a surveyed position nor a simulated survey",
    "variation-on-orthophoto": "a texture variation on an orthophoto, which does not repeat",
    "no-plants": "vegetation without a plant group",
    "dem-coverage": "a DEM that does not cover the terrain extent (``value``: the X and Y "
                    "it covers, min-X max-X min-Y max-Y)",
    "readout-not-shorter": "a rolling shutter's readout not shorter than the trigger "
                           "interval (``value``: the camera id, the readout and the interval, "
                           "s)",
    "distortion-and-rolling-shutter": "a camera with a lens distortion and a rolling "
                                      "shutter (``value``: its id)",
    "name-vs-format": "a photo's name whose extension is not the output format's "
                      "(``value``: the format; ``choices``: its extensions)",
    "stations-too-low": "camera stations below, or within the camera's near distance of, "
                        "the terrain, a building or a plant (``value``: a "
                        "designer.checks.station_clearance.LowStations)",
    "colour": "a colour (``attr``) that is not three numbers from 0 to 1 (``value``: as "
              "read)",
}


class SourceMap:
    """Where each model object came from: (object, element) → line, and the text for columns.

    Objects are identified by ``id()``; the map keeps a reference to the project so
    the ids stay valid.
    """

    def __init__(self, text: str) -> None:
        self._lines = text.splitlines()
        self._where: dict[tuple[int, str], int] = {}
        self._first: dict[int, int] = {}
        self.keep_alive: object = None

    def add(self, obj: object, key: str, line: int | None) -> None:
        line = int(line or 1)
        self._where[(id(obj), key)] = line
        self._first.setdefault(id(obj), line)

    def locate(self, issue: Issue) -> Problem:
        """The issue as a located :class:`Problem`."""
        key = issue.key or issue.tag
        line = self._where.get((id(issue.obj), key)) or self._first.get(id(issue.obj), 1)
        line, column = self.position(line, issue.tag, issue.attr)
        return Problem.about(issue.tag, issue.message, line, column, issue=issue)

    def position(self, line: int, tag: str, attr: str | None = None) -> tuple[int, int]:
        """(line, 1-based column) of ``<tag``, or of ``attr=`` inside that start tag.

        lxml records only a line per element, and for a start tag spread over several
        lines it is the last one; so the tag is searched backwards from ``line`` and
        the attribute forwards from the tag. Column 1 when not found.
        """
        if not 1 <= line <= len(self._lines):
            return line, 1
        tag_re = re.compile(rf"<(?:[\w.\-]+:)?{re.escape(tag)}(?=[\s/>]|$)")
        tag_line, start = line, None
        for back in range(line, max(0, line - 50), -1):
            hits = list(tag_re.finditer(self._lines[back - 1]))
            if hits:
                tag_line, start = back, hits[-1].start()
                break
        if start is None:
            return line, 1
        if attr is None:
            return tag_line, start + 1
        attr_re = re.compile(rf"(?<![\w\-]){re.escape(attr)}\s*=")
        for n in range(tag_line, min(len(self._lines), tag_line + 50) + 1):
            text = self._lines[n - 1]
            begin = start if n == tag_line else 0
            end = text.find(">", begin)
            a = attr_re.search(text, begin, end if end >= 0 else len(text))
            if a:
                return n, a.start() + 1
            if end >= 0:
                break
        return tag_line, start + 1


def unlocated(issue: Issue) -> Problem:
    """An issue of a model that was not read from a file (line 0, column 0)."""
    return Problem.about(issue.tag, issue.message, 0, 0, issue=issue)
