"""The project XSD's preamble and named simple types: what
:mod:`designer.project.xsd_gen` writes before the elements.

``SCHEMA_DOC`` is the schema's own documentation (its conventions, the same as
docs/conventions.md); ``SIMPLE_TYPES`` the named simple types the declarations refer to
(``xsd="d:Identifier"``, ``d:FiniteDouble`` under every number). lxml-free.
"""

from __future__ import annotations

from dataclasses import dataclass

from designer.project.declare_structure import ListOf

SCHEMA_DOC = """\
designer project, schema version 1.0 (namespace urn:designer:project:1).

A project describes one virtual photogrammetric survey: the scene (terrain, texture,
ground control targets, other objects, lighting), the camera(s), where the photos are
taken (explicit exterior orientations and/or a flight plan), image effects, render
settings and the ground truth to export.

Conventions (the same everywhere in designer, see docs/conventions.md):
- World frame: right-handed, metres. X = Easting, Y = Northing, Z = height (up).
  Every coordinate in this file (X, Y, Z, the terrain extent, GCPs, photo positions,
  flight area) is a WORLD coordinate, in the CRS named by project/crs. The project
  origin (E0, N0, H0) is only the point that designer subtracts before handing
  geometry to Blender (float32); it does not shift the coordinates written here.
- Camera frame (photogrammetric, same as Blender's camera): x = image right,
  y = image top, z = backwards; the camera looks along -z.
- Orientation: omega, phi, kappa in DEGREES. R = Rx(omega) . Ry(phi) . Rz(kappa),
  counter-clockwise positive, maps camera-frame vectors to world:
  X_world = C + R . x_cam, C = perspective centre. omega = phi = kappa = 0 is a
  nadir camera with the image top pointing north.
- Pixels: continuous coordinates, origin at the top-left CORNER of the top-left
  pixel, u right, v down; pixel (i, j) has its centre at (i + 0.5, j + 0.5).
- Interior orientation: focal length and sensor size in mm, image size in px,
  principal point offset in mm from the sensor centre (x right, y up). Pixels are
  square (sensor width / image width = sensor height / image height to 1e-6
  relative) unless a pixel aspect is stated. Lens distortion: Brown-Conrady with
  OpenCV's meaning and order (k1, k2, k3, p1, p2) on normalised computer-vision
  coordinates, or OpenCV's equidistant fisheye model (k1..k4 on theta).
- Units: lengths in metres unless the name says mm or px; angles in degrees; times
  in seconds; numbers with a '.' decimal point and no thousands separators. NaN and
  infinity are not allowed anywhere.
- File paths (texture, DEM, meshes, output folder) are relative to the folder of
  this XML file unless absolute.
"""


@dataclass(frozen=True)
class NamedSimpleType:
    """A named ``xs:simpleType``: a restriction of ``base`` by ``facets`` ((facet, value),
    e.g. ("minInclusive", "-1e8"); an enumeration value may add its documentation), or
    of a list (``base`` a :class:`designer.project.declare_structure.ListOf`)."""

    name: str
    doc: str
    base: str | ListOf
    facets: tuple[tuple[str, ...], ...]


SIMPLE_TYPES = (
    NamedSimpleType("FiniteDouble", "A finite decimal number ('.' decimal point, optional "
                    "exponent). NaN and INF are rejected.", "xs:double",
                    (("pattern", r"[+\-]?([0-9]+(\.[0-9]*)?|\.[0-9]+)([eE][+\-]?[0-9]+)?"),)),
    NamedSimpleType("Coordinate", "A world coordinate in metres (|value| at most 1e8 m).",
                    "d:FiniteDouble", (("minInclusive", "-1e8"), ("maxInclusive", "1e8"))),
    NamedSimpleType("Height", "A world height Z in metres, -12000 to 100000 m.",
                    "d:FiniteDouble",
                    (("minInclusive", "-12000"), ("maxInclusive", "100000"))),
    NamedSimpleType("Identifier", "A short name used to refer to something: letters, "
                    "digits, '_', '.', '-' and '+', starting with a letter or digit, at most "
                    "128 characters.", "xs:string",
                    (("pattern", r"[A-Za-z0-9][A-Za-z0-9_.+\-]{0,127}"),)),
    NamedSimpleType("Text", "Free text, 1 to 1000 characters.", "xs:string",
                    (("minLength", "1"), ("maxLength", "1000"))),
    NamedSimpleType("FilePath", "A file path, relative to the folder of this XML file "
                    "unless absolute; '/' works as the separator on every system.",
                    "xs:string", (("minLength", "1"), ("maxLength", "4096"))),
    NamedSimpleType("SchemaVersion", "The schema versions this file format defines: 1.0.",
                    "xs:string", (("enumeration", "1.0"),)),
    NamedSimpleType("ImageSuffix", "Text added to an image name before its extension "
                    "(IMG_00001.png becomes IMG_00001_F.png with _F): 1 to 32 letters, "
                    "digits, '_', '.', '+' or '-'.", "xs:string",
                    (("pattern", r"[A-Za-z0-9_.+\-]{1,32}"),)),
)
