"""A small cloudy scene shared by the tests of the cloud shadows the 3D view draws."""

from __future__ import annotations

from designer.gui.state import edits, files
from designer.project import model as m

#: 3.125 m/s east: 1 s of wind is 8 steps of the 100 m / 256 preview grid
CLOUDS = m.CloudShadows(cover=0.5, size_m=20.0, softness_m=1.0, depth=0.8,
                        wind_speed_m_s=3.125, wind_direction_deg=90.0, seed=4)
HUT = m.Building("hut", footprint=tuple(m.PathPoint(X, Y) for X, Y in (
    (-2.0, -2.0), (2.0, -2.0), (2.0, 2.0), (-2.0, 2.0))), eave_height_m=3.0)


def cloudy_hut() -> m.Project:
    """The blank project (flat 100 × 100 m, origin 0) with cloud shadows and a 4 × 4 m
    flat-roofed hut at its centre."""
    p = edits.replace_path(files.blank_project(), "scene.lighting.clouds", CLOUDS)
    return edits.replace_path(p, "scene.buildings", (HUT,))
