"""A small rolling-shutter survey: checker targets on flat ground flown over at a known
speed (docs/world.md, "Rolling shutter")."""

from __future__ import annotations

import math
from dataclasses import replace

from designer.project import model as m
from tests.synthetic import model_camera
from tests.world.helpers import ORIGIN

TAKEOFF = "2026-06-21T09:30:00Z"
SPEED_M_S = 10.0
#: flight direction, degrees clockwise from north: the camera moves east and north, so
#: the readout both skews (east) and stretches (north) the image
AZIMUTH_DEG = 60.0
READOUT_S = 0.03
SIZE_PX = (320, 240)
#: 30 m above ground, 8 mm lens, 10 µm pixels: GSD 3.75 cm; 0.3 m during the readout is
#: 8 px between the first and the last row
HEIGHT_M = 30.0


def rolling_project(readout_s: float = READOUT_S, direction: str = "top-to-bottom",
                    samples: int = 256, time_line: bool = True,
                    kappa_deg: float = 20.0) -> m.Project:
    E0, N0, H0 = ORIGIN
    cam = model_camera(SIZE_PX, focal_length_mm=8.0, pixel_pitch_mm=0.01,
                       rolling_shutter=m.RollingShutter(readout_s, direction))
    targets = tuple(
        m.Target(f"T{i + 1}{j + 1}", "control", "checker", 1.2,
                 m.TruePosition(E0 + 2.6 * i, N0 + 2.6 * j),
                 m.SurveyedPosition(m.Point3(E0 + 2.6 * i, N0 + 2.6 * j, H0),
                                    m.Sigma3(0.0, 0.0, 0.0)))
        for i in (-1, 0, 1) for j in (-1, 0, 1))
    scene = m.Scene(
        terrain=m.Terrain(m.Extent(E0 - 25, N0 - 25, E0 + 25, N0 + 25), m.FlatTerrain(H0)),
        texture=m.Texture(m.ProceduralTexture("grass", seed=2, texel_size_m=0.02),
                          repeat_X=8, repeat_Y=8, interpolation="linear"),
        targets=m.Targets(targets),
        lighting=m.Lighting(m.Sun(azimuth_deg=150.0, elevation_deg=55.0)))
    az = math.radians(AZIMUTH_DEG)
    # two photos 1 m apart along the flight direction: both on one straight leg
    photos = tuple(
        m.ExteriorOrientation(f"IMG_{k:03d}.png", "cam", E0 + (k - 0.5) * math.sin(az),
                              N0 + (k - 0.5) * math.cos(az), H0 + HEIGHT_M, 0.0, 0.0,
                              kappa_deg)
        for k in range(2))
    tl = m.TimeLine(TAKEOFF, SPEED_M_S) if time_line else None
    return m.Project(
        name="rolling shutter", crs="EPSG:32632", origin=m.Origin(E0, N0, H0), scene=scene,
        cameras=(cam,), trajectory=m.Trajectory(photos, None, tl),
        render=m.Render(preset="survey", samples=samples, workers=1),
        outputs=m.Outputs("output", ("colmap", "odm", "metashape", "opk", "gcp")))


def global_shutter(project: m.Project) -> m.Project:
    """The same project with a global shutter (no rolling-shutter element)."""
    return replace(project, cameras=tuple(replace(c, rolling_shutter=None)
                                          for c in project.cameras))
