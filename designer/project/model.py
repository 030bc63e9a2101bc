"""The project model: a survey description in photogrammetric terms, Qt-free and bpy-free.

It mirrors ``schema/designer-project-1.0.xsd`` one to one (element ``focal-length-mm``
is field ``focal_length_mm``), and the schema is written from it
(``python -m designer.project.xsd_gen``): each class's declarations
(designer.project.declare, .declare_structure) give its element's attributes and
children, and the first paragraph of its docstring is the element's documentation —
what ``designer check`` quotes — so it speaks of the file (min-height-m), later
paragraphs of the code (``min_height_m``). Conventions (docs/conventions.md):

* every coordinate is a **world** coordinate in metres, X = Easting, Y = Northing,
  Z = height; the origin (E0, N0, H0) is only subtracted for Blender;
* angles are **degrees** here, as in the file (``*_deg``); R = Rx(ω)·Ry(φ)·Rz(κ) maps
  the photogrammetric camera frame (x right, y up, z backwards) to world;
* focal length, sensor and principal point in mm, image sizes in px;
* file paths are stored as written (relative to the XML file's folder).

All classes are frozen dataclasses holding tuples, so a project is a value: two
projects are equal when every field is. Construction does not validate; call
:func:`designer.project.validate.semantic_problems` (or load through
:func:`designer.project.load.load_project`) for that.
"""

from __future__ import annotations

import typing
from dataclasses import MISSING, dataclass
from typing import Literal

from designer.project.declare import SEED_RANGE, attr, element, group
from designer.project.declare_structure import (
    Choice,
    ListOf,
    OneOf,
    Wrapper,
    XsdAttr,
    nested,
    schema_attrs,
    xml_type,
)
from designer.project.processing import (  # noqa: F401  (part of the model's face)
    POSITION_PRIOR_SIGMAS_M,
    Calibration,
    ControlSelection,
    GcpProcessing,
    Matching,
    PositionPrior,
    PreCalibrationError,
    Processing,
    Sfm,
)

SCHEMA_VERSION = "1.0"

Role = Literal["control", "check"]
TargetShape = Literal["checker", "cross", "circle", "square"]
TexturePattern = Literal["grass", "soil", "gravel", "noise", "checkerboard", "slanted-edge"]
Interpolation = Literal["closest", "linear"]
Preset = Literal["draft", "survey", "metrology"]
PixelFilterType = Literal["box", "gaussian", "blackman-harris"]
ImageFormat = Literal["png", "jpeg", "tiff", "exr"]
ImageMetadata = Literal["none", "exif"]
GroundTruthFormat = Literal["colmap", "odm", "metashape", "opk", "gcp"]
Orientation = Literal["landscape", "portrait"]
StartCorner = Literal["SW", "SE", "NW", "NE"]

#: samples per pixel of each render preset (render/samples overrides it)
PRESET_SAMPLES = {"draft": 4, "survey": 16, "metrology": 64}


# ---------------------------------------------------------------------- project level
#: the range of a world coordinate X or Y, and of a world height Z (m)
COORDINATE_RANGE = (-1e8, 1e8)
HEIGHT_RANGE = (-12000, 100000)


@element("origin", title="project origin", path="origin")
@xml_type(named=True)
@dataclass(frozen=True)
class Origin:
    """Project origin (world frame, m), kept in float64. Geometry handed to Blender
    is local = world - origin, so choose a point near the survey area. It does not
    change the meaning of any coordinate in this file."""

    E0: float = attr(doc="easting of the origin", unit="m", range=COORDINATE_RANGE, xml="E0",
                     decimals=3, step=1)
    N0: float = attr(doc="northing of the origin", unit="m", range=COORDINATE_RANGE,
                     xml="N0", decimals=3, step=1)
    H0: float = attr(doc="height of the origin", unit="m", range=HEIGHT_RANGE, xml="H0",
                     decimals=3, step=1)


@dataclass(frozen=True)
class Point3:
    """A world point (m): X = Easting, Y = Northing, Z = height; an attribute group (the
    X, Y, Z attributes of the element that holds it)."""

    X: float = attr(doc="easting, world frame", unit="m", range=COORDINATE_RANGE, xml="X")
    Y: float = attr(doc="northing, world frame", unit="m", range=COORDINATE_RANGE, xml="Y")
    Z: float = attr(doc="height, world frame", unit="m", range=HEIGHT_RANGE, xml="Z")


# ---------------------------------------------------------------------- terrain
@element("extent", title="terrain extent", path="scene.terrain.extent")
@dataclass(frozen=True)
class Extent:
    """Rectangle of ground covered by the terrain, world frame, m (min-X < max-X,
    min-Y < max-Y). A DEM or mesh file must cover it; GCP targets must lie inside
    it."""

    min_X: float = attr(doc="west edge (easting)", unit="m", range=COORDINATE_RANGE,
                        xml="min-X")
    min_Y: float = attr(doc="south edge (northing)", unit="m", range=COORDINATE_RANGE,
                        xml="min-Y")
    max_X: float = attr(doc="east edge (easting)", unit="m", range=COORDINATE_RANGE,
                        xml="max-X")
    max_Y: float = attr(doc="north edge (northing)", unit="m", range=COORDINATE_RANGE,
                        xml="max-Y")

    @property
    def width_m(self) -> float:
        return self.max_X - self.min_X

    @property
    def length_m(self) -> float:
        return self.max_Y - self.min_Y

    def contains(self, X: float, Y: float) -> bool:
        return self.min_X <= X <= self.max_X and self.min_Y <= Y <= self.max_Y


@element("flat", title="flat terrain")
@dataclass(frozen=True)
class FlatTerrain:
    """A horizontal plane."""

    height_m: float = attr(doc="height Z of the plane, world frame", unit="m",
                           range=HEIGHT_RANGE)


@element("procedural", title="procedural terrain")
@dataclass(frozen=True)
class ProceduralTerrain:
    """Generated smooth hills (octaves of noise fixed to the world) on a regular grid
    over the extent; every height lies between min-height-m and max-height-m (world
    Z, m), a terrain a few hill sizes across reaches about 90 % of that range.

    The largest hills are ``hill_size_m`` across (:mod:`designer.scene.terrain`)."""

    seed: int = attr(doc="random seed of the relief", range=SEED_RANGE)
    grid_spacing_m: float = attr(doc="distance between grid nodes; the extent's width and "
                                 "length must be whole multiples of it", unit="m",
                                 range=(0, 1e6), low_open=True, label="grid spacing")
    roughness: float = attr(doc="0 (rolling hills) to 1 (rugged ground)", range=(0, 1))
    min_height_m: float = attr(doc="lowest terrain height, world Z", unit="m",
                               range=HEIGHT_RANGE, label="lowest")
    max_height_m: float = attr(doc="highest terrain height, world Z (at least "
                               "min-height-m)", unit="m", range=HEIGHT_RANGE, label="highest")
    hill_size_m: float = attr(100.0, doc="wavelength of the largest hills", unit="m",
                              range=(0, 1e6), low_open=True)


def _file(doc: str):
    """A declared, required file path (relative to the XML file's folder)."""
    return attr(doc=doc, xsd="d:FilePath")


@element("dem", title="DEM terrain")
@dataclass(frozen=True)
class DemTerrain:
    """A digital elevation model file: GeoTIFF (.tif, .tiff) or ESRI ASCII grid
    (.asc), heights in world Z (m) on a grid in world X/Y. Each cell's value is the
    height at the cell centre. A GeoTIFF in another CRS than project/crs (another
    UTM zone, or geographic degrees such as EPSG:4326) is reprojected into it with
    bilinear heights; a GeoTIFF without a CRS is refused when project/crs names one.
    Only the cells over the extent must hold heights (nodata elsewhere is fine)."""

    file: str = _file("the DEM file, relative to this XML file's folder")


@element("mesh", title="mesh terrain")
@dataclass(frozen=True)
class MeshTerrain:
    """A terrain mesh file (.ply, .obj or .stl) whose vertices are world coordinates
    minus the project origin (m)."""

    file: str = _file("the mesh file, relative to this XML file's folder")


TerrainSource = FlatTerrain | ProceduralTerrain | DemTerrain | MeshTerrain


#: what is rendered beyond the declared terrain (:mod:`designer.scene.surroundings`):
#: "auto" continues the terrain as far as the images see (procedural and flat terrain
#: continue their own heights; a DEM its edge heights, an orthophoto its edge colours);
#: "none" renders the declared terrain only
SurroundingsMode = Literal["auto", "none"]
SURROUNDINGS_MODES: tuple[str, ...] = typing.get_args(SurroundingsMode)


@element("terrain", title="terrain")
@xml_type(named=True, holders={
    "surroundings": ("What is rendered beyond the extent, so that the images see "
                     "ground in every pixel below the horizon as a real flight does. "
                     "auto (the default for flat and procedural terrain): the terrain "
                     "continues as far as any image of the project sees, procedural "
                     "hills and textures as they are fixed to the world, a DEM at its "
                     "edge heights with an orthophoto's edge colours, and beyond a few"
                     " kilometres a plain ground to the horizon; none (the default for"
                     " DEM and mesh files): only the extent is rendered and pixels "
                     "beyond it show the background. Statistics still cover the extent"
                     " (the area of interest).", True)})
@dataclass(frozen=True)
class Terrain:
    """The ground surface: its extent and one source of heights (flat, procedural,
    DEM file or mesh file)."""

    extent: Extent
    source: TerrainSource
    #: None: the terrain kind's default (auto for flat and procedural terrain, none for
    #: DEM and mesh files)
    surroundings: SurroundingsMode | None = attr(
        None, doc="auto: continue the terrain as far as the images see; none: render the "
        "extent only (none given: auto for flat and procedural terrain, none for DEM and "
        "mesh files)", child="surroundings", xml="mode", label="surroundings")

    @property
    def kind(self) -> str:
        return {FlatTerrain: "flat", ProceduralTerrain: "procedural",
                DemTerrain: "dem", MeshTerrain: "mesh"}[type(self.source)]


# ---------------------------------------------------------------------- texture
@element("image", title="texture image")
@dataclass(frozen=True)
class ImageTexture:
    """A texture image file (PNG, JPEG, TIFF, EXR or BMP); should be seamless when
    tiled. Its texel ground size is the tile size divided by the image size in px."""

    file: str = _file("the texture image file, relative to this XML file's folder")


@element("orthophoto", title="orthophoto")
@dataclass(frozen=True)
class OrthophotoTexture:
    """A georeferenced orthophoto (GeoTIFF, bands red, green, blue) draped exactly:
    each terrain point (world X, Y) takes the colour of the image pixel its
    geotransform puts there (GDAL convention: the geotransform gives the outer
    corner of the top-left pixel). It may cover another extent, at another
    resolution, than the DEM; it must cover the terrain extent. An image in another
    CRS than project/crs is transformed on the fly (its pixels are not resampled).
    Use interpolation 'linear'."""

    file: str = _file("the orthophoto (GeoTIFF), relative to this XML file's folder")


@element("procedural", title="procedural texture")
@dataclass(frozen=True)
class ProceduralTexture:
    """A generated, seamless texture."""

    pattern: TexturePattern = attr(doc="the generated pattern")
    seed: int = attr(doc="random seed of the pattern", range=SEED_RANGE)
    texel_size_m: float = attr(doc="ground size of one texel", unit="m", range=(0, 1e6),
                               low_open=True, label="texel size")


@element("variation", title="texture variation", path="scene.texture.variation")
@dataclass(frozen=True)
class TextureVariation:
    """A seeded, non-repeating large-scale variation over the tiled texture, fixed to
    the ground (world X, Y): the brightness varies by 1 +/- strength and the texture
    blends with two mirrored, shifted copies of itself, so the ground does not repeat
    with the tile. Without it the texture repeats exactly every tile (see
    docs/world.md).

    ``scale_m`` is the wavelength of the coarsest of ``octaves`` noise octaves (each
    next one half as long); ``strength`` (0..1) the brightness swing, 1 ± strength."""

    seed: int = attr(doc="the variation's random seed", range=SEED_RANGE)
    scale_m: float = attr(doc="wavelength of the coarsest variation, e.g. 2-3 tiles",
                          unit="m", range=(0, 1e6), low_open=True, xml="scale-m")
    strength: float = attr(doc="brightness swing, 1 ± strength", range=(0, 1))
    octaves: int = attr(4, doc="noise octaves, each next one half as long", range=(1, 8))


@element("texture", title="ground texture")
@xml_type(named=True, holders={
    "tiling": ("How many times the texture repeats across the terrain extent; tile "
               "size = extent / repeats (m).", False)})
@dataclass(frozen=True)
class Texture:
    """The ground's colour: an image file or a generated pattern, repeated (tiled) over
    the terrain extent; or a georeferenced orthophoto, placed on the ground by its
    own geotransform (no tiling).

    ``repeat_X × repeat_Y`` repeats over the extent; an orthophoto's repeats are 1, and
    ``variation`` is for tiled textures only."""

    source: ImageTexture | ProceduralTexture | OrthophotoTexture = nested(
        alone=(OrthophotoTexture,))
    repeat_X: int = attr(doc="repeats along X (Easting)", range=(1, 10000), child="tiling",
                         xml="repeat-X", label="repeats X")
    repeat_Y: int = attr(doc="repeats along Y (Northing)", range=(1, 10000), child="tiling",
                         xml="repeat-Y", label="repeats Y")
    interpolation: Interpolation = attr(doc="texture lookup between texels: closest (sharp "
                                        "texel edges, exact for checkerboards) or linear "
                                        "(bilinear)")
    variation: TextureVariation | None = None


# ---------------------------------------------------------------------- targets
@element("true", title="true target centre")
@dataclass(frozen=True)
class TruePosition:
    """True position of the target centre, world frame, m. Omit Z to drape the
    target on the terrain surface (its height is then computed from the terrain)."""

    X: float = attr(doc="easting of the target centre", unit="m", range=COORDINATE_RANGE,
                    xml="X")
    Y: float = attr(doc="northing of the target centre", unit="m", range=COORDINATE_RANGE,
                    xml="Y")
    Z: float | None = attr(None, doc="height of the target centre (none: on the terrain)",
                           unit="m", range=HEIGHT_RANGE, xml="Z")


#: the range of a standard deviation of a measured position (m)
SIGMA_RANGE = (0, 1e6)


@dataclass(frozen=True)
class Sigma3:
    """Standard deviations along X, Y, Z (m); an attribute group (sigma-X, sigma-Y,
    sigma-Z)."""

    X: float = attr(doc="standard deviation in X (Easting)", unit="m", range=SIGMA_RANGE,
                    xml="sigma-X")
    Y: float = attr(doc="standard deviation in Y (Northing)", unit="m", range=SIGMA_RANGE,
                    xml="sigma-Y")
    Z: float = attr(doc="standard deviation in Z (height)", unit="m", range=SIGMA_RANGE,
                    xml="sigma-Z")


@element("surveyed", title="surveyed target position")
@dataclass(frozen=True)
class SurveyedPosition:
    """Surveyed (measured) position handed to the SfM software, world frame, m, with
    its standard deviations."""

    position: Point3 = group()
    sigma: Sigma3 = group()


@element("target", title="GCP target")
@dataclass(frozen=True)
class Target:
    """One GCP target, identified by its id."""

    id: str = attr(doc="the target's id (unique)", xsd="d:Identifier")
    role: Role = attr(doc="control georeferences, check only measures accuracy")
    shape: TargetShape = attr(doc="the target's pattern")
    size_m: float = attr(doc="side (or diameter) of the target plate", unit="m",
                         range=(0, 1e6), low_open=True, label="size", decimals=3, step=0.1)
    true: TruePosition
    surveyed: SurveyedPosition | None = None


@element("survey-accuracy", title="simulated survey", path="scene.targets.survey_accuracy")
@dataclass(frozen=True)
class SurveyAccuracy:
    """Simulated GNSS/total-station survey: a target without a 'surveyed' element
    gets surveyed = true + Gaussian noise with these standard deviations (m).
    Required when any target lacks 'surveyed'."""

    sigma: Sigma3 = group()
    seed: int = attr(doc="random seed of the simulated survey errors", range=SEED_RANGE,
                     draw="survey-error")


@xml_type(named=True, content=("survey_accuracy", ...))
@dataclass(frozen=True)
class Targets:
    """Ground control point (GCP) targets laid out on the terrain."""

    targets: tuple[Target, ...] = ()
    survey_accuracy: SurveyAccuracy | None = None


# ---------------------------------------------------------------------- objects, light
#: the range of an ω, φ or κ of a photo or a placed object (deg)
ANGLE_RANGE = (-360, 360)


def _omega(doc: str = "rotation about the world X axis, counter-clockwise positive "
           "(first factor of R)"):
    return attr(doc=doc, unit="deg", range=ANGLE_RANGE, xml="omega", label="ω")


def _phi(doc: str = "rotation about the once-rotated Y axis (second factor of R)"):
    return attr(doc=doc, unit="deg", range=ANGLE_RANGE, xml="phi", label="φ")


def _kappa(doc: str = "rotation about the twice-rotated Z axis (third factor of R)"):
    return attr(doc=doc, unit="deg", range=ANGLE_RANGE, xml="kappa", label="κ")


@element("placement", title="object placement")
@dataclass(frozen=True)
class Placement:
    """Where the mesh goes: its local origin is put at (X, Y, Z) in the world frame
    (m), rotated by R = Rx(omega) . Ry(phi) . Rz(kappa) (degrees) and scaled
    uniformly."""

    position: Point3 = group()
    omega_deg: float = _omega()
    phi_deg: float = _phi()
    kappa_deg: float = _kappa()
    scale: float = attr(1.0, doc="uniform scale factor from mesh units to metres",
                        range=(0, 1e6), low_open=True)


@element("object", title="scene object")
@dataclass(frozen=True)
class SceneObject:
    """A mesh file placed in the world."""

    name: str = attr(doc="the object's name", xsd="d:Identifier")
    file: str = _file("the mesh file, relative to this XML file's folder")
    placement: Placement


@element("point", title="path point")
@dataclass(frozen=True)
class PathPoint:
    """A point of the path, in order of travel (at least two)."""

    X: float = attr(doc="world X (easting) of the point", unit="m", range=COORDINATE_RANGE,
                    xml="X")
    Y: float = attr(doc="world Y (northing) of the point", unit="m", range=COORDINATE_RANGE,
                    xml="Y")


#: the XML attributes of a moving object's ``size_m`` (length, width, height; m), the
#: hand-written part of ``<object>`` in ``<moving-objects>``
MOVING_SIZE_XML = ("length-m", "width-m", "height-m")

#: built-in moving-object shapes: name → (length, width, height) m (person: a cylinder of
#: diameter width; box: the object's own length-m/width-m/height-m)
MOVING_SHAPES = {"car": (4.5, 1.8, 1.5), "person": (0.5, 0.5, 1.75), "box": None}


@element("object", title="moving object")
@dataclass(frozen=True)
class MovingObject:
    """One moving object: a built-in shape (car, person, box) or a mesh file in the
    object's frame (origin at the base centre, +Y forward, +Z up, metres).

    A vehicle or person moving along a polyline ``path`` at ``speed_m_s`` from
    ``start_s`` seconds after take-off, standing on the terrain, heading along the path.
    Exactly one of ``shape`` (MOVING_SHAPES) and ``file`` (a mesh in the object's frame:
    origin at the base centre, +Y forward, +Z up, m). ``size_m`` (length, width,
    height) is required for a box and overrides a car's or person's size.
    ``albedo_rgb`` is the linear diffuse colour."""

    id: str = attr(doc="the object's id", xsd="d:Identifier")
    path: tuple[PathPoint, ...] = nested(doc="A polyline (world X/Y, m) travelled at "
                                         "speed-m-s (m/s) from start-s (seconds after "
                                         "take-off, default 0); before it starts the "
                                         "object waits at the first point, after the "
                                         "end at the last, or with loop=\"true\" it goes"
                                         " round the closed polyline again.",
                                         wrapper=Wrapper("path"))
    speed_m_s: float = attr(doc="speed along the path", unit="m/s", range=(0, 100),
                            low_open=True, child="path", label="speed", decimals=2, step=0.5)
    shape: str | None = attr("car", doc="a built-in shape (car, person, box)", absent=None)
    file: str | None = attr(None, doc="a mesh file in the object's frame", xsd="d:FilePath")
    size_m: tuple[float, float, float] | None = schema_attrs(
        None,
        XsdAttr("length-m", "Length along the direction of travel, m (required for a box).",
                "d:FiniteDouble"),
        XsdAttr("width-m", "Width across the direction of travel, m (a person's diameter).",
                "d:FiniteDouble"),
        XsdAttr("height-m", "Height above the ground, m.", "d:FiniteDouble"))
    start_s: float = attr(0.0, doc="when it starts along its path, after take-off", unit="s",
                          range=(0, None), child="path", write_default=False,
                          label="starts at", decimals=1, step=1)
    loop: bool = attr(False, doc="go round the path again", child="path",
                      write_default=False)
    albedo_rgb: tuple[float, float, float] = schema_attrs(
        (0.85, 0.82, 0.78),
        XsdAttr("albedo-rgb", "Linear diffuse colour: three numbers from 0 to 1 (default 0.85 "
                "0.82 0.78).", "xs:string"))


#: roof shapes of an extruded building (docs/world.md, Buildings and structures)
ROOF_SHAPES = ("flat", "gable", "hip")


@element("building", title="building")
@dataclass(frozen=True)
class Building:
    """One building: a footprint extruded to eave-height-m with a roof, or a mesh
    file (file, X, Y, heading-deg).

    A building standing on the terrain: its base is the lowest terrain height under
    its footprint, its walls go down to it. Either an extruded ``footprint`` (a simple
    polygon, world X/Y m) with a ``roof`` (ROOF_SHAPES): walls up to ``eave_height_m``
    above the base, a gable or hip roof rising to ``ridge_height_m`` above the base
    (rectangular footprints only) with the ridge along ``ridge_direction_deg``
    (clockwise from grid north; None: along the longer side) — or a mesh ``file`` in the
    building's frame (origin at the base centre, +Y forward, +Z up, m) placed with its
    origin at ``position`` (X, Y) turned by ``heading_deg`` (clockwise from grid north)."""

    id: str = attr(doc="the building's id", xsd="d:Identifier")
    footprint: tuple[PathPoint, ...] = nested((), doc="The footprint polygon: world X Y pairs "
                                              "(m), space separated, at least three "
                                              "vertices, not self-intersecting, either"
                                              " orientation, not closed (the last "
                                              "vertex is joined to the first). A gable"
                                              " or hip roof needs a rectangle (four "
                                              "vertices, right angles).",
                                              xsd="xs:string")
    roof: str = attr("flat", doc="roof shape of an extruded building (flat, gable, hip)")
    eave_height_m: float = attr(6.0, doc="wall height above the base", unit="m",
                                range=(0, 500), low_open=True, label="walls", decimals=2,
                                step=0.5)
    ridge_height_m: float | None = attr(None, doc="ridge height above the base (pitched "
                                        "roofs, above the eaves)", unit="m", range=(0, 500),
                                        low_open=True, label="ridge", decimals=2, step=0.5)
    ridge_direction_deg: float | None = attr(None, doc="ridge direction, clockwise from grid "
                                             "north (none: along the longer side)",
                                             unit="deg", label="ridge direction",
                                             decimals=1, step=5)
    file: str | None = attr(None, doc="a mesh file in the building's frame",
                             xsd="d:FilePath")
    position: PathPoint | None = schema_attrs(
        None, XsdAttr("X", "World X (easting) of a mesh building's origin, m.", "d:FiniteDouble"),
        XsdAttr("Y", "World Y (northing) of a mesh building's origin, m.", "d:FiniteDouble"))
    heading_deg: float = attr(0.0, doc="turn of a mesh building, clockwise from grid north",
                              unit="deg", label="heading", decimals=1, step=5)


#: built-in plant kinds: name → (height, crown diameter) m defaults
PLANT_KINDS = {"grass-tuft": (0.3, 0.2), "shrub": (1.0, 1.2), "tree": (8.0, 5.0)}


@element("plants", title="plant group", first=("kind", "mesh"))
@dataclass(frozen=True)
class PlantGroup:
    """One group of plants: a built-in kind (grass-tuft, shrub, tree) or a mesh file
    in the plant's frame (origin at the base centre, +Z up, metres).

    Plants of one kind scattered over the terrain at ``density_per_m2`` (plants per
    m²): exactly one of ``kind`` (PLANT_KINDS) and ``mesh`` (a mesh file in the plant's
    frame: origin at the base centre, +Z up, m). Each plant's height is drawn from a
    normal distribution (``height_m`` ± ``height_sd_m``, m; None: the kind's default or
    the mesh's own height); its crown diameter ``crown_m`` (m; None: the kind's default
    or the mesh's width) scales with its height. ``albedo_rgb`` (linear; None: the
    kind's green) is the foliage colour."""

    density_per_m2: float = attr(doc="plants per m²", unit="/m²", range=(0, 100),
                                 low_open=True, label="density", decimals=4, step=0.01)
    kind: str | None = attr("shrub", doc="a built-in plant kind (grass-tuft, shrub, tree)",
                            absent=None)
    mesh: str | None = attr(None, doc="a mesh file in the plant's frame", xsd="d:FilePath")
    height_m: float | None = attr(None, doc="mean plant height (none: the kind's or the "
                                  "mesh's)", unit="m", range=(0, 150), low_open=True,
                                  label="height", decimals=2, step=0.1)
    height_sd_m: float = attr(0.0, doc="σ of the plant heights (at most the mean height)",
                              unit="m", range=(0, 150), label="height spread", decimals=2,
                              step=0.05)
    crown_m: float | None = attr(None, doc="crown diameter (none: the kind's or the mesh's "
                                 "width)", unit="m", range=(0, 100), low_open=True,
                                 label="crown", decimals=2, step=0.1)
    albedo_rgb: tuple[float, float, float] | None = schema_attrs(
        None, XsdAttr("albedo-rgb", "Linear foliage colour: three numbers from 0 to 1 "
                      "(default: the kind's green).", "xs:string"))


@element("wind", title="wind", path="scene.vegetation.wind")
@dataclass(frozen=True)
class Wind:
    """Each plant turns about its base by amplitude-deg · sin(2π t / gust-period-s + its
    own phase), leaning towards direction-deg, at each photo's time t on the
    trajectory's time line; without a time line the plants stand upright."""

    amplitude_deg: float = attr(5.0, doc="largest lean of a plant from upright", unit="deg",
                                range=(0, 45), label="sway amplitude", decimals=1,
                                step=1)
    gust_period_s: float = attr(4.0, doc="period of one sway", unit="s", range=(0, 3600),
                                low_open=True, label="gust period", decimals=2,
                                step=0.5)
    direction_deg: float = attr(90.0, doc="direction the wind blows to, clockwise from grid "
                                "north", unit="deg", range=(0, 360), high_open=True,
                                label="blowing towards", decimals=1, step=5)


@element("vegetation", title="vegetation", path="scene.vegetation")
@xml_type(named=True)
@dataclass(frozen=True)
class Vegetation:
    """Plants placed by a seeded Poisson process inside the terrain extent, standing on
    the terrain (base at the ground height below the plant's centre), kept clear of
    every GCP target plate; part of the true surface (DSM), not of the bare earth
    (DTM)."""

    plants: tuple[PlantGroup, ...]
    seed: int = attr(0, doc="the placement's random seed", range=SEED_RANGE)
    clearance_m: float = attr(0.5, doc="distance kept clear around every GCP target plate",
                              unit="m", range=(0, 100), label="clear of targets",
                              decimals=2, step=0.1)
    wind: Wind | None = None


@element("sun", title="sun direction")
@dataclass(frozen=True)
class Sun:
    """Sun direction."""

    azimuth_deg: float = attr(doc="sun azimuth, clockwise from grid north", unit="deg",
                              range=(0, 360), high_open=True, label="azimuth",
                              decimals=1, step=5)
    elevation_deg: float = attr(doc="sun elevation above the horizon", unit="deg",
                                range=(0, 90), low_open=True, label="elevation", decimals=1,
                                step=5)


@element("sun-position", title="sun for a moment and place")
@dataclass(frozen=True)
class SunPosition:
    """Sun direction computed for a moment and place on Earth."""

    date_time: str = attr(doc="the moment, ISO 8601 with a time zone", label="date, time",
                          xsd="xs:dateTime")
    latitude_deg: float = attr(doc="latitude of the site", unit="deg", range=(-90, 90),
                               label="latitude", decimals=5, step=0.1)
    longitude_deg: float = attr(doc="longitude of the site", unit="deg", range=(-180, 180),
                                label="longitude", decimals=5, step=0.1)


@element("sun-over-time", title="sun over time")
@dataclass(frozen=True)
class SunOverTime:
    """Sun direction computed for each photo's moment on the trajectory's time-line
    (which it needs), so shadows move during the flight. The place is the project
    origin converted to latitude and longitude with the CRS, unless both attributes
    are given; the azimuth is turned from true to grid north by the meridian
    convergence there. The light map is baked for each photo (docs/world.md)."""

    latitude_deg: float | None = attr(None, doc="latitude of the site (none: the origin's)",
                                      unit="deg", range=(-90, 90), label="latitude",
                                      decimals=5, step=0.1)
    longitude_deg: float | None = attr(None, doc="longitude of the site (none: the origin's)",
                                       unit="deg", range=(-180, 180), label="longitude",
                                       decimals=5, step=0.1)


@element("cloud-shadows", title="cloud shadows", path="scene.lighting.clouds")
@dataclass(frozen=True)
class CloudShadows:
    """Shadows of drifting clouds on the terrain: a seeded field of clouds moving
    with the wind over the flight's time line (frozen at take-off without one). Only
    the direct sun is dimmed (docs/world.md).

    Drifting cloud shadows on the terrain (docs/world.md): ``cover`` the shadowed
    fraction of the ground (0..1), ``size_m`` the clouds' typical size (m),
    ``softness_m`` the width of a shadow's edge (m, 10 % to 90 % of the depth),
    ``depth`` the share of the direct sun a cloud takes away (0..1), the wind's speed
    (m/s) and the direction it blows towards (deg clockwise from grid north), ``seed``
    the field's random seed."""

    cover: float = attr(0.3, doc="shadowed fraction of the ground", range=(0, 1),
                        label="cover", decimals=3, step=0.05)
    size_m: float = attr(40.0, doc="typical size of a cloud shadow", unit="m",
                         range=(0, 1e5), low_open=True, factor="cloud-size-m",
                         label="cloud size", decimals=1, step=5)
    softness_m: float = attr(5.0, doc="width of a shadow's edge, 10 % to 90 % of the depth",
                             unit="m", range=(0, 1e4), label="edge softness", decimals=2,
                             step=1)
    depth: float = attr(0.6, doc="share of the direct sun a cloud takes away", range=(0, 1),
                        factor="cloud-depth", label="shadow depth", decimals=3, step=0.05)
    wind_speed_m_s: float = attr(5.0, doc="speed the cloud shadows drift at", unit="m/s",
                                 range=(0, 100), factor="wind-speed-m-s", label="wind speed",
                                 decimals=2, step=0.5)
    wind_direction_deg: float = attr(90.0, doc="direction the cloud shadows drift towards, "
                                     "clockwise from grid north", unit="deg", range=(0, 360),
                                     high_open=True, factor="wind-direction-deg",
                                     label="wind towards", decimals=1, step=5)
    seed: int = attr(0, doc="the cloud field's random seed", range=SEED_RANGE,
                     draw="clouds")


@element("lighting", title="lighting", path="scene.lighting")
@xml_type(named=True)
@dataclass(frozen=True)
class Lighting:
    """Sun and sky. The sun is given by its direction, or computed from a date, time
    and place; optionally cloud shadows."""

    sun: Sun | SunPosition | SunOverTime
    sun_strength: float = attr(4.0, doc="sun irradiance in Blender units (about 3 to 5: a "
                               "sunny day)", unit="W/m²", range=(0, 1000),
                               label="sun strength", decimals=2, step=0.5)
    sky_strength: float = attr(1.0, doc="multiplier of the sky light (1: a clear sky)",
                               range=(0, 1000), label="sky strength", decimals=2, step=0.1)
    #: None: no clouds (the static ideal)
    clouds: CloudShadows | None = None


@xml_type(named=True, content=("terrain", "texture", ..., "lighting"))
@dataclass(frozen=True)
class Scene:
    """What the cameras see."""

    terrain: Terrain = nested(doc="The ground surface: extent (world X/Y, m) and "
                                  "heights (world Z, m).")
    texture: Texture = nested(doc="The ground texture, tiled over the terrain extent, "
                                  "or an orthophoto placed by its geotransform.")
    lighting: Lighting = nested(doc="Sun (azimuth and elevation in degrees, or date, "
                                    "time and place) and sky strength.")
    targets: Targets | None = nested(None, doc="Ground control point targets (world frame, m).")
    objects: tuple[SceneObject, ...] = nested(
        (), doc="Other objects: mesh files placed in the world frame.",
        wrapper=Wrapper("objects", "Objects", "Other objects placed in the scene (buildings, "
                        "validation bodies, ...)."))
    moving_objects: tuple[MovingObject, ...] = nested(
        (), doc="Vehicles and people moving along paths during the flight (needs a "
                "time line; docs/world.md).",
        wrapper=Wrapper("moving-objects", "MovingObjects", "Objects posed at each photo's time "
                        "on the trajectory's time line: they stand on the terrain and head "
                        "along their path."))
    buildings: tuple[Building, ...] = nested(
        (), doc="Buildings and structures standing on the terrain: extruded footprints"
                " with flat, gable or hip roofs, or mesh files (docs/world.md).",
        wrapper=Wrapper("buildings", "Buildings", "Buildings standing on the terrain. A "
                        "building's base is the lowest terrain height under its "
                        "footprint; its walls go down to it. Heights are metres above that base."))
    #: None: no plants (the static ideal)
    vegetation: Vegetation | None = nested(None, doc="Plants scattered over the terrain by a "
                                           "seeded process, kept off the GCP targets, "
                                           "optionally swaying in the wind "
                                           "(docs/world.md, Vegetation and wind).")


# ---------------------------------------------------------------------- cameras
def _coefficient(doc: str):
    """A declared distortion coefficient: dimensionless, -1000 to 1000, default 0."""
    return attr(0.0, doc=doc, range=(-1000, 1000), decimals=6, step=0.001)


@element("brown-conrady", title="Brown-Conrady distortion")
@dataclass(frozen=True)
class BrownConradyDistortion:
    """Brown-Conrady lens distortion with OpenCV's meaning (k1, k2, k3 radial; p1,
    p2 tangential) on normalised computer-vision coordinates (x/z, y/z). Omit the
    element for an ideal pinhole lens."""

    k1: float = _coefficient("radial coefficient of r²")
    k2: float = _coefficient("radial coefficient of r⁴")
    k3: float = _coefficient("radial coefficient of r⁶")
    p1: float = _coefficient("tangential coefficient p1 (OpenCV's order)")
    p2: float = _coefficient("tangential coefficient p2 (OpenCV's order)")


@element("fisheye-equidistant", title="equidistant fisheye distortion")
@dataclass(frozen=True)
class FisheyeEquidistantDistortion:
    """OpenCV's equidistant fisheye model: theta_d = theta (1 + k1 theta^2 + k2
    theta^4 + k3 theta^6 + k4 theta^8), theta the angle from the optical axis in
    radians."""

    k1: float = _coefficient("coefficient of θ²")
    k2: float = _coefficient("coefficient of θ⁴")
    k3: float = _coefficient("coefficient of θ⁶")
    k4: float = _coefficient("coefficient of θ⁸")


#: the order the rows of a rolling-shutter sensor are read in
RollingShutterDirection = Literal["top-to-bottom", "bottom-to-top"]


@element("rolling-shutter", title="rolling shutter")
@dataclass(frozen=True)
class RollingShutter:
    """A rolling-shutter sensor: the rows are read one after the other over readout-s
    seconds per frame while the camera moves along the flight's time line (a
    trajectory time-line is required). The photo's pose and time are those of the
    first row read; row r counted from it is exposed r / H x readout-s later (H the
    image height, px), the camera moving at the velocity of the leg it flies and
    keeping its attitude. Omitted, or readout-s 0: a global shutter. See
    docs/world.md, "Rolling shutter".

    Row r (counted from the first row read) is read at the photo's time + r / H ·
    ``readout_s``; ``readout_s`` 0 is a global shutter."""

    readout_s: float = attr(doc="time to read all rows of a frame (0: a global shutter)",
                            unit="s", range=(0, 0.5), label="readout", decimals=4,
                            step=0.005)
    direction: RollingShutterDirection = attr("top-to-bottom", doc="the order the rows are "
                                              "read in", label="rows read")


@element("camera", title="camera", first=("id", "name"))
@xml_type(named=True, holders={
    "sensor": ("Size of the imaging area of the sensor, mm.", False),
    "image": ("Full image size of the camera, px (render settings may scale it down).", False),
    "principal-point": ("Principal point offset from the sensor centre, mm, "
                        "photogrammetric image axes (x right, y up). Omitted means (0,"
                        " 0). In pixels: cx = W/2 + x0 W/sw, cy = H/2 - y0 H/sh.", True)})
@dataclass(frozen=True)
class Camera:
    """A camera: its interior orientation (mm, px), lens distortion and shutter.

    Interior orientation in photogrammetric terms (mm, px); see core.interior.
    ``rolling_shutter`` None (or a readout of 0): a global shutter. The ranges are the
    file's (the schema's Millimetres and PixelCount): what a field accepts, the file
    check accepts."""

    id: str = attr(doc="the camera's id, named by photos, flight plans and rig mounts",
                   xsd="d:Identifier")
    focal_length_mm: float = attr(doc="principal distance (calibrated focal length) of the "
                                  "lens, not the 35 mm-equivalent", unit="mm",
                                  range=(0, 1000), low_open=True, text=True,
                                  label="focal length", decimals=4, step=0.1)
    sensor_width_mm: float = attr(doc="sensor width along image x (columns)", unit="mm",
                                  range=(0, 1000), low_open=True, child="sensor",
                                  xml="width-mm", label="sensor width", decimals=4, step=0.1)
    sensor_height_mm: float = attr(doc="sensor height along image y (rows)", unit="mm",
                                   range=(0, 1000), low_open=True, child="sensor",
                                   xml="height-mm", label="sensor height", decimals=6,
                                   step=0.1)
    image_width_px: int = attr(doc="image width (columns)", unit="px", range=(1, 100000),
                               child="image", xml="width-px", label="image width")
    image_height_px: int = attr(doc="image height (rows)", unit="px", range=(1, 100000),
                                child="image", xml="height-px", label="image height")
    principal_point_x_mm: float = attr(0.0, doc="principal point offset from the sensor "
                                       "centre, x right", unit="mm", range=(-1000, 1000),
                                       child="principal-point", xml="x-mm",
                                       write_default=False, label="principal point x",
                                       decimals=4, step=0.01)
    principal_point_y_mm: float = attr(0.0, doc="principal point offset from the sensor "
                                       "centre, y up", unit="mm", range=(-1000, 1000),
                                       child="principal-point", xml="y-mm",
                                       write_default=False, label="principal point y",
                                       decimals=4, step=0.01)
    pixel_aspect: float | None = attr(None, doc="pixel height / pixel width (none: square "
                                      "pixels, checked against the sensor and image sizes)",
                                      range=(0, 100), low_open=True, text=True,
                                      label="pixel aspect", decimals=6, step=0.01)
    distortion: BrownConradyDistortion | FisheyeEquidistantDistortion | None = None
    name: str | None = attr(None, doc="make and model, e.g. 'DJI Phantom 4 Pro'", text=True,
                            xsd="d:Text")
    rolling_shutter: RollingShutter | None = None

    @property
    def readout_s(self) -> float:
        """Rolling-shutter readout time per frame (s); 0 for a global shutter."""
        return self.rolling_shutter.readout_s if self.rolling_shutter is not None else 0.0


# ---------------------------------------------------------------------- trajectory
@element("photo", title="photo", first=("name", "camera"))
@dataclass(frozen=True)
class ExteriorOrientation:
    """One photo: perspective centre (X, Y, Z) in the world frame (m) and
    orientation omega, phi, kappa (degrees), R = Rx(omega) . Ry(phi) . Rz(kappa)
    mapping camera to world."""

    name: str = attr(doc="image file name, unique in the project, e.g. IMG_0001.png",
                     xsd="d:Identifier")
    camera: str = attr(doc="id of the camera that takes this photo, or the name of a rig: "
                       "then one image per mount, named with the mount's suffix",
                       xsd="d:Identifier")
    X: float = attr(doc="easting of the perspective centre, world frame", unit="m",
                    range=COORDINATE_RANGE, xml="X")
    Y: float = attr(doc="northing of the perspective centre, world frame", unit="m",
                    range=COORDINATE_RANGE, xml="Y")
    Z: float = attr(doc="height of the perspective centre, world frame", unit="m",
                    range=HEIGHT_RANGE, xml="Z")
    omega_deg: float = _omega()
    phi_deg: float = _phi()
    kappa_deg: float = _kappa()
    time_s: float | None = attr(None, doc="seconds after takeoff-utc on the time-line when "
                                "this photo is taken (needs a time-line; none: flown in "
                                "order at its speed)", unit="s", range=(0, 1e7))


@element("pose-noise", title="pose noise", path="trajectory.flight_plan.pose_noise")
@dataclass(frozen=True)
class PoseNoise:
    """Gaussian noise added to each planned pose, as a real aircraft never flies the
    plan exactly: position C' = C + N(0, sigma^2) per world axis (m); rotation R' =
    R . Exp(delta), delta ~ N(0, sigma^2) per camera axis x, y, z (degrees), close
    to omega, phi, kappa noise at nadir."""

    sigma_X_m: float = attr(0.0, doc="σ of the flown position along X (Easting)", unit="m",
                            range=(0, 1e6), label="σ X", decimals=3, step=0.01)
    sigma_Y_m: float = attr(0.0, doc="σ of the flown position along Y (Northing)", unit="m",
                            range=(0, 1e6), label="σ Y", decimals=3, step=0.01)
    sigma_Z_m: float = attr(0.0, doc="σ of the flown position along Z (height)", unit="m",
                            range=(0, 1e6), label="σ Z", decimals=3, step=0.01)
    sigma_omega_deg: float = attr(0.0, doc="σ of the flown rotation about the camera x axis",
                                  unit="deg", range=(0, 90), label="σ ω", decimals=3,
                                  step=0.01)
    sigma_phi_deg: float = attr(0.0, doc="σ of the flown rotation about the camera y axis",
                                unit="deg", range=(0, 90), label="σ φ", decimals=3,
                                step=0.01)
    sigma_kappa_deg: float = attr(0.0, doc="σ of the flown rotation about the camera z axis",
                                  unit="deg", range=(0, 90), label="σ κ", decimals=3,
                                  step=0.01)


@element("flight-plan", title="grid flight plan", path="trajectory.flight_plan")
@xml_type(named=True, content=("area", Choice(("altitude_agl_m", "gsd_m")), ...))
@dataclass(frozen=True)
class FlightPlan:
    """A grid (lawn-mower) flight over a polygon; photo positions follow from the
    camera, the height or GSD and the overlaps.

    A grid flight over ``area`` (world X/Y vertices, m); exactly one of altitude/GSD.
    Its values are the texts of child elements (``text=True``) but for ``camera`` and
    ``image_prefix``; the area, the altitude reference and the pose noise are
    hand-written parts of the reader and writer."""

    camera: str = attr(doc="id of the camera flown, or the name of a rig (e.g. a nadir camera "
                       "or an oblique rig)", xsd="d:Identifier", factor="flight-camera")
    image_prefix: str = attr(doc="planned photos are named prefix + 5-digit number + "
                             "extension", xsd="d:Identifier")
    area: tuple[tuple[float, float], ...] = nested(
        doc="Polygon to cover, world X/Y (m), at least 3 vertices in order, not "
            "self-intersecting.",
        wrapper=Wrapper("area"), tag="vertex", item_doc="A corner of the area, world frame, m.",
        item_attrs=(XsdAttr("X", "Easting, m.", "d:Coordinate", True),
                    XsdAttr("Y", "Northing, m.", "d:Coordinate", True)), min_items=3)
    altitude_agl_m: float | None = attr(None, doc="flying height above ground level "
                                        "(exactly one of it and gsd-m)", unit="m",
                                        range=(0, 1e6), low_open=True, text=True,
                                        label="height above ground", decimals=2, step=1)
    gsd_m: float | None = attr(None, doc="ground sample distance of the images at nadir "
                               "(exactly one of it and altitude-agl-m)", unit="m/px",
                               range=(0, 1e6), low_open=True, text=True,
                               label="ground sample distance",
                               decimals=4, step=0.001)
    front_overlap_percent: float = attr(80.0, doc="forward overlap of consecutive images",
                                        unit="%", range=(0, 95), text=True,
                                        factor="front-overlap-percent",
                                        label="front overlap", decimals=1, step=5)
    side_overlap_percent: float = attr(70.0, doc="overlap of neighbouring flight lines",
                                       unit="%", range=(0, 95), text=True,
                                       factor="side-overlap-percent", label="side overlap",
                                       decimals=1, step=5)
    grid_angle_deg: float = attr(0.0, doc="direction of the flight lines, clockwise from grid "
                                 "north", unit="deg", range=(0, 180), high_open=True,
                                 text=True, label="line azimuth", decimals=1, step=5)
    crosshatch: bool = attr(False, doc="fly the grid a second time at 90 degrees", text=True,
                            factor="crosshatch")
    orientation: Orientation = attr("landscape", doc="landscape: image top along the flight "
                                    "direction; portrait: image right along it", text=True)
    start_corner: StartCorner = attr("SW", doc="corner of the area where the first line "
                                     "starts", text=True)
    terrain_following: bool = attr(False, doc="every photo at altitude-agl-m above the "
                                   "terrain below it", text=True)
    #: "mean" | "max" | "min" of the terrain in the area, or a world height Z (m)
    altitude_reference: str | float = nested(
        "mean", doc="Ground height the constant-height flight is measured from "
                    "(ignored with terrain following): mean (default), max or min of "
                    "the terrain inside the area, or a height (world Z, m).",
        xsd=OneOf(("d:Height",), ("mean", "max", "min")))
    tilt_deg: float = attr(0.0, doc="forward camera tilt from nadir", unit="deg",
                           range=(-80, 80), text=True, factor="tilt-deg", label="forward tilt",
                           decimals=1, step=5)
    pose_noise: PoseNoise | None = None
    random_seed: int = attr(0, doc="seed of the pose noise", range=SEED_RANGE, text=True,
                            draw="pose-noise")


@element("time-line", title="time line", path="trajectory.time_line")
@xml_type(named=True)
@dataclass(frozen=True)
class TimeLine:
    """The flight's clock: the first photo is taken at takeoff-utc, then the stations
    (explicit photos, then the flight plan) are flown in order along straight legs at
    speed-m-s, with turn-s added at each change of flight line. Photos are triggered
    by distance (at the planned stations); a photo's time-s overrides its computed
    time. docs/world.md.

    ``trigger_interval_s`` is the camera's shortest interval between photos (s), checked
    against the planned spacing (designer.survey.timeline)."""

    takeoff_utc: str = attr(doc="moment of the first photo, ISO 8601 UTC",
                            label="take-off (UTC)", xsd="xs:dateTime")
    speed_m_s: float = attr(doc="ground speed along the flight lines", unit="m/s",
                            range=(0, 100), low_open=True, factor="flight-speed-m-s",
                            label="ground speed", decimals=2, step=0.5)
    turn_s: float = attr(0.0, doc="seconds more at each change of flight line", unit="s",
                         range=(0, 3600), factor="turn-s", write_default=False,
                         label="per turn", decimals=1, step=1)
    trigger_interval_s: float | None = attr(None, doc="the camera's shortest interval "
                                            "between photos", unit="s", range=(0, 3600),
                                            low_open=True, label="trigger interval",
                                            decimals=2, step=0.1)


@element("mount", title="rig mount")
@dataclass(frozen=True)
class Mount:
    """One camera of the rig.

    One camera of a rig: the project camera ``camera`` mounted on the platform, rotated
    by ω φ κ (deg) relative to it — R_cam_to_world = R_platform · Rx(ω)·Ry(φ)·Rz(κ), the
    same convention as a photo's angles with the platform in place of the world. Its
    images are named as the station's with ``suffix`` before the extension
    (IMG_00001.png → IMG_00001_F.png)."""

    camera: str = attr(doc="the id of the project camera mounted", xsd="d:Identifier")
    suffix: str = attr(doc="added to the station's image name before the extension",
                       xsd="d:ImageSuffix")
    omega_deg: float = attr(0.0, doc="rotation about the platform's x axis", unit="deg",
                            range=(-180, 180), xml="omega", label="ω")
    phi_deg: float = attr(0.0, doc="rotation about the platform's y axis", unit="deg",
                          range=(-180, 180), xml="phi", label="φ")
    kappa_deg: float = attr(0.0, doc="rotation about the platform's z axis", unit="deg",
                            range=(-180, 180), xml="kappa", label="κ")


@element("rig", title="camera rig")
@xml_type(named=True)
@dataclass(frozen=True)
class Rig:
    """Cameras fired together at each station, sharing its perspective centre. The
    station's pose is the platform's; each mount's camera is turned by its omega,
    phi, kappa relative to the platform: R_cam_to_world = R_platform . Rx(omega) .
    Ry(phi) . Rz(kappa) (omega = phi = kappa = 0: the camera looks where the platform
    looks, image top forward)."""

    name: str = attr(doc="the rig's name, used as the camera of photos and flight plans",
                     xsd="d:Identifier")
    mounts: tuple[Mount, ...]


def _pattern_camera():
    return attr(doc="id of the camera flown, or the name of a rig (one image per mount at "
                "each station)", xsd="d:Identifier")


def _pattern_prefix():
    return attr(doc="photos are named prefix + 5-digit number (from 00001, in flight order) "
                "+ the output format's extension", xsd="d:Identifier")


@element("orbit", title="orbit flight")
@xml_type(named="Orbit")
@dataclass(frozen=True)
class OrbitPattern:
    """Stations evenly spaced on a circle around the point of interest (X, Y, Z;
    world, m), clockwise seen from above, each camera facing the centre with its
    image top away from the ground. docs/world.md.

    Stations on a circle around a point of interest ``centre`` (world, m): radius
    ``radius_m``, ``height_m`` above the centre, ``n_stations`` evenly spaced clockwise
    from ``start_azimuth_deg`` (the station's direction from the centre, clockwise from
    grid north). Each camera faces the centre, image top away from the ground, tilted
    ``tilt_deg`` from nadir (None: aimed exactly at the centre). ``camera`` is a camera
    id or a rig name; images are named ``image_prefix`` + 5-digit number."""

    camera: str = _pattern_camera()
    image_prefix: str = _pattern_prefix()
    centre: Point3 = group()
    radius_m: float = attr(doc="horizontal distance of the stations from the centre",
                           unit="m", range=(0, 1e6), low_open=True, label="radius")
    height_m: float = attr(doc="height of the stations above the centre", unit="m",
                           range=(-1000, 10000), label="height")
    n_stations: int = attr(doc="number of stations on the circle", range=(1, 10000),
                           xml="stations", label="stations")
    tilt_deg: float | None = attr(None, doc="viewing axis from nadir towards the centre (90: "
                                  "level; none: aimed exactly at the centre)", unit="deg",
                                  range=(0, 90), label="tilt from nadir")
    start_azimuth_deg: float = attr(0.0, doc="direction of the first station from the "
                                    "centre, clockwise from grid north", unit="deg",
                                    range=(-360, 360), label="first station at")


FacadeSide = Literal["left", "right"]


@element("facade", title="facade flight")
@xml_type(named="Facade", lead=("start", "end", "heights_m"))
@dataclass(frozen=True)
class FacadePattern:
    """Rows of stations parallel to a facade segment (X1, Y1) to (X2, Y2) at
    distance-m from it, on its side as seen walking from the first point to the
    second, one every spacing-m along it, one row per height in heights-m above
    base-Z; rows are flown back and forth. Each camera faces the facade, tilt-deg
    below the horizontal. docs/world.md.

    Rows of stations along a facade from ``start`` to ``end`` (world X, Y, m), on its
    ``side`` (seen walking from start to end) at ``distance_m`` from it, every
    ``spacing_m`` along it, one row per height in ``heights_m`` above ``base_Z`` (world
    Z of the ground there, m), rows flown back and forth. Each camera faces the facade,
    ``tilt_deg`` below the horizontal (0: level). ``camera`` is a camera id or a rig
    name; images are named ``image_prefix`` + 5-digit number."""

    camera: str = _pattern_camera()
    image_prefix: str = _pattern_prefix()
    start: tuple[float, float] = schema_attrs(
        MISSING,
        XsdAttr("X1", "Easting of the facade's first end, world frame, m.", "d:Coordinate", True),
        XsdAttr("Y1", "Northing of the facade's first end, world frame, m.", "d:Coordinate",
                True))
    end: tuple[float, float] = schema_attrs(
        MISSING,
        XsdAttr("X2", "Easting of the facade's second end, world frame, m.", "d:Coordinate",
                True),
        XsdAttr("Y2", "Northing of the facade's second end, world frame, m.", "d:Coordinate",
                True))
    base_Z: float = attr(doc="world Z of the ground at the facade; the rows' heights are "
                         "above it", unit="m", range=COORDINATE_RANGE, xml="base-Z")
    distance_m: float = attr(doc="horizontal distance of the stations from the facade",
                             unit="m", range=(0, 1e6), low_open=True, label="distance")
    heights_m: tuple[float, ...] = schema_attrs(
        MISSING, XsdAttr("heights-m", "Heights of the rows above base-Z, m, space "
                                 "separated, e.g. \"3 6 9\".",
                         ListOf("d:FiniteDouble", 1, 1000), True))
    spacing_m: float = attr(doc="distance between two stations of a row", unit="m",
                            range=(0, 1e6), low_open=True, label="spacing")
    side: FacadeSide = attr("right", doc="where the stations stand, seen walking from the "
                            "first end to the second")
    tilt_deg: float = attr(0.0, doc="viewing axis below the horizontal (0: level)",
                           unit="deg", range=(-45, 80), label="tilt below level")


FlightPattern = OrbitPattern | FacadePattern


@xml_type(named=True, content=("rigs", ..., "time_line"))
@dataclass(frozen=True)
class Trajectory:
    """Where the photos are taken: explicit exterior orientations, a flight plan, or
    both; optionally multi-camera rigs they fly."""

    exterior_orientations: tuple[ExteriorOrientation, ...] = nested(
        (), doc="Photos with explicit poses: X, Y, Z (world, m), omega, phi, kappa "
                "(degrees).",
        wrapper=Wrapper("exterior-orientations", "ExteriorOrientations",
                        "Photos with exactly known poses (no pose noise is added)."))
    flight_plan: FlightPlan | None = nested(None, doc="A grid flight plan.")
    time_line: TimeLine | None = nested(None, doc="When each photo is taken. Without it the "
                                        "photos have no time (the static ideal).")
    #: multi-camera rigs a photo or the flight plan may name instead of a camera
    rigs: tuple[Rig, ...] = nested((), doc="A multi-camera rig (e.g. nadir + four 45 degree "
                                 "obliques): a photo or the flight plan whose camera "
                                 "attribute names the rig takes one image per mount at"
                                 " each station. docs/world.md.")
    #: orbit and facade flights, flown after the photos and the flight plan
    patterns: tuple[FlightPattern, ...] = nested((), member_docs={
        OrbitPattern: "Stations on a circle around a point of interest, flown after the photos and "
        "the flight plan.",
        FacadePattern: "Rows of stations along a facade, flown after the photos and the flight "
                       "plan."})

    def rig(self, name: str) -> Rig | None:
        """The rig of this name, or None (a plain camera id)."""
        return next((r for r in self.rigs if r.name == name), None)


# ---------------------------------------------------------------------- effects, render
@element("vignetting", title="vignetting", path="effects.vignetting", on={"corner_falloff": 0.2})
@dataclass(frozen=True)
class Vignetting:
    """Darkening towards the image corners, fixed to the sensor: gain = [cos^4 theta] x
    (1 - corner-falloff rho^2 + rho4 rho^4 + rho6 rho^6), rho the distance from the
    principal point on the sensor divided by the distance to the farthest image
    corner (rho = 1 there), theta the angle of the pixel's ray to the optical axis
    (from the camera's distortion model). The gain must stay between 0 and 1 over the
    image (checked)."""

    corner_falloff: float = attr(0.0, doc="gain lost at the farthest corner (ρ² term)",
                                 range=(0, 1), label="corner fall-off (ρ²)", step=0.05)
    rho4: float = attr(0.0, doc="ρ⁴ term of the gain", range=(-1, 1), write_default=False,
                       label="ρ⁴ term", step=0.05)
    rho6: float = attr(0.0, doc="ρ⁶ term of the gain", range=(-1, 1), write_default=False,
                       label="ρ⁶ term", step=0.05)
    natural_cos4: bool = attr(False, doc="natural cos⁴ fall-off of the lens",
                              write_default=False, xml="natural-cos4",
                              label="natural cos⁴ fall-off of the lens")


@element("defocus", title="defocus (thin lens)", path="effects.defocus",
         on={"f_number": 2.8, "focus_distance_m": 50.0})
@dataclass(frozen=True)
class Defocus:
    """Thin-lens defocus: a uniform disc point spread function of diameter c = f^2
    |d - s| / (N d (s - f)) on the sensor, f the focal length, N the f-number, s the
    focus distance and d the object distance (per image: the distance along the
    optical axis to the ground at the principal point, unless object-distance-m is
    given)."""

    f_number: float = attr(doc="aperture f-number", range=(0.5, 64), label="f-number",
                           decimals=2, step=0.5)
    focus_distance_m: float = attr(doc="distance the lens is focused at", unit="m",
                                   range=(0.1, 1e6), label="focused at", decimals=2, step=1)
    object_distance_m: float | None = attr(None, doc="distance of the ground (none: each "
                                           "image's own)", unit="m", range=(0.1, 1e6),
                                           label="object distance", decimals=2, step=1)


@element("sensor-noise", title="sensor noise (Gaussian, in DN)", path="effects.sensor_noise",
         on={"sigma_dn": 1.5})
@dataclass(frozen=True)
class SensorNoise:
    """Gaussian sensor noise added to every pixel."""

    sigma_dn: float = attr(doc="σ of additive Gaussian noise, 8-bit digital numbers",
                           unit="DN", range=(0, 100), label="σ", decimals=2, step=0.5)
    seed: int = attr(0, doc="the noise's random seed", range=SEED_RANGE,
                     draw="sensor-noise")


@element("sensor", title="sensor (photon shot noise, dark current, read noise, ADC)",
         path="effects.sensor", on={"full_well_e": 20000.0, "read_noise_e": 3.0})
@dataclass(frozen=True)
class Sensor:
    """A physical image sensor, applied in linear light after the optics: photon shot
    noise (Poisson), dark current, Gaussian read noise and quantisation by the ADC,
    then re-encoded to sRGB at the output bit depth. White in the render collects
    exposure-scale x full-well-e electrons. Each image draws its own noise from
    (seed, image index)."""

    full_well_e: float = attr(doc="electrons a pixel holds", unit="e⁻", range=(1, 1e7),
                              label="full well", decimals=0, step=1000)
    read_noise_e: float = attr(doc="σ of the read noise", unit="e⁻", range=(0, 1e4),
                               label="read noise", decimals=2, step=0.5)
    dark_current_e_per_s: float = attr(0.0, doc="dark current", unit="e⁻/s",
                                       range=(0, 1e6), label="dark current", decimals=2,
                                       step=0.5)
    exposure_time_s: float = attr(0.001, doc="exposure time (shutter)", unit="s",
                                  range=(0, 60), label="exposure time (shutter)", decimals=5,
                                  step=0.0005)
    adc_bits: int = attr(12, doc="bits of the analogue-to-digital converter", unit="bits",
                         range=(1, 16), label="ADC")
    exposure_scale: float = attr(0.8, doc="white in the render collects this × full well",
                                 unit="× full well", range=(0, 100), label="white at",
                                 decimals=3, step=0.05)
    seed: int = attr(0, doc="the noise's random seed", range=SEED_RANGE,
                     draw="sensor-noise")


@element("blur", title="optical blur (Gaussian)", path="effects.blur", on={"sigma_px": 0.5})
@dataclass(frozen=True)
class Blur:
    """Gaussian defocus/optical blur."""

    sigma_px: float = attr(doc="σ of the Gaussian", unit="px", range=(0, 50), label="σ",
                           decimals=3, step=0.1)


@element("motion-blur", title="motion blur", path="effects.motion_blur",
         on={"exposure_time_s": 0.001, "speed_m_s": 8.0})
@dataclass(frozen=True)
class MotionBlur:
    """Linear blur along the direction of flight: length = speed x exposure time /
    GSD (px)."""

    exposure_time_s: float = attr(doc="exposure time (shutter)", unit="s", range=(0, 1),
                                  label="exposure time (shutter)", decimals=5, step=0.0005)
    speed_m_s: float = attr(doc="ground speed during the exposure", unit="m/s",
                            range=(0, 100), label="ground speed", decimals=2, step=1)


@element("jpeg", title="JPEG compression", path="effects.jpeg", on={"quality": 92})
@dataclass(frozen=True)
class Jpeg:
    """JPEG compression artefacts, as a camera that saves JPEG images."""

    quality: int = attr(doc="JPEG compression quality", range=(1, 100), label="quality",
                        factor="jpeg-quality")


@element("exposure-variation", title="auto exposure and white balance (per image)",
         path="effects.exposure_variation")
@dataclass(frozen=True)
class ExposureVariation:
    """Auto exposure and auto white balance drawn anew for each image, as a drone
    camera meters each photo: brightness × 2^e with e ~ N(0, exposure-sigma-ev²)
    stops, colour balanced for a temperature T ~ N(reference-k,
    white-balance-sigma-k²) K while the light is reference-k. Applied in linear
    light before the sensor.

    A drone camera's auto exposure and auto white balance, drawn anew for each image:
    the image's brightness is scaled by 2^e, e ~ N(0, ``exposure_sigma_ev``²) stops, and
    its colour balanced for a colour temperature T ~ N(``reference_k``,
    ``white_balance_sigma_k``²) K while the light is ``reference_k``: each channel is
    multiplied by the ratio of black-body radiance at its wavelength (R 600, G 540,
    B 460 nm) for T and for the reference, green kept (designer.effects.exposure)."""

    exposure_sigma_ev: float = attr(0.15, doc="σ of the per-image exposure error",
                                    unit="EV", range=(0, 2), factor="exposure-sigma-ev",
                                    label="exposure σ", decimals=3, step=0.05)
    white_balance_sigma_k: float = attr(150.0, doc="σ of the per-image white-balance "
                                        "colour temperature", unit="K", range=(0, 3000),
                                        factor="white-balance-sigma-k",
                                        label="white balance σ", decimals=0, step=50)
    reference_k: float = attr(5500.0, doc="colour temperature of the light", unit="K",
                              range=(2000, 12000), label="light at", decimals=0, step=100)
    seed: int = attr(0, doc="the draws' random seed", range=SEED_RANGE,
                     draw="exposure-variation")


@element("chromatic-aberration", title="lateral chromatic aberration",
         path="effects.chromatic_aberration")
@dataclass(frozen=True)
class ChromaticAberration:
    """Lateral chromatic aberration (lateral colour): the red and the blue image are
    imaged at a slightly different scale than the green one, radially about the
    principal point. A point of a channel at radius r from the principal point lands
    at r x (1 + s x 1e-6), s the channel's scale in parts per million; green is exact
    (its ground truth is the exported one). Resampled with cubic B-splines in linear
    light, on the output pixels, right after the lens distortion and before
    vignetting, blur and the sensor.

    A channel's scale is its ``*_scale_ppm``; green stays exact, so the exported ground
    truth is green's (designer.effects.chromatic). Switched on at 0 ppm, so a study
    factor varies only the channel it names."""

    red_scale_ppm: float = attr(0.0, doc="radial scale of the red image relative to green "
                                "(+: farther from the principal point)", unit="ppm",
                                range=(-5000, 5000), factor="chromatic-aberration-red-ppm",
                                label="red scale", decimals=1, step=10)
    blue_scale_ppm: float = attr(0.0, doc="radial scale of the blue image relative to "
                                 "green (+: farther from the principal point)", unit="ppm",
                                 range=(-5000, 5000), factor="chromatic-aberration-blue-ppm",
                                 label="blue scale", decimals=1, step=10)


@xml_type(named=True, all=True, content=("vignetting", "defocus", ...))
@dataclass(frozen=True)
class Effects:
    """Image effects applied after rendering, each optional and off when absent.
    Lens distortion is not an effect: it comes from the camera (brown-conrady or
    fisheye-equidistant)."""

    vignetting: Vignetting | None = None
    sensor_noise: SensorNoise | None = None
    sensor: Sensor | None = None
    blur: Blur | None = None
    motion_blur: MotionBlur | None = None
    jpeg: Jpeg | None = None
    defocus: Defocus | None = None
    exposure_variation: ExposureVariation | None = None
    chromatic_aberration: ChromaticAberration | None = None


@element("render", title="render settings", path="render")
@xml_type(named=True, holders={
    "pixel-filter": ("Cycles pixel (reconstruction) filter.", False),
    "output": ("Image file format of the photos.", False)})
@dataclass(frozen=True)
class Render:
    """How Blender (Cycles) renders the photos.

    How Cycles renders the photos: values held as child-element texts, the pixel
    filter's and the output's as attributes of ``<pixel-filter>`` and ``<output>``."""

    preset: Preset = attr("survey", doc="quality preset: Cycles samples per pixel (draft 4, "
                          "survey 16, metrology 64)", text=True)
    samples: int | None = attr(None, doc="Cycles samples per pixel, instead of the preset's",
                               range=(1, 65536), text=True, label="samples")
    pixel_filter_type: PixelFilterType = attr("box", doc="Cycles pixel filter",
                                              child="pixel-filter", xml="type",
                                              label="pixel filter")
    pixel_filter_width_px: float = attr(1.0, doc="pixel filter width", unit="px",
                                        range=(0.01, 10), child="pixel-filter",
                                        xml="width-px", label="filter width", decimals=2,
                                        step=0.1)
    resolution_scale: float = attr(1.0, doc="rendered image size = camera image size × this",
                                   range=(0, 1), low_open=True, text=True,
                                   label="resolution scale", decimals=3, step=0.05)
    workers: int = attr(1, doc="Blender worker processes run at once", range=(1, 256),
                        text=True, label="workers")
    output_format: ImageFormat = attr("png", doc="image file format of the photos",
                                      child="output", xml="format", label="format")
    bit_depth: int = attr(8, doc="bits per channel (png 8 or 16, jpeg 8, tiff 8, 16 or 32, "
                          "exr 16 or 32)", range=(8, 32), child="output", xml="bit-depth",
                          label="bit depth")
    distortion_oversample: int = attr(1, doc="a distorted camera's pinhole render is this "
                                      "many times larger before it is resampled",
                                      range=(1, 4), text=True, write_default=False,
                                      label="distortion oversample")
    #: "exif": each image carries its time (DateTimeOriginal…) from the time line
    image_metadata: ImageMetadata = attr("none", doc="exif: each image carries its time "
                                         "from the time line", child="output",
                                         xml="metadata", write_default=False,
                                         label="image metadata")

    @property
    def effective_samples(self) -> int:
        return self.samples if self.samples is not None else PRESET_SAMPLES[self.preset]


@element("outputs", title="outputs", path="outputs")
@xml_type(named=True)
@dataclass(frozen=True)
class Outputs:
    """Where results go and which ground truth is exported with the photos (always
    in world coordinates)."""

    directory: str = attr("output", doc="output folder, relative to this XML file's folder",
                          xsd="d:FilePath")
    ground_truth: tuple[GroundTruthFormat, ...] = nested(
        (), doc="One ground-truth export.", tag="ground-truth",
        item_attrs=(XsdAttr("format", "colmap (cameras.txt, images.txt, points3D.txt), odm "
                            "(gcp_list.txt, geo.txt), metashape (calibration XML, "
                            "camera and marker reference CSV), opk "
                            "(camera_poses_opk.csv: image, X, Y, Z, omega, phi, "
                            "kappa), gcp (gcp_truth.csv and gcp_observations.csv).",
                            required=True),))


# ---------------------------------------------------------------------- the project
@xml_type(tag="project", content=("name", "description", ..., "effects", "render", "outputs",
                                        "processing"))
@dataclass(frozen=True)
class Project:
    """One virtual survey. Root element; its schema-version attribute says which
    version of this format the file follows."""

    name: str = nested(doc="Project name, shown in reports.", xsd="d:Text")
    crs: str = nested(doc="Label of the coordinate reference system of all world "
                          "coordinates, e.g. 'EPSG:32632 (WGS 84 / UTM zone 32N)'. A "
                          "label only: designer never reprojects; exporters copy it "
                          "into ground-truth files.", xsd="d:Text")
    origin: Origin = nested(doc="Project origin (E0, N0, H0), world frame, m; "
                                "subtracted before geometry goes to Blender.")
    scene: Scene = nested(doc="The scene: terrain, texture, GCP targets, other objects"
                              " and lighting.")
    cameras: tuple[Camera, ...] = nested(
        doc="The cameras: interior orientation (mm, px) and lens distortion.",
        wrapper=Wrapper("cameras", "Cameras", "The cameras of the survey (at least one)."),
        item_doc="One camera: its interior orientation and lens distortion.")
    trajectory: Trajectory = nested(doc="Where the photos are taken: exterior "
                                        "orientations (world frame, m; omega, phi, "
                                        "kappa in degrees) and/or a flight plan.")
    render: Render = nested(factory=Render, optional=False,
                            doc="Cycles render settings and the image file format.")
    outputs: Outputs = nested(factory=Outputs, optional=False,
                              doc="Output folder and ground-truth formats.")
    effects: Effects | None = nested(None, doc="Optional image effects (vignetting, sensor "
                                     "noise, blur, motion blur, JPEG).")
    description: str | None = nested(None, doc="Optional free-text description.", xsd="d:Text")
    processing: Processing | None = nested(
        None, doc="Optional photogrammetric processing settings used by 'designer "
                  "reconstruct' (camera calibration, how GCPs and camera positions "
                  "enter the adjustment, matching, dense matching). Without it: fixed "
                  "interior orientation, a similarity on the control GCPs, no "
                  "camera-position priors.")
    schema_version: str = schema_attrs(
        SCHEMA_VERSION, XsdAttr("schema-version", "Version of this file format: \"1.0\". A file "
                                "of another version is refused with the list of supported "
                                "versions.",
                                "d:SchemaVersion", True))

    def camera(self, camera_id: str) -> Camera:
        """The camera with this id (KeyError if there is none)."""
        for cam in self.cameras:
            if cam.id == camera_id:
                return cam
        raise KeyError(camera_id)

    @property
    def targets(self) -> tuple[Target, ...]:
        return self.scene.targets.targets if self.scene.targets else ()
