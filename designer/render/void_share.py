"""How much of each rendered image sees no object: its *void share*.

A camera ray that hits nothing shows only the world background (black in most projects:
``RenderJob.background_rgb``). Such pixels are void: nothing in them can be matched or
measured, and a survey whose images are largely void is weaker than its overlap says.

The render worker (:mod:`designer.render.worker`) has Cycles write a *void map* beside
every frame: its mist pass, with the mist starting at the camera and ending far beyond
any object, so each sample that hits an object adds 0 and each that sees only the
background adds 1. A pixel of the map is then the share of its samples (weighted by the
pixel filter) that saw no object — exact at the terrain's edge, and whatever the colours:
a black GCP square on a black background is not void. The map is measured on Blender's
own render, before any camera effect, and the images are the same bytes as without it.

This module reads the maps and sums them up (numpy and OpenCV; no bpy).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path

#: an image with more void than this share gets a warning from ``designer render``
VOID_WARN_SHARE = 0.01
#: the void map kept beside a raw render (``keep_raw``): ``STEM`` + this
VOID_MAP_SUFFIX = ".void-map.png"
#: full scale of the void map (a 16-bit grey PNG: 0 = every sample hit an object)
VOID_MAP_FULL_SCALE = 65535
#: decimals of the void share in the manifest (1e-5 of an image)
VOID_SHARE_DECIMALS = 5


def void_share_of_map(path: Path) -> float:
    """The void share (0..1) of the image whose void map is ``path``: the mean of the
    map, i.e. the share of the image's pixel area that sees no object."""
    import cv2
    import numpy as np

    if not Path(path).is_file():
        raise FileNotFoundError(f"{path}: no void map; Blender wrote none for this render")
    coverage = cv2.imread(str(path), cv2.IMREAD_UNCHANGED)
    if coverage is None or coverage.dtype != np.uint16 or coverage.ndim != 2:
        raise ValueError(f"{path}: not a void map (a 16-bit grey PNG written by the render "
                         "worker)")
    return float(coverage.mean(dtype=np.float64)) / VOID_MAP_FULL_SCALE


def round_void_share(share: float) -> float:
    """A void share as the manifest stores it."""
    return round(float(share), VOID_SHARE_DECIMALS)


@dataclass(frozen=True)
class VoidSummary:
    """The void of a render folder's images (the manifest's ``void``)."""

    #: images whose void share is recorded (images from an older designer have none)
    images_measured: int
    #: images with more void than ``threshold_share``
    images_over_threshold: int
    threshold_share: float = VOID_WARN_SHARE
    #: the image with the most void (None when no image is measured) and its share
    worst_image: str | None = None
    worst_share: float | None = None


def void_summary(shares: Mapping[str, float | None],
                 threshold_share: float = VOID_WARN_SHARE) -> VoidSummary:
    """Sum up ``shares`` (image name → void share, None where not measured); the worst
    image is the first by name among equals."""
    measured = {name: float(s) for name, s in shares.items() if s is not None}
    if not measured:
        return VoidSummary(0, 0, threshold_share)
    worst = max(sorted(measured), key=measured.__getitem__)
    over = sum(1 for s in measured.values() if s > threshold_share)
    return VoidSummary(len(measured), over, threshold_share, worst, measured[worst])


def void_warning(summary: VoidSummary) -> str | None:
    """One line for the end of ``designer render`` when images have more void than the
    threshold, naming how many, the worst and the fix; None when none has."""
    if summary.images_over_threshold == 0:
        return None
    return (f"{summary.images_over_threshold} of {summary.images_measured} images have "
            f"more than {summary.threshold_share:.0%} void (pixels that see no object, "
            f"only the background), worst {summary.worst_image} with "
            f"{summary.worst_share:.1%}; declare <surroundings> in the terrain or enlarge "
            "the terrain")
