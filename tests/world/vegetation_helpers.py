"""A small timed project with red shrubs swaying in the wind under a nadir camera."""

from __future__ import annotations

from dataclasses import replace

from designer.project import model as m
from tests.world.helpers import ORIGIN, timed_survey

RED = (0.8, 0.04, 0.04)
WIND = m.Wind(amplitude_deg=20.0, gust_period_s=4.0, direction_deg=60.0)


def vegetation_project(times_s=(0.0, 1.0), samples=16, wind=WIND, density_per_m2=0.25,
                       flat=True) -> m.Project:
    """Two nadir photos 30 m above the origin (160 x 120 px, 6 cm/px) of a 40 x 40 m site
    with red shrubs (1 m tall, 1.2 m across) and the small survey's nine targets (one in
    view at the origin)."""
    p = timed_survey(times_s, sun_over_time=False)
    veg = m.Vegetation((m.PlantGroup(density_per_m2, "shrub", height_m=1.0, height_sd_m=0.15,
                                     crown_m=1.2, albedo_rgb=RED),), seed=5, clearance_m=0.3,
                       wind=wind)
    texture = m.Texture(m.ProceduralTexture("noise", seed=2, texel_size_m=0.02), 4, 4, "linear")
    scene = replace(p.scene, texture=texture, vegetation=veg)
    if flat:
        scene = replace(scene, terrain=replace(p.scene.terrain,
                                               source=m.FlatTerrain(ORIGIN[2] + 0.25)))
    return replace(p, scene=scene, render=replace(p.render, samples=samples))
