"""Where a project file's element or attribute is edited in the window (Qt-free): the
panel (:func:`panel_for_tag`) and the declared field (:func:`declaration_at`), so a
problem found in the file is said as ``Camera › sensor width``, the way the panel labels
it."""

from __future__ import annotations

import dataclasses
import functools
import typing

from designer.project import model as m
from designer.project.declare import Declared, attributes, declared, element_of

#: keywords in an element's name → the panel that edits it (the first match wins)
PANEL_KEYWORDS = (
    ("Processing", ("processing", "calibration", "gcps", "control", "position-prior",
                    "matching", "sfm", "dense")),
    ("Flight", ("flight", "area", "vertex", "overlap", "altitude", "gsd", "pose-noise",
                "trajectory", "exterior", "time-line", "mount", "grid-angle", "crosshatch",
                "start-corner", "tilt", "random-seed")),
    ("Camera", ("camera", "sensor", "focal", "distortion", "principal", "image-width",
                "image-height", "brown", "fisheye", "rolling-shutter")),
    ("GCPs", ("target", "true", "surveyed", "survey-accuracy", "sigma")),
    ("Texture", ("texture", "tiling", "image", "procedural-texture", "orthophoto")),
    ("Lighting", ("lighting", "sun", "sky", "cloud")),
    ("Vegetation", ("vegetation", "plants", "wind")),
    ("Buildings", ("building",)),
    ("Terrain", ("terrain", "extent", "procedural", "dem", "mesh", "flat")),
    ("Effects", ("effects", "vignetting", "noise", "blur", "jpeg", "motion", "defocus",
                 "exposure", "chromatic")),
    ("Render", ("render", "samples", "pixel-filter", "output", "resolution", "preset",
                "workers")),
    ("Moving objects", ("moving-objects", "path")),
)

#: where a declared element lives in the project (its ``path``) → the panel that edits it
PATH_PANELS = (
    ("scene.terrain", "Terrain"), ("scene.texture", "Texture"),
    ("scene.lighting", "Lighting"), ("scene.vegetation", "Vegetation"),
    ("scene.targets", "GCPs"), ("effects", "Effects"), ("render", "Render"),
    ("outputs", "Render"), ("processing", "Processing"), ("trajectory", "Flight"),
)


#: elements that come in lists or alternatives (no ``path``) whose name says too little
CLASS_PANELS = {m.ProceduralTexture: "Texture", m.ImageTexture: "Texture",
                m.OrthophotoTexture: "Texture", m.MovingObject: "Moving objects",
                m.PathPoint: "Moving objects", m.Terrain: "Terrain", m.Camera: "Camera",
                m.Building: "Buildings",
                m.ExteriorOrientation: "Flight", m.OrbitPattern: "Flight",
                m.FacadePattern: "Flight"}


def panel_for_object(obj: object, tag: str) -> str | None:
    """The panel of a model object's element ``<tag>``: by where the element's
    declaration puts it in the project (the Effects panel's ``<sensor-noise>``, the
    Texture panel's ``<procedural>``), else by its name."""
    if type(obj) in CLASS_PANELS:
        return CLASS_PANELS[type(obj)]
    el = element_of(type(obj))
    if el is not None and el.path is not None:
        for prefix, title in PATH_PANELS:
            if el.path == prefix or el.path.startswith(prefix + "."):
                return title
    return panel_for_tag(tag)


def panel_for_tag(tag: str) -> str | None:
    """The title of the panel that edits the element ``<tag>``, or None."""
    for title, words in PANEL_KEYWORDS:
        if any(w in tag for w in words):
            return title
    return None


def panel_for_element(tag: str, parent: str | None) -> str | None:
    """The panel of ``<tag>`` inside ``<parent>``: the parent's panel first (a
    ``<procedural>`` inside ``<texture>`` is the Texture panel's), else the element's."""
    return (panel_for_tag(parent) if parent else None) or panel_for_tag(tag)


def _classes(root: type) -> list[type]:
    """Every dataclass reachable from ``root`` by its fields' type hints (each once)."""
    seen: list[type] = []

    def visit(hint: object) -> None:
        if isinstance(hint, type):
            if hint in seen or not dataclasses.is_dataclass(hint):
                return
            seen.append(hint)
            for inner in typing.get_type_hints(hint).values():
                visit(inner)
        else:
            for arg in typing.get_args(hint):
                visit(arg)

    visit(root)
    return seen


#: attributes the reader maps by hand (no model field declares them on their element) →
#: the declared field that holds the same kind of value: a vertex of the survey area or
#: of a building's footprint, and a mesh building's position, are points as a moving
#: object's path points are
SAME_AS = {("vertex", "X"): (m.PathPoint, "X"), ("vertex", "Y"): (m.PathPoint, "Y"),
           ("building", "X"): (m.PathPoint, "X"), ("building", "Y"): (m.PathPoint, "Y")}


@functools.cache
def _index() -> dict[tuple[str, str | None], Declared]:
    """(element, attribute) → the declared field, for every declared element's
    attributes, those of its attribute groups (a point's X, Y, Z) included (a value
    given as an element's text: (element, None)), and the hand-mapped ones of
    :data:`SAME_AS`."""
    out: dict[tuple[str, str | None], Declared] = {}
    for cls in _classes(m.Project):
        el = element_of(cls)
        if el is None:
            continue
        for _group, d in attributes(cls):
            key = (d.xml, None) if d.attr.text else (d.attr.child or el.tag, d.xml)
            out.setdefault(key, d)
    for key, (cls, name) in SAME_AS.items():
        out.setdefault(key, next(d for d in declared(cls) if d.name == name))
    return out


def declaration_at(tag: str, attr: str | None, parent: str | None) -> Declared | None:
    """The declared field a file's ``<tag attr=…>`` (or ``<tag>`` text, ``attr`` None)
    inside ``<parent>`` holds, or None when none is declared for it."""
    return _index().get((tag, attr))


def element_title(tag: str, parent: str | None, obj: object = None) -> str | None:
    """What the window calls the element ``<tag>`` (inside ``<parent>``) where no panel
    edits it: its declaration's title (``project origin``, ``object placement``); of two
    elements of one name, the one a field named as ``parent`` holds (``<object>`` in
    ``<objects>``: a scene object). None for an element declared nowhere."""
    if obj is not None and element_of(type(obj)) is not None:
        return element_of(type(obj)).title
    found = [c for c in _classes(m.Project)
             if element_of(c) is not None and element_of(c).tag == tag]
    if len(found) > 1 and parent is not None:
        holders = [c for c in found if any(
            f.name == parent.replace("-", "_") and c in _classes_of_hint(hint)
            for holder in _classes(m.Project) if dataclasses.is_dataclass(holder)
            for f in dataclasses.fields(holder)
            for hint in (typing.get_type_hints(holder)[f.name],))]
        found = holders or found
    return element_of(found[0]).title if found else None


def _classes_of_hint(hint: object) -> list[type]:
    if isinstance(hint, type):
        return [hint]
    return [c for arg in typing.get_args(hint) for c in _classes_of_hint(arg)]
