"""Example projects written by ``designer new --template NAME``.

Each template is a model built in code plus the companion files it references (a
mesh, a texture image), so the installed tool needs no data files and the examples in
``resources/examples/`` are just these templates written out (a test checks that).
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass, field

import numpy as np

from designer.project import model as m
from designer.project.assets import cube_obj_bytes, seamless_texture_png

TEMPLATE_NAMES = ("survey", "survey-ideal", "survey-dynamic", "survey-structures",
                  "survey-block", "validation-cube", "psf", "texture")


@dataclass(frozen=True)
class Template:
    """A project and the files it references, by path relative to the XML file."""

    project: m.Project
    files: dict[str, bytes] = field(default_factory=dict)


def phantom4pro(camera_id: str = "p4p") -> m.Camera:
    """DJI Phantom 4 Pro: 1-inch 20 MP, 13.2 × 8.8 mm, 5472 × 3648 px, 8.8 mm lens."""
    return m.Camera(
        id=camera_id, name="DJI Phantom 4 Pro (1-inch, 20 MP)", focal_length_mm=8.8,
        sensor_width_mm=13.2, sensor_height_mm=8.8, image_width_px=5472, image_height_px=3648,
        distortion=m.BrownConradyDistortion(k1=-0.02, k2=0.01),
    )


def _look_at_opk_deg(C: np.ndarray, target: np.ndarray) -> tuple[float, float, float]:
    """ω φ κ (deg) of a camera at C looking at ``target`` with the image top upwards."""
    from designer.core.rotation import opk_from_rotation

    z = (C - target) / np.linalg.norm(C - target)  # camera z points backwards
    x = np.cross([0.0, 0.0, 1.0], z)
    x /= np.linalg.norm(x)
    y = np.cross(z, x)
    omega, phi, kappa = opk_from_rotation(np.column_stack([x, y, z]))
    return tuple(round(float(np.degrees(a)), 6) + 0.0 for a in (omega, phi, kappa))  # no -0.0


def _grid_targets(E0: float, N0: float, half: float, size: float) -> tuple[m.Target, ...]:
    """Ten targets draped on the terrain: a 3 × 3 grid plus one off-centre; 3 are checks."""
    offsets = [(-1, -1), (0, -1), (1, -1), (-1, 0), (0, 0), (1, 0), (-1, 1), (0, 1), (1, 1),
               (0.45, 0.55)]
    out = []
    for i, (a, b) in enumerate(offsets):
        role = "check" if i in (1, 5, 7) else "control"
        out.append(m.Target(
            id=f"GCP{i + 1:02d}", role=role, shape="checker", size_m=size,
            true=m.TruePosition(E0 + a * half, N0 + b * half)))
    return tuple(out)


def survey() -> Template:
    """The example survey: 100 × 100 m of hills (−10..10 m), grass, 10 GCPs, grid flight."""
    E0, N0 = 512000.0, 5406000.0
    cam = phantom4pro()
    extent = m.Extent(E0 - 50, N0 - 50, E0 + 50, N0 + 50)
    scene = m.Scene(
        terrain=m.Terrain(extent, m.ProceduralTerrain(
            seed=7, grid_spacing_m=0.5, roughness=0.3, min_height_m=-10.0, max_height_m=10.0)),
        # 20 m tiles under a 75 x 50 m footprint: the variation keeps images that do not
        # overlap from showing the same ground (docs/world.md)
        texture=m.Texture(m.ProceduralTexture("grass", seed=3, texel_size_m=0.025),
                          repeat_X=5, repeat_Y=5, interpolation="linear",
                          variation=m.TextureVariation(seed=7, scale_m=40.0, strength=0.35)),
        targets=m.Targets(_grid_targets(E0, N0, 38.0, 0.8),
                          m.SurveyAccuracy(m.Sigma3(0.01, 0.01, 0.02), seed=11)),
        lighting=m.Lighting(m.Sun(azimuth_deg=135.0, elevation_deg=50.0),
                            sun_strength=4.0, sky_strength=1.0),
    )
    plan = m.FlightPlan(
        camera=cam.id, image_prefix="DJI_",
        area=((E0 - 35, N0 - 35), (E0 + 35, N0 - 35), (E0 + 35, N0 + 35), (E0 - 35, N0 + 35)),
        altitude_agl_m=50.0, front_overlap_percent=80.0, side_overlap_percent=70.0,
        grid_angle_deg=0.0, crosshatch=False, terrain_following=False, tilt_deg=0.0,
        pose_noise=m.PoseNoise(0.3, 0.3, 0.2, 0.5, 0.5, 1.0), random_seed=42)
    project = m.Project(
        name="Example survey: 100 m x 100 m hills",
        description=("A 1-inch 20 MP drone camera flies a grid at 50 m over the central 70 x 70 m "
                     "of procedural hills "
                     "with 10 GCP targets (7 control, 3 check). Images render at a quarter "
                     "of the full size (1368 x 912 px) so the demo runs in minutes on 2 "
                     "cores; set resolution-scale to 1 for full-size images."),
        crs="EPSG:32632 (WGS 84 / UTM zone 32N)",
        origin=m.Origin(E0, N0, 0.0),
        scene=scene, cameras=(cam,), trajectory=m.Trajectory(flight_plan=plan),
        # What a typical survey camera does to its images: mild barrel distortion (in the
        # camera), vignetting, shot + read noise of a 1-inch sensor, a 1/1000 s exposure
        # at 8 m/s, JPEG at quality 95. The 'survey-ideal' template has none of it.
        effects=m.Effects(
            vignetting=m.Vignetting(0.2),
            sensor=m.Sensor(full_well_e=20000.0, read_noise_e=3.0, dark_current_e_per_s=0.5,
                            exposure_time_s=0.001, adc_bits=12, exposure_scale=0.8, seed=5),
            motion_blur=m.MotionBlur(0.001, 8.0), jpeg=m.Jpeg(95)),
        # one worker using both cores: two workers hold two copies of the scene and its
        # 4000 x 4000 texture and render 20-40 % slower on 2 cores (designer bench render)
        render=m.Render(preset="survey", pixel_filter_type="box", pixel_filter_width_px=1.0,
                        resolution_scale=0.25, workers=1, output_format="png", bit_depth=8),
        outputs=m.Outputs("output", ("colmap", "odm", "metashape", "opk", "gcp")),
    )
    return Template(project)


def survey_ideal() -> Template:
    """The example survey with an ideal camera: no distortion and no image effects."""
    import dataclasses

    tpl = survey()
    cam = dataclasses.replace(tpl.project.cameras[0], distortion=None)
    project = dataclasses.replace(
        tpl.project, name="Example survey, ideal camera", cameras=(cam,), effects=None,
        description=("The example survey seen by an ideal pinhole camera: no lens distortion, "
                     "no vignetting, no noise, no compression: only what the renderer must "
                     "do."))
    return Template(project)


def survey_dynamic() -> Template:
    """The example survey in a world that changes during the flight (docs/world.md), each
    change switched on lightly: a time line (5 m/s, 8 s turns, take-off 09:30 UTC), the
    sun moving with it, drifting cloud shadows (20 % cover, 3 m/s wind) and a car and a
    person crossing the block."""
    import dataclasses

    tpl = survey()
    p = tpl.project
    E0, N0 = p.origin.E0, p.origin.N0
    lighting = dataclasses.replace(
        p.scene.lighting, sun=m.SunOverTime(),
        clouds=m.CloudShadows(cover=0.2, size_m=40.0, softness_m=8.0, depth=0.5,
                              wind_speed_m_s=3.0, wind_direction_deg=60.0, seed=4))
    movers = (
        m.MovingObject("car1", (m.PathPoint(E0 - 45, N0 - 20), m.PathPoint(E0 + 45, N0 + 10)),
                       speed_m_s=2.0, shape="car", albedo_rgb=(0.6, 0.08, 0.06)),
        m.MovingObject("walker1", (m.PathPoint(E0 + 20, N0 - 40), m.PathPoint(E0 + 10, N0 + 40)),
                       speed_m_s=1.2, shape="person", albedo_rgb=(0.1, 0.2, 0.6)),
    )
    scene = dataclasses.replace(p.scene, lighting=lighting, moving_objects=movers)
    trajectory = dataclasses.replace(
        p.trajectory, time_line=m.TimeLine("2026-06-21T09:30:00Z", speed_m_s=5.0, turn_s=8.0))
    project = dataclasses.replace(
        p, name="Example survey, changing world", scene=scene, trajectory=trajectory,
        description=("The example survey flown at 5 m/s from 09:30 UTC on 21 June: the sun "
                     "moves during the flight, cloud shadows drift with a 3 m/s wind, a car "
                     "and a person cross the block. Masks of the moving objects and each "
                     "image's time are in the ground truth."))
    return Template(project)


def _house(id_: str, E: float, N: float, width_m: float, depth_m: float, roof: str,
           eave_m: float, ridge_m: float | None = None) -> m.Building:
    """A rectangular building centred on (E, N), ``width_m`` east-west, ``depth_m``
    north-south."""
    w, d = width_m / 2, depth_m / 2
    corners = ((E - w, N - d), (E + w, N - d), (E + w, N + d), (E - w, N + d))
    return m.Building(id_, tuple(m.PathPoint(x, y) for x, y in corners), roof, eave_m, ridge_m)


def survey_structures() -> Template:
    """The example survey with what practitioners lose accuracy to (docs/world.md): four
    buildings (gable, hip, a flat 12 m block), grass, shrubs and trees swaying in a 5°
    wind; the grid flown at 5 m/s by a nadir + four 45° oblique rig (a longer lens on
    the obliques; 70 % / 60 % overlaps, the obliques add the rest), then an orbit around
    the buildings by a drone camera with a rolling shutter (20 ms readout)."""
    import dataclasses

    from designer.core.rig import PENTA_MOUNTS

    tpl = survey()
    p = tpl.project
    E0, N0 = p.origin.E0, p.origin.N0
    sensor = dataclasses.replace(phantom4pro("nadir"), distortion=None,
                                 name="1-inch 20 MP, 8.8 mm, global shutter")
    drone = dataclasses.replace(
        sensor, id="drone", rolling_shutter=m.RollingShutter(readout_s=0.02),
        name="1-inch 20 MP, 8.8 mm, electronic (rolling) shutter, 20 ms readout")
    oblique = dataclasses.replace(sensor, id="oblique", focal_length_mm=12.0,
                                  name="1-inch 20 MP, 12 mm, global shutter")
    rig = m.Rig("penta", tuple(m.Mount("nadir" if s == "_N" else "oblique", s, o, ph, k)
                               for s, o, ph, k in PENTA_MOUNTS))
    buildings = (
        _house("house1", E0 - 19, N0 - 19, 10.0, 8.0, "gable", 5.0, 8.0),
        _house("house2", E0 + 19, N0 - 19, 12.0, 9.0, "hip", 4.5, 7.5),
        _house("block", E0 - 19, N0 + 19, 14.0, 10.0, "flat", 12.0),
        _house("barn", E0 - 19, N0, 8.0, 12.0, "gable", 4.0, 7.0),
    )
    vegetation = m.Vegetation(
        (m.PlantGroup(0.5, "grass-tuft", height_sd_m=0.05),
         m.PlantGroup(0.02, "shrub", height_sd_m=0.2),
         m.PlantGroup(0.002, "tree", height_m=7.0, height_sd_m=1.5)),
        seed=5, clearance_m=1.0, wind=m.Wind(5.0, 4.0, 60.0))
    scene = dataclasses.replace(p.scene, buildings=buildings, vegetation=vegetation)
    plan = dataclasses.replace(p.trajectory.flight_plan, camera=rig.name, pose_noise=None,
                               front_overlap_percent=70.0, side_overlap_percent=60.0)
    orbit = m.OrbitPattern(camera=drone.id, image_prefix="ORBIT_",
                           centre=m.Point3(E0 - 5, N0, 0.0), radius_m=35.0, height_m=30.0,
                           n_stations=16)
    trajectory = dataclasses.replace(
        p.trajectory, flight_plan=plan, rigs=(rig,), patterns=(orbit,),
        time_line=m.TimeLine("2026-06-21T09:30:00Z", speed_m_s=5.0, turn_s=8.0))
    project = dataclasses.replace(
        p, name="Example survey with structures", cameras=(drone, sensor, oblique),
        scene=scene, trajectory=trajectory,
        description=("The example survey with four buildings, grass, shrubs and trees "
                     "swaying in the wind: the grid flown at 5 m/s by a nadir + four 45° "
                     "oblique rig, then an orbit around the buildings by a rolling-shutter "
                     "camera (20 ms readout). Compare its clouds with the bare earth "
                     "(designer compare --surface dtm) or the surface (dsm)."))
    return Template(project)


#: the survey-block's flight area (m a side) and its GCP layout: control on a 4 × 4 grid
#: (16 for about 720 images: 2.2 per 100 images, in the 2–3 per 100 beyond which
#: Sanz-Ablanedo et al. 2018 find accuracy levels off), its outer ring 10 m inside the
#: area's edge so every point is seen by several strips; check points on the 3 × 3 grid
#: between them, where the block is weakest
BLOCK_AREA_M = 350.0
BLOCK_CONTROL_OFFSETS_M = (-165.0, -55.0, 55.0, 165.0)
BLOCK_CHECK_OFFSETS_M = (-110.0, 0.0, 110.0)


def survey_block() -> Template:
    """The example survey at a real survey's size: 500 × 500 m of hills, a 350 × 350 m
    flight area (12.25 ha, about 720 images with the example's camera, height and
    overlaps), the same texture, 16 control and 9 check GCPs spread over the block."""
    import dataclasses

    tpl = survey()
    p = tpl.project
    E0, N0 = p.origin.E0, p.origin.N0
    half_terrain, half_area = 250.0, BLOCK_AREA_M / 2
    terrain = dataclasses.replace(
        p.scene.terrain, extent=m.Extent(E0 - half_terrain, N0 - half_terrain,
                                         E0 + half_terrain, N0 + half_terrain),
        source=dataclasses.replace(p.scene.terrain.source, hill_size_m=150.0))
    control = [(E0 + a, N0 + b) for b in BLOCK_CONTROL_OFFSETS_M for a in BLOCK_CONTROL_OFFSETS_M]
    check = [(E0 + a, N0 + b) for b in BLOCK_CHECK_OFFSETS_M for a in BLOCK_CHECK_OFFSETS_M]
    targets = tuple(
        m.Target(id=f"{prefix}{i + 1:02d}", role=role, shape="checker", size_m=0.8,
                 true=m.TruePosition(E, N))
        for prefix, role, points in (("GCP", "control", control), ("CHK", "check", check))
        for i, (E, N) in enumerate(points))
    scene = dataclasses.replace(
        p.scene, terrain=terrain,
        # the example's 20 m tiles, 25 a side over 500 m; the variation's 40 m keeps them
        # from repeating across the block
        texture=dataclasses.replace(p.scene.texture, repeat_X=25, repeat_Y=25),
        targets=dataclasses.replace(p.scene.targets, targets=targets))
    area = tuple((E0 + a * half_area, N0 + b * half_area)
                 for a, b in ((-1, -1), (1, -1), (1, 1), (-1, 1)))
    plan = dataclasses.replace(p.trajectory.flight_plan, area=area)
    project = dataclasses.replace(
        p, name="Survey block: 12 ha, about 720 images", scene=scene,
        trajectory=dataclasses.replace(p.trajectory, flight_plan=plan),
        description=("The example survey at a real survey's size: the same camera, height "
                     "(50 m), overlaps (80 % / 70 %) and texture over a 350 x 350 m flight "
                     "area (12.25 ha, about 720 images) on 500 x 500 m of hills. 16 control "
                     "GCPs on a 4 x 4 grid (about 2.2 per 100 images, the density beyond "
                     "which accuracy levels off, Sanz-Ablanedo et al. 2018) and 9 check "
                     "points between them. Images render at a quarter of the full size."))
    return Template(project)


#: a block's declared terrain reaches this far past its flight area on every side (the
#: example's 15 m)
BLOCK_TERRAIN_MARGIN_M = 15.0


def block_of_side(project: m.Project, area_m: float) -> m.Project:
    """``project`` (the example survey, or a project like it) flown over a square area
    ``area_m`` a side about its origin: the declared terrain 15 m wider on every side,
    the ground texture's tiles kept 20 m across, control GCPs on a k × k grid (k = 4 at
    350 m as in the survey-block template, at least 3) with the outer ring 10 m inside
    the area, check points on the grid between them. ``area_m`` a whole number of metres
    keeps the terrain's extent a whole number of 0.5 m grid cells."""
    import dataclasses

    E0, N0 = project.origin.E0, project.origin.N0
    half = area_m / 2
    terrain_half = half + BLOCK_TERRAIN_MARGIN_M
    terrain = dataclasses.replace(project.scene.terrain, extent=m.Extent(
        E0 - terrain_half, N0 - terrain_half, E0 + terrain_half, N0 + terrain_half))
    tiles = max(1, round(2 * terrain_half / 20.0))
    texture = dataclasses.replace(project.scene.texture, repeat_X=tiles, repeat_Y=tiles)
    k = max(3, round(4 * area_m / BLOCK_AREA_M))
    inset = max(half - 10.0, half / 2)
    control = [-inset + 2 * inset * i / (k - 1) for i in range(k)]
    check = [(a + b) / 2 for a, b in itertools.pairwise(control)]
    targets = tuple(
        m.Target(id=f"{prefix}{i + 1:02d}", role=role, shape="checker", size_m=0.8,
                 true=m.TruePosition(E0 + a, N0 + b))
        for prefix, role, offsets in (("GCP", "control", control), ("CHK", "check", check))
        for i, (a, b) in enumerate((a, b) for b in offsets for a in offsets))
    old = project.scene.targets or m.Targets(())
    scene = dataclasses.replace(project.scene, terrain=terrain, texture=texture,
                                targets=dataclasses.replace(old, targets=targets))
    area = tuple((E0 + a * half, N0 + b * half)
                 for a, b in ((-1, -1), (1, -1), (1, 1), (-1, 1)))
    plan = dataclasses.replace(project.trajectory.flight_plan, area=area)
    return dataclasses.replace(project, scene=scene, trajectory=dataclasses.replace(
        project.trajectory, flight_plan=plan))


def validation_cube() -> Template:
    """A 4 m cube on flat ground seen by 24 oblique photos on a circle: exact geometry."""
    cam = m.Camera(id="a7r4", name="Sony a7R IV, 35 mm lens", focal_length_mm=35.0,
                   sensor_width_mm=35.7, sensor_height_mm=23.8,
                   image_width_px=9504, image_height_px=6336)
    photos = []
    centre = np.array([0.0, 0.0, 2.0])
    for i in range(24):
        a = 2 * np.pi * i / 24
        C = np.array([22.0 * np.sin(a), 22.0 * np.cos(a), 12.0])
        omega, phi, kappa = _look_at_opk_deg(C, centre)
        photos.append(m.ExteriorOrientation(
            f"ORBIT_{i + 1:02d}.png", cam.id, round(float(C[0]), 6) + 0.0,
            round(float(C[1]), 6) + 0.0,
            float(C[2]), omega, phi, kappa))
    corners = [(-10.0, -10.0), (10.0, -10.0), (10.0, 10.0), (-10.0, 10.0),
               (-10.0, 0.0), (10.0, 0.0), (0.0, -10.0), (0.0, 10.0)]
    targets = tuple(
        m.Target(f"T{i + 1}", "check" if i >= 6 else "control", "checker", 0.5,
                 m.TruePosition(X, Y, 0.0),
                 m.SurveyedPosition(m.Point3(X, Y, 0.0), m.Sigma3(0.002, 0.002, 0.003)))
        for i, (X, Y) in enumerate(corners))
    scene = m.Scene(
        # the experiment measures against the background beyond the plate: no surroundings
        terrain=m.Terrain(m.Extent(-30.0, -30.0, 30.0, 30.0), m.FlatTerrain(0.0), "none"),
        texture=m.Texture(m.ProceduralTexture("noise", seed=1, texel_size_m=0.02),
                          repeat_X=6, repeat_Y=6, interpolation="linear"),
        targets=m.Targets(targets),
        objects=(m.SceneObject("cube", "cube.obj", m.Placement(
            m.Point3(0.0, 0.0, 0.0), 0.0, 0.0, 0.0, scale=4.0)),),
        lighting=m.Lighting(m.Sun(200.0, 45.0), sun_strength=4.0, sky_strength=1.0),
    )
    project = _local_project(
        "Validation cube",
        "A 4 m cube (mesh cube.obj, unit cube scaled 4x) on a flat plane, 24 photos on a 22 m "
        "circle at 12 m height looking at its centre. Pinhole camera, no effects: "
        "reconstructions should match to a fraction of GSD.",
        scene, cam, m.Trajectory(exterior_orientations=tuple(photos)),
        render=m.Render(preset="survey", resolution_scale=0.125, workers=2),
        outputs=m.Outputs("output", ("colmap", "opk", "gcp")),
    )
    return Template(project, {"cube.obj": cube_obj_bytes()})


def _local_project(name: str, description: str, scene: m.Scene, camera: m.Camera,
                   trajectory: m.Trajectory, **settings) -> m.Project:
    """A project of one camera in a local engineering frame (m) with its origin at 0, as
    the experiments' templates (validation cube, PSF, texture) are; ``settings`` are the
    project's other fields (render, outputs, effects)."""
    return m.Project(name=name, description=description, crs="local engineering frame (m)",
                     origin=m.Origin(0.0, 0.0, 0.0), scene=scene, cameras=(camera,),
                     trajectory=trajectory, **settings)


def psf() -> Template:
    """Slanted edges photographed at nadir to measure the point spread function."""
    cam = phantom4pro("p4p")
    photos = tuple(
        m.ExteriorOrientation(f"PSF_{i + 1:02d}.png", cam.id, float(x), float(y), 30.0,
                              0.0, 0.0, 0.0)
        for i, (x, y) in enumerate((x, y) for y in (-2.0, 0.0, 2.0) for x in (-2.0, 0.0, 2.0)))
    scene = m.Scene(
        # the experiment is designed around its plane and background: no surroundings
        terrain=m.Terrain(m.Extent(-20.0, -20.0, 20.0, 20.0), m.FlatTerrain(0.0), "none"),
        texture=m.Texture(m.ProceduralTexture("slanted-edge", seed=0, texel_size_m=0.005),
                          repeat_X=8, repeat_Y=8, interpolation="closest"),
        lighting=m.Lighting(m.Sun(180.0, 60.0), sun_strength=4.0, sky_strength=1.0),
    )
    project = _local_project(
        "PSF: slanted edges",
        "Nadir photos from 30 m of a plane tiled with slanted edges (5 m tiles, 5 mm texels, "
        "closest interpolation) to measure the system's point spread function: Cycles pixel "
        "filter plus a 0.7 px Gaussian blur.",
        scene, cam, m.Trajectory(exterior_orientations=photos),
        effects=m.Effects(blur=m.Blur(0.7)),
        render=m.Render(preset="metrology", samples=256, pixel_filter_type="gaussian",
                        pixel_filter_width_px=1.5, resolution_scale=0.5, workers=2,
                        output_format="png", bit_depth=16),
        outputs=m.Outputs("output", ("opk",)),
    )
    return Template(project)


def texture() -> Template:
    """An image texture (texture.png, seamless) tiled over a plane, flown at a given GSD."""
    cam = m.Camera(id="s100", name="Canon PowerShot S100", focal_length_mm=5.2,
                   sensor_width_mm=7.6, sensor_height_mm=5.7,
                   image_width_px=4000, image_height_px=3000,
                   distortion=m.BrownConradyDistortion(k1=-0.05, k2=0.02, p1=1e-4, p2=-1e-4))
    scene = m.Scene(
        # the experiment is designed around its plane and background: no surroundings
        terrain=m.Terrain(m.Extent(-20.0, -20.0, 20.0, 20.0), m.FlatTerrain(0.0), "none"),
        texture=m.Texture(m.ImageTexture("texture.png"), repeat_X=8, repeat_Y=8,
                          interpolation="linear"),
        lighting=m.Lighting(m.SunPosition("2024-06-21T11:00:00+02:00", 47.37, 8.54),
                            sun_strength=4.0, sky_strength=1.0),
    )
    plan = m.FlightPlan(
        camera=cam.id, image_prefix="TEX_",
        area=((-15.0, -15.0), (15.0, -15.0), (15.0, 15.0), (-15.0, 15.0)),
        gsd_m=0.02, front_overlap_percent=75.0, side_overlap_percent=65.0,
        grid_angle_deg=30.0, crosshatch=True, terrain_following=False, tilt_deg=0.0,
        pose_noise=None, random_seed=0)
    project = _local_project(
        "Texture: an image texture tiled 8 x 8",
        "A seamless 512 x 512 px image (texture.png) tiled 8 x 8 over a 40 m plane: 5 m "
        "tiles, about 1 cm texels; a crosshatch flight at 2 cm GSD.",
        scene, cam, m.Trajectory(flight_plan=plan),
        render=m.Render(preset="draft", resolution_scale=0.25, workers=2),
        outputs=m.Outputs("output", ("colmap", "metashape")),
    )
    return Template(project, {"texture.png": seamless_texture_png(512, seed=5)})


_BUILDERS = {"survey": survey, "survey-ideal": survey_ideal, "survey-dynamic": survey_dynamic,
             "survey-structures": survey_structures, "survey-block": survey_block,
             "validation-cube": validation_cube, "psf": psf, "texture": texture}


def template(name: str) -> Template:
    """The template called ``name`` (one of :data:`TEMPLATE_NAMES`)."""
    return _BUILDERS[name]()
