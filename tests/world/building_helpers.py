"""A small project with buildings: a gable house, a hip house and a flat-roofed tower
that hides a GCP target from one photo."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import cv2
import numpy as np

from designer.project import model as m
from tests.synthetic import small_survey
from tests.world.helpers import ORIGIN

#: the GCP the tower hides from photo 0
HIDDEN = "G_hidden"


def rectangle(x0: float, y0: float, x1: float, y1: float) -> tuple[m.PathPoint, ...]:
    """Counter-clockwise rectangle, metres from the origin's E and N."""
    E0, N0, _ = ORIGIN
    return tuple(m.PathPoint(E0 + x, N0 + y) for x, y in ((x0, y0), (x1, y0), (x1, y1), (x0, y1)))


def building_project(samples: int = 4, with_buildings: bool = True) -> m.Project:
    """Two nadir photos 50 m up (160 x 120 px, 10 cm/px): photo 0 above the origin,
    photo 1 above the hidden target 6 m east of it; a 15 m tower at 4.5..5.5 m east
    stands between photo 0 and that target."""
    p = small_survey(origin=ORIGIN, n_photos=2, samples=samples, size_px=(160, 120))
    E0, N0, H0 = ORIGIN
    photos = tuple(m.ExteriorOrientation(f"IMG_{k:03d}.png", "cam", E0 + x, N0, H0 + 50.0,
                                         0.0, 0.0, 0.0) for k, x in enumerate((0.0, 6.0)))
    targets = tuple(
        m.Target(name, role, "checker", 1.0, m.TruePosition(E0 + x, N0 + y),
                 m.SurveyedPosition(m.Point3(E0 + x, N0 + y, H0), m.Sigma3(0.0, 0.0, 0.0)))
        for name, role, x, y in ((HIDDEN, "control", 6.0, 0.0), ("G_open", "check", -5.5, 0.0)))
    buildings = (
        m.Building("tower", rectangle(4.5, -1.0, 5.5, 1.0), "flat", 15.0),
        m.Building("gable", rectangle(-4.0, -4.5, 2.0, -1.5), "gable", 3.0, 5.0),
        m.Building("hip", rectangle(-4.0, 1.0, 1.0, 4.0)[::-1], "hip", 2.5, 4.0),
    )
    scene = replace(p.scene, targets=m.Targets(targets),
                    buildings=buildings if with_buildings else ())
    return replace(p, scene=scene, trajectory=m.Trajectory(photos))


def changed_pixels(out: Path, bare: Path, name: str) -> np.ndarray:
    """Pixels the buildings change (by more than 30 of 765 levels summed over RGB)."""
    a = cv2.imread(str(out / "images" / name)).astype(int)
    b = cv2.imread(str(bare / "images" / name)).astype(int)
    return np.abs(a - b).sum(axis=-1) > 30
