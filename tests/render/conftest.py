"""Small real surveys rendered with Blender/Cycles for the render tests."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np

from designer.project import model as m
from designer.project import write_project


def small_survey(
    origin=(0.0, 0.0, 0.0), principal_point_mm=(0.0, 0.0), n_photos=4, samples=16,
    effects=None, distortion=None, size_px=(640, 480), focal_length_mm=5.0,
    pixel_pitch_mm=0.01,
) -> m.Project:
    """A 40 x 40 m gentle terrain, 9 large checker targets, a few photos from 30 m."""
    E0, N0, H0 = origin
    W, H = size_px
    cam = m.Camera(id="cam", focal_length_mm=focal_length_mm,
                   sensor_width_mm=W * pixel_pitch_mm, sensor_height_mm=H * pixel_pitch_mm,
                   image_width_px=W, image_height_px=H,
                   principal_point_x_mm=principal_point_mm[0],
                   principal_point_y_mm=principal_point_mm[1], distortion=distortion)
    targets = tuple(
        m.Target(f"T{i}{j}", "check" if (i + j) % 2 else "control", "checker", 1.5,
                 m.TruePosition(E0 + 10.0 * i, N0 + 10.0 * j),
                 m.SurveyedPosition(m.Point3(E0 + 10.0 * i, N0 + 10.0 * j, H0),
                                    m.Sigma3(0.0, 0.0, 0.0)))
        for i in (-1, 0, 1) for j in (-1, 0, 1))
    scene = m.Scene(
        terrain=m.Terrain(m.Extent(E0 - 20, N0 - 20, E0 + 20, N0 + 20), m.ProceduralTerrain(
            seed=1, grid_spacing_m=0.5, roughness=0.1, min_height_m=H0 - 0.5,
            max_height_m=H0 + 0.5)),
        texture=m.Texture(m.ProceduralTexture("grass", seed=2, texel_size_m=0.02),
                          repeat_X=4, repeat_Y=4, interpolation="linear"),
        targets=m.Targets(targets),
        lighting=m.Lighting(m.Sun(azimuth_deg=150.0, elevation_deg=55.0)),
    )
    rng = np.random.default_rng(4)
    photos = tuple(
        m.ExteriorOrientation(f"IMG_{k:03d}.png", cam.id,
                              E0 + float(rng.uniform(-4, 4)), N0 + float(rng.uniform(-4, 4)),
                              H0 + 30.0 + float(rng.uniform(-1, 1)),
                              float(rng.uniform(-4, 4)), float(rng.uniform(-4, 4)),
                              float(rng.uniform(-180, 180)))
        for k in range(n_photos))
    return m.Project(
        name="render test", crs="EPSG:32632", origin=m.Origin(E0, N0, H0), scene=scene,
        cameras=(cam,), trajectory=m.Trajectory(exterior_orientations=photos),
        effects=effects,
        render=m.Render(preset="survey", samples=samples, workers=1),
        outputs=m.Outputs("output", ("colmap", "odm", "metashape", "opk", "gcp")),
    )


def write(project: m.Project, folder: Path) -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / "project.xml"
    write_project(project, path)
    return path


replace = dataclasses.replace


def small_flight_survey(samples=16, origin=(500000.0, 5000000.0, 250.0), effects=None,
                        distortion=None) -> m.Project:
    """A 60 x 60 m hilly terrain flown at 30 m: a dozen 640 x 480 images for SfM tests.

    The texture's texel (3 cm) is half the GSD (6 cm), so the renderer resolves it without
    aliasing and SIFT finds repeatable features.
    """
    E0, N0, H0 = origin
    cam = m.Camera(id="cam", focal_length_mm=5.0, sensor_width_mm=6.4, sensor_height_mm=4.8,
                   image_width_px=640, image_height_px=480, distortion=distortion)
    targets = tuple(
        m.Target(f"G{k}", "check" if k in (1, 4) else "control", "checker", 1.5,
                 m.TruePosition(E0 + x, N0 + y))
        for k, (x, y) in enumerate([(-14, -14), (0, -12), (14, -14), (-14, 14), (0, 12),
                                    (14, 14), (0, 0)]))
    scene = m.Scene(
        terrain=m.Terrain(m.Extent(E0 - 30, N0 - 30, E0 + 30, N0 + 30), m.ProceduralTerrain(
            seed=5, grid_spacing_m=0.5, roughness=0.3, min_height_m=H0 - 3.0,
            max_height_m=H0 + 3.0)),
        texture=m.Texture(m.ProceduralTexture("grass", seed=2, texel_size_m=0.03),
                          repeat_X=1, repeat_Y=1, interpolation="linear"),
        targets=m.Targets(targets, m.SurveyAccuracy(m.Sigma3(0.0, 0.0, 0.0), seed=1)),
        lighting=m.Lighting(m.Sun(azimuth_deg=150.0, elevation_deg=55.0)),
    )
    plan = m.FlightPlan(
        camera=cam.id, image_prefix="IMG_",
        area=((E0 - 15, N0 - 15), (E0 + 15, N0 - 15), (E0 + 15, N0 + 15), (E0 - 15, N0 + 15)),
        altitude_agl_m=30.0, front_overlap_percent=65.0, side_overlap_percent=55.0,
        pose_noise=m.PoseNoise(0.2, 0.2, 0.1, 0.5, 0.5, 1.0), random_seed=3)
    return m.Project(
        name="SfM test survey", crs="EPSG:32632", origin=m.Origin(E0, N0, H0), scene=scene,
        cameras=(cam,), trajectory=m.Trajectory(flight_plan=plan), effects=effects,
        render=m.Render(preset="survey", samples=samples, workers=2),
        outputs=m.Outputs("output", ("colmap", "odm", "opk", "gcp")),
    )
