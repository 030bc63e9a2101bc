"""Processing settings of a project (``<processing>``): how ``designer reconstruct``
treats the rendered images — camera calibration, GCPs, camera-position priors, matching.

Part of the project model (lxml-free frozen dataclasses); re-exported by
``designer.project.model``. Units: px for image quantities, m for positions.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Literal

CalibrationMode = Literal["fixed", "focal", "focal-principal-point", "radial", "full"]
GcpMode = Literal["none", "similarity", "bundle"]
PositionPriorMode = Literal["none", "gnss", "rtk"]
Pairing = Literal["footprint", "position", "exhaustive"]
DenseMode = Literal["none", "cpu", "auto"]


#: default camera-position prior sigmas (horizontal, vertical) in m, by prior mode:
#: consumer drone GNSS and RTK/PPK (docs/processing.md)
POSITION_PRIOR_SIGMAS_M = {"gnss": (2.5, 5.0), "rtk": (0.02, 0.03)}


@dataclass(frozen=True)
class PreCalibrationError:
    """σ of the errors of the starting (or fixed) interior orientation: focal length and
    principal point (px, cx and cy each), k1..k3, p1, p2 (dimensionless); seeded."""

    focal_px: float = 0.0
    principal_point_px: float = 0.0
    k1: float = 0.0
    k2: float = 0.0
    k3: float = 0.0
    p1: float = 0.0
    p2: float = 0.0
    seed: int = 0


@dataclass(frozen=True)
class Calibration:
    """Which interior parameters the adjustment estimates (``fixed``: none)."""

    mode: CalibrationMode = "fixed"
    pre_calibration_error: PreCalibrationError | None = None


@dataclass(frozen=True)
class ControlSelection:
    """Control targets by ``ids``, or ``count`` of them spread ``even``ly or at ``random``."""

    ids: tuple[str, ...] = ()
    count: int | None = None
    spread: Literal["even", "random"] = "even"
    seed: int = 0


@dataclass(frozen=True)
class GcpProcessing:
    """How control points enter; marking error σ (px per axis, seeded) of every target."""

    mode: GcpMode = "similarity"
    marking_sigma_px: float = 0.0
    seed: int = 0
    control: ControlSelection | None = None


@dataclass(frozen=True)
class PositionPrior:
    """Camera centres measured in flight (true + seeded errors), weighted priors (m)."""

    mode: PositionPriorMode = "none"
    sigma_horizontal_m: float | None = None
    sigma_vertical_m: float | None = None
    seed: int = 0

    @property
    def sigmas_m(self) -> tuple[float, float]:
        """(horizontal, vertical) σ in m: the given ones, else the mode's defaults."""
        h, v = POSITION_PRIOR_SIGMAS_M.get(self.mode, (0.0, 0.0))
        return (self.sigma_horizontal_m if self.sigma_horizontal_m is not None else h,
                self.sigma_vertical_m if self.sigma_vertical_m is not None else v)


@dataclass(frozen=True)
class Matching:
    max_features: int = 8192
    pairs: Pairing = "footprint"
    min_track_length: int = 3


@dataclass(frozen=True)
class Processing:
    """Photogrammetric processing settings of ``designer reconstruct``."""

    calibration: Calibration = field(default_factory=Calibration)
    gcps: GcpProcessing = field(default_factory=GcpProcessing)
    position_prior: PositionPrior = field(default_factory=PositionPrior)
    matching: Matching = field(default_factory=Matching)
    dense: DenseMode = "none"


