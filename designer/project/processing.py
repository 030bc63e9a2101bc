"""Processing settings of a project (``<processing>``): how ``designer reconstruct``
treats the rendered images — camera calibration, GCPs, camera-position priors, matching.

Part of the project model (lxml-free frozen dataclasses); re-exported by
``designer.project.model``. Units: px for image quantities, m for positions.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

from designer.project.declare import SEED_RANGE, attr, element
from designer.project.declare_structure import ListOf, XsdAttr, nested, schema_attrs, xml_type

CalibrationMode = Literal["fixed", "focal", "focal-principal-point", "radial", "full"]
GcpMode = Literal["none", "similarity", "bundle"]
PositionPriorMode = Literal["none", "gnss", "rtk"]
Pairing = Literal["footprint", "position", "exhaustive"]
SiftScale = Literal["doubled", "original", "half"]
DenseMode = Literal["none", "cpu", "auto"]
Mapper = Literal["incremental", "global"]
RollingShutterProcessing = Literal["none", "compensate"]


#: default camera-position prior sigmas (horizontal, vertical) in m, by prior mode:
#: consumer drone GNSS and RTK/PPK (docs/processing.md)
POSITION_PRIOR_SIGMAS_M = {"gnss": (2.5, 5.0), "rtk": (0.02, 0.03)}


@element("pre-calibration-error", title="pre-calibration error",
         path="processing.calibration.pre_calibration_error", stage="processing")
@dataclass(frozen=True)
class PreCalibrationError:
    """The starting (or fixed) interior orientation differs from the true camera by
    normally distributed errors with these standard deviations, drawn from the seed.
    Absent: the starting values are the true ones.

    Units: px for the focal length and the principal point (cx and cy each), none for
    k1..k3, p1, p2."""

    focal_px: float = attr(0.0, doc="σ of the starting focal-length error", unit="px",
                           range=(0, 1e6), factor="pre-calibration-focal-px",
                           label="focal length σ", decimals=2, step=1)
    principal_point_px: float = attr(0.0, doc="σ of the starting principal-point error, "
                                     "cx and cy each", unit="px", range=(0, 1e6),
                                     label="principal point σ", decimals=2, step=1)
    k1: float = attr(0.0, doc="σ of the starting k1 error", range=(0, 1e6),
                     factor="pre-calibration-k1", label="k1 σ", decimals=4, step=0.001)
    k2: float = attr(0.0, doc="σ of the starting k2 error", range=(0, 1e6), label="k2 σ",
                     decimals=4, step=0.001)
    k3: float = attr(0.0, doc="σ of the starting k3 error", range=(0, 1e6), label="k3 σ",
                     decimals=4, step=0.001)
    p1: float = attr(0.0, doc="σ of the starting p1 error", range=(0, 1e6), label="p1 σ",
                     decimals=5, step=0.0001)
    p2: float = attr(0.0, doc="σ of the starting p2 error", range=(0, 1e6), label="p2 σ",
                     decimals=5, step=0.0001)
    seed: int = attr(0, doc="the errors' random seed", range=SEED_RANGE,
                     draw="pre-calibration")


@element("calibration", title="calibration", path="processing.calibration",
         stage="processing")
@dataclass(frozen=True)
class Calibration:
    """Interior orientation in the adjustment: fixed (to the starting values), focal
    (f), focal-principal-point (f, cx, cy), radial (f, cx, cy, k1, k2, k3) or full
    (f, cx, cy, k1, k2, k3, p1, p2) self-calibration.

    Which interior parameters the adjustment estimates (``fixed``: none), and whether
    it models the motion of rolling-shutter images during their readout (``compensate``:
    each image's velocity, docs/processing.md § Rolling shutter)."""

    mode: CalibrationMode = attr("fixed", doc="interior parameters the adjustment "
                                 "estimates", factor="calibration", label="estimate")
    pre_calibration_error: PreCalibrationError | None = None
    rolling_shutter: RollingShutterProcessing = attr(
        "none", doc="rolling-shutter images: none (treated as global shutter) or "
        "compensate (each image's velocity during the readout is estimated)",
        factor="rolling-shutter-processing", label="rolling shutter", write_default=False)


@xml_type(lead=("ids",))
@element("control", title="control points", path="processing.gcps.control",
         stage="processing")
@dataclass(frozen=True)
class ControlSelection:
    """Which targets are control points (the others are check points): a list of
    ids, or a count chosen evenly spread over the area or at random (seeded).
    Absent: each target's role."""

    ids: tuple[str, ...] = schema_attrs(
        (), XsdAttr("ids", "Space-separated target ids.", ListOf("d:Identifier")))
    count: int | None = attr(None, doc="number of GCPs used as control (the others are check "
                             "points)", range=(1, 10000),
                             label="count")
    spread: Literal["even", "random"] = attr("even", doc="how control-count GCPs are chosen "
                                             "(even: spread over the area)",
                                             factor="control-spread", label="spread")
    seed: int = attr(0, doc="the random choice's seed", range=SEED_RANGE)


@element("gcps", title="GCPs", path="processing.gcps", stage="processing")
@dataclass(frozen=True)
class GcpProcessing:
    """How ground control points enter the processing: none (not used), similarity
    (a 7-parameter similarity fitted to the control points after SfM) or bundle
    (control points marked in the images and weighted by their surveyed sigma in the
    bundle adjustment). Check points are marked too but never used."""

    mode: GcpMode = attr("similarity", doc="how control points enter the adjustment",
                         factor="gcp-mode", label="GCPs enter as")
    marking_sigma_px: float = attr(0.0, doc="σ of the GCP marking error in the images, each "
                                   "axis", unit="px", range=(0, 50),
                                   factor="marking-sigma-px", label="marking σ", decimals=2,
                                   step=0.1)
    seed: int = attr(0, doc="the marking error's random seed", range=SEED_RANGE,
                     draw="marking-error")
    control: ControlSelection | None = None


@element("position-prior", title="camera-position prior",
         path="processing.position_prior", stage="processing")
@dataclass(frozen=True)
class PositionPrior:
    """Camera positions measured in flight, used as weighted priors in the
    adjustment: none, gnss (default sigma 2.5 m horizontal, 5 m vertical) or rtk
    (0.02 m, 0.03 m). The measured positions are the true centres plus normally
    distributed errors of these sigmas (seeded)."""

    mode: PositionPriorMode = attr("none", doc="camera positions measured in flight",
                                   factor="position-prior", label="camera positions")
    sigma_horizontal_m: float | None = attr(None, doc="σ of the measured positions, "
                                            "horizontal (none: the mode's)", unit="m",
                                            range=(0, 1000), low_open=True,
                                            label="σ horizontal", decimals=3, step=0.01)
    sigma_vertical_m: float | None = attr(None, doc="σ of the measured positions, vertical "
                                          "(none: the mode's)", unit="m", range=(0, 1000),
                                          low_open=True, label="σ vertical", decimals=3,
                                          step=0.01)
    seed: int = attr(0, doc="the position errors' random seed", range=SEED_RANGE,
                     draw="position-prior")

    @property
    def sigmas_m(self) -> tuple[float, float]:
        """(horizontal, vertical) σ in m: the given ones, else the mode's defaults."""
        h, v = POSITION_PRIOR_SIGMAS_M.get(self.mode, (0.0, 0.0))
        return (self.sigma_horizontal_m if self.sigma_horizontal_m is not None else h,
                self.sigma_vertical_m if self.sigma_vertical_m is not None else v)


def control_count(selection: ControlSelection | None, targets) -> int:
    """How many of ``targets`` (the project's GCP targets) are control points under
    ``selection``: their declared roles when there is none, else its ids or its count
    (at most the targets there are)."""
    if selection is None:
        return sum(t.role == "control" for t in targets)
    if selection.ids:
        return len(set(selection.ids))
    return min(selection.count or 0, len(targets))


@element("matching", title="matching", path="processing.matching", stage="processing")
@dataclass(frozen=True)
class Matching:
    """Features and image pairs."""

    max_features: int = attr(8192, doc="SIFT features per image", range=(100, 1_000_000),
                             factor="max-features", label="features per image")
    pairs: Pairing = attr("footprint", doc="which image pairs are matched",
                          label="pairs matched")
    min_track_length: int = attr(3, doc="fewest images a point is seen in", unit="images",
                                 range=(2, 100), label="shortest track")
    sift_scale: SiftScale = attr(
        "doubled", doc="the image size SIFT's first octave works on: doubled (COLMAP's "
        "default, first octave -1; Metashape's 'highest' alignment accuracy), original "
        "(first octave 0, Metashape's 'high': about a quarter of the extraction work, "
        "without the features finer than a pixel or two) or half (first octave 1, "
        "'medium')", label="SIFT image size")


@element("sfm", title="structure from motion", path="processing.sfm", stage="processing")
@dataclass(frozen=True)
class Sfm:
    """Structure from motion: which mapper finds the cameras and tie points."""

    mapper: Mapper = attr("incremental", doc="how the cameras and tie points are found: "
                          "incremental (COLMAP's, image by image with bundle adjustments "
                          "along the way) or global (GLOMAP's, all rotations, then all "
                          "positions, then one adjustment)", factor="mapper",
                          label="SfM mapper")
    global_adjustment_growth: float = attr(
        1.1, doc="the incremental mapper adjusts the whole model again once it has grown "
        "by this factor (registered images, tie points): COLMAP's 1.1; 1.4 took 30 to 42 % "
        "less mapper CPU on blocks of 230 and 720 images, with the same cameras (designer "
        "bench mapper)", range=(1.01, 10.0), decimals=2, step=0.05,
        label="whole-model adjustment after growth by")


@element("processing", title="processing", path="processing", stage="processing")
@xml_type(named=True, all=True, content=(..., "sfm", "dense"), holders={
    "dense": ("Dense matching: none, cpu or auto.", True)})
@dataclass(frozen=True)
class Processing:
    """How the rendered images are processed, as a practitioner sets up Metashape,
    Pix4D or OpenDroneMap. Every child is optional; an absent child keeps its
    defaults. Command-line options of 'designer reconstruct' override these values."""

    calibration: Calibration = nested(factory=Calibration, optional=True)
    gcps: GcpProcessing = nested(factory=GcpProcessing, optional=True)
    position_prior: PositionPrior = nested(factory=PositionPrior, optional=True)
    matching: Matching = nested(factory=Matching, optional=True)
    dense: DenseMode = attr("none", doc="dense matching: none (sparse cloud only), cpu "
                            "(dense matching on the CPU) or auto (the best available)",
                            child="dense", xml="mode", label="dense matching")
    sfm: Sfm = nested(factory=Sfm, optional=True)


