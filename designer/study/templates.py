"""Example studies written by ``designer study new FILE --template NAME``.

Each writes the study file and its base project (``STEM-base.xml`` beside it): a
60 × 60 m hilly field with ten GCP targets flown at 30 m by a small 640 × 480
camera (GSD ≈ 6 cm), small enough to run a study on a laptop. ``tiny`` uses 160 × 120
images for tests.
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

from designer.project import model as m

ORIGIN = (500000.0, 5000000.0, 250.0)
#: where the GCP targets stand, metres east and north of the origin
GCP_SPOTS_M = ((-14, -14), (0, -12), (14, -14), (-14, 14), (0, 12), (14, 14), (0, 0),
               (-13, 0), (13, 0), (6, 6))


def base_project(width_px: int = 640, height_px: int = 480, samples: int = 16,
                 origin: tuple[float, float, float] = ORIGIN) -> m.Project:
    """A 60 × 60 m hilly field, 10 GCP targets, a grid flight at 30 m (GSD 6 cm at 640 px)."""
    E0, N0, H0 = origin
    cam = m.Camera(id="cam", focal_length_mm=5.0, sensor_width_mm=6.4, sensor_height_mm=4.8,
                   image_width_px=width_px, image_height_px=height_px)
    targets = tuple(
        m.Target(f"G{k:02d}", "control", "checker", 1.5, m.TruePosition(E0 + x, N0 + y))
        for k, (x, y) in enumerate(GCP_SPOTS_M))
    scene = m.Scene(
        terrain=m.Terrain(m.Extent(E0 - 30, N0 - 30, E0 + 30, N0 + 30), m.ProceduralTerrain(
            seed=5, grid_spacing_m=0.5, roughness=0.3, min_height_m=H0 - 3.0,
            max_height_m=H0 + 3.0, hill_size_m=60.0)),  # the largest hills span the field
        # the variation keeps the tile's copies in the surroundings from repeating it
        texture=m.Texture(m.ProceduralTexture("grass", seed=2, texel_size_m=0.03 * 640 / width_px),
                          repeat_X=1, repeat_Y=1, interpolation="linear",
                          variation=m.TextureVariation(seed=7, scale_m=40.0, strength=0.35)),
        targets=m.Targets(targets, m.SurveyAccuracy(m.Sigma3(0.01, 0.01, 0.015), seed=1)),
        lighting=m.Lighting(m.Sun(azimuth_deg=150.0, elevation_deg=55.0)),
    )
    plan = m.FlightPlan(
        camera=cam.id, image_prefix="IMG_",
        area=((E0 - 15, N0 - 15), (E0 + 15, N0 - 15), (E0 + 15, N0 + 15), (E0 - 15, N0 + 15)),
        altitude_agl_m=30.0, front_overlap_percent=65.0, side_overlap_percent=55.0,
        pose_noise=m.PoseNoise(0.2, 0.2, 0.1, 0.5, 0.5, 1.0), random_seed=3)
    processing = m.Processing(
        calibration=m.Calibration("fixed"),
        gcps=m.GcpProcessing("bundle", marking_sigma_px=0.5, seed=1,
                             control=m.ControlSelection(count=5, spread="even")),
        matching=m.Matching(max_features=4096))
    return m.Project(
        name="study base survey", crs="EPSG:32632", origin=m.Origin(E0, N0, H0), scene=scene,
        cameras=(cam,), trajectory=m.Trajectory(flight_plan=plan),
        render=m.Render(preset="survey", samples=samples, workers=1),
        outputs=m.Outputs("output", ("colmap", "opk", "gcp")), processing=processing)


_HEAD = ('<?xml version="1.0" encoding="UTF-8"?>\n'
         '<study xmlns="urn:designer:project:1" schema-version="1.0" name="{name}">\n'
         '  <description>{description}</description>\n'
         '  <base-project file="{base}"/>\n')

STUDIES = {
    "gcp-count": ("How many control GCPs does the check-point accuracy need? The others are "
                  "check points; every replicate re-draws which GCPs are control and the "
                  "marking error. One render serves every run.",
                  '  <factor name="control-count">\n'
                  '    <description>GCPs used as control</description>\n'
                  '    <values>3 4 6 8</values>\n  </factor>\n'
                  '  <design>one-at-a-time</design>\n'
                  '  <replicates count="3" vary="gcp-selection marking-error survey-error"/>\n'
                  '  <metrics>check_rmse_xy_m check_rmse_z_m cloud_nmad_m</metrics>\n'),
    "flight-geometry": ("Does a convergent flight (crosshatch, tilted camera) stop the doming "
                        "of a self-calibrated camera? Each geometry with a fixed and a "
                        "self-calibrated (radial) camera, the GCPs as a similarity after the "
                        "adjustment or in it; the dome is measured on the dense cloud.",
                        '  <factor name="flight-geometry">\n'
                        '    <values>nadir crosshatch tilted</values>\n  </factor>\n'
                        '  <factor name="calibration">\n'
                        '    <values>fixed radial</values>\n  </factor>\n'
                        '  <factor name="gcp-mode">\n'
                        '    <values>similarity bundle</values>\n  </factor>\n'
                        '  <design>full-factorial</design>\n'
                        '  <replicates count="2" vary="marking-error pre-calibration"/>\n'
                        '  <metrics>dome_amplitude_m check_rmse_z_m cloud_median_m k1_error'
                        '</metrics>\n'),
    "doming": ("Does a self-calibrated parallel block over flat ground dome, and does a "
               "convergent flight cure it (James and Robson 2014)? A flat 120 m field flown "
               "over 60 x 60 m at 30 m (GSD 6 cm) nadir or with the camera tilted 20 deg "
               "forward (the view alternating with the line direction), self-calibrated "
               "(radial) from a pre-calibration wrong by 5 px in f and 0.02 in k1, the GCPs "
               "as a similarity, 4 DN of sensor noise; with the SIFT features of a weak "
               "block (512 an image) and of a full one (4096). Each replicate re-draws the "
               "pre-calibration and the marking error; the dome is fitted to the tie points "
               "over the flown area (dense matching on in the base gives the dense cloud's "
               "too).",
               '  <factor name="tilt-deg">\n'
               '    <description>forward camera tilt (0: parallel axes)</description>\n'
               '    <values>0 20</values>\n  </factor>\n'
               '  <factor name="max-features">\n'
               '    <description>SIFT features per image</description>\n'
               '    <values>512 4096</values>\n  </factor>\n'
               '  <design>full-factorial</design>\n'
               '  <replicates count="3" vary="pre-calibration marking-error"/>\n'
               '  <metrics>sparse_dome_gsd check_rmse_z_gsd focal_error_px k1_error '
               'k1_error_beyond_focal</metrics>\n'),
    "block-size": ("How does the error grow with the block? The example survey (its "
                   "camera, height, overlaps and hills) over square areas of 70, 184 and 352 "
                   "m a side (about 60, 240 and 720 images, the scale bench's blocks; "
                   "control GCPs on a grid, about 2 to 3 per 100 images, check points "
                   "between them), images at a quarter of the example's size (342 x 228 px), "
                   "with a fixed and a self-calibrated (radial) camera starting from a "
                   "pre-calibration wrong by 5 px in f and 0.02 in k1; the GCPs as a "
                   "similarity after the adjustment. One render per block.",
                   '  <factor name="block-side-m">\n'
                   '    <description>side of the flight area</description>\n'
                   '    <values>70 184 352</values>\n  </factor>\n'
                   '  <factor name="calibration">\n'
                   '    <values>fixed radial</values>\n  </factor>\n'
                   '  <design>full-factorial</design>\n'
                   '  <replicates count="1"/>\n'
                   '  <metrics>registered check_rmse_xy_m check_rmse_z_gsd sparse_dome_gsd '
                   'focal_error_px k1_error</metrics>\n'),
    "altitude": ("Flight altitude (GSD) against accuracy and render time.",
                 '  <factor name="altitude-m">\n'
                 '    <range start="25" stop="40" step="5"/>\n  </factor>\n'
                 '  <design>one-at-a-time</design>\n'
                 '  <replicates count="2" vary="marking-error"/>\n'
                 '  <metrics>check_rmse_xy_m check_rmse_z_m check_rmse_z_gsd</metrics>\n'),
    "rolling-shutter": ("How much does a rolling shutter cost at 8 m/s, and does "
                        "compensation in the bundle adjustment (a velocity per image during "
                        "the readout) recover it? Readouts of 10 and 30 ms, each processed "
                        "without and with compensation; one render per readout.",
                        '  <factor name="rolling-shutter-readout-s">\n'
                        '    <values>0.01 0.03</values>\n  </factor>\n'
                        '  <factor name="rolling-shutter-processing">\n'
                        '    <values>none compensate</values>\n  </factor>\n'
                        '  <design>full-factorial</design>\n'
                        '  <replicates count="1"/>\n'
                        '  <metrics>check_rmse_xy_m check_rmse_z_m check_rmse_z_gsd</metrics>\n'),
    "rig-obliques": ("Do obliques from a rig (nadir + four 45° cameras, one camera type) "
                     "help a self-calibrating adjustment? The grid flown by the nadir "
                     "camera alone or by the rig, with a fixed (wrong) and a self-calibrated "
                     "(radial) camera; one render per flight.",
                     '  <factor name="flight-camera">\n'
                     '    <values>cam penta</values>\n  </factor>\n'
                     '  <factor name="calibration">\n'
                     '    <values>fixed radial</values>\n  </factor>\n'
                     '  <design>full-factorial</design>\n'
                     '  <replicates count="1"/>\n'
                     '  <metrics>check_rmse_xy_m check_rmse_z_m focal_error_px k1_error '
                     'cloud_median_m</metrics>\n'),
    "tiny": ("A tiny study for tests: a processing-only factor and a render factor.",
             '  <factor name="marking-sigma-px">\n    <values>0.2 2</values>\n  </factor>\n'
             '  <factor name="sun-elevation-deg">\n    <values>40</values>\n  </factor>\n'
             '  <design>one-at-a-time</design>\n'
             '  <replicates count="1"/>\n'
             '  <metrics>check_rmse_z_m registered</metrics>\n'),
    "example-processing": ("The example survey (60 images of 100 m x 100 m of hills) processed "
                           "four ways: a fixed or a self-calibrated (radial) camera, the GCPs "
                           "as a similarity after the adjustment or in it, each with five "
                           "draws of a 0.5 px marking error. One render, one feature "
                           "extraction and matching, one SfM model per calibration.",
                           '  <factor name="calibration">\n'
                           '    <values>fixed radial</values>\n  </factor>\n'
                           '  <factor name="gcp-mode">\n'
                           '    <values>similarity bundle</values>\n  </factor>\n'
                           '  <design>full-factorial</design>\n'
                           '  <replicates count="5" vary="marking-error"/>\n'
                           '  <metrics>check_rmse_xy_m check_rmse_z_m check_rmse_z_gsd'
                           ' cloud_median_m</metrics>\n'),
}

TEMPLATE_NAMES = tuple(STUDIES)


def template_base(name: str) -> m.Project:
    if name == "example-processing":
        from designer.project.templates import template

        p = template("survey").project
        return replace(p, processing=m.Processing(
            gcps=m.GcpProcessing(mode="similarity", marking_sigma_px=0.5, seed=1),
            matching=m.Matching(4096)))
    if name == "tiny":
        p = base_project(160, 120, samples=4)
        E0, N0, _ = ORIGIN
        half = 7.0  # a 14 x 14 m flight at 12 m (GSD 10 cm), 3 lines of 3-4 images
        targets = tuple(replace(t, size_m=1.0, true=m.TruePosition(
            E0 + 0.5 * (t.true.X - E0), N0 + 0.5 * (t.true.Y - N0))) for t in p.targets)
        p = replace(p, scene=replace(p.scene, targets=replace(p.scene.targets,
                                                              targets=targets),
                                     texture=replace(p.scene.texture, source=replace(
                                         p.scene.texture.source, texel_size_m=0.05))))
        plan = replace(p.trajectory.flight_plan, altitude_agl_m=12.0,
                       area=((E0 - half, N0 - half), (E0 + half, N0 - half),
                             (E0 + half, N0 + half), (E0 - half, N0 + half)),
                       front_overlap_percent=70.0, side_overlap_percent=60.0)
        p = replace(p, trajectory=m.Trajectory(flight_plan=plan),
                    processing=replace(p.processing, gcps=replace(
                        p.processing.gcps, mode="similarity",
                        control=m.ControlSelection(count=4)), matching=m.Matching(1024)))
        return p
    if name == "rig-obliques":
        from designer.core.rig import PENTA_MOUNTS

        p = template_base("flight-geometry")
        rig = m.Rig("penta", tuple(m.Mount("cam", s, o, ph, k) for s, o, ph, k in PENTA_MOUNTS))
        return replace(p, trajectory=replace(p.trajectory, rigs=(rig,)),
                       processing=replace(p.processing, dense="none"))
    if name == "rolling-shutter":
        p = base_project()
        cam = replace(p.cameras[0], rolling_shutter=m.RollingShutter(0.03))
        time_line = m.TimeLine("2026-06-21T09:30:00Z", speed_m_s=8.0, turn_s=5.0)
        return replace(p, cameras=(cam,),
                       trajectory=replace(p.trajectory, time_line=time_line))
    if name == "doming":
        return doming_base()
    if name == "block-size":
        return block_size_base()
    if name == "flight-geometry":
        p = base_project()
        cam = replace(p.cameras[0], distortion=m.BrownConradyDistortion(k1=-0.08, k2=0.01))
        proc = replace(p.processing, calibration=m.Calibration(
            "fixed", m.PreCalibrationError(focal_px=5.0, k1=0.02, seed=1)), dense="cpu")
        return replace(p, cameras=(cam,), processing=proc)
    return base_project()


def doming_base() -> m.Project:
    """The flight-geometry base over flat ground: a 120 × 120 m field at the origin's
    height, the GCPs spread twice as wide, a 60 × 60 m flight at front 80 % / side 65 %
    (75 images nadir, 95 tilted 20° forward), 4 DN of sensor noise, radial
    self-calibration and the GCPs as a similarity; no dense matching (the tie points'
    dome is the study's measure; docs/studies.md, "Doming on flat ground")."""
    p = template_base("flight-geometry")
    E0, N0, H0 = ORIGIN
    targets = tuple(replace(t, true=m.TruePosition(E0 + 2.0 * (t.true.X - E0),
                                                   N0 + 2.0 * (t.true.Y - N0)))
                    for t in p.targets)
    scene = replace(p.scene,
                    terrain=m.Terrain(m.Extent(E0 - 60, N0 - 60, E0 + 60, N0 + 60),
                                      m.FlatTerrain(H0)),
                    targets=replace(p.scene.targets, targets=targets))
    plan = replace(p.trajectory.flight_plan,
                   area=((E0 - 30, N0 - 30), (E0 + 30, N0 - 30), (E0 + 30, N0 + 30),
                         (E0 - 30, N0 + 30)),
                   front_overlap_percent=80.0, side_overlap_percent=65.0)
    processing = replace(p.processing,
                         calibration=replace(p.processing.calibration, mode="radial"),
                         gcps=replace(p.processing.gcps, mode="similarity"), dense="none")
    return replace(p, scene=scene, trajectory=m.Trajectory(flight_plan=plan),
                   processing=processing,
                   effects=m.Effects(sensor_noise=m.SensorNoise(4.0, seed=1)))


def block_size_base() -> m.Project:
    """The example survey at a quarter of its image size (resolution scale 0.0625: 342 ×
    228 px), its camera pre-calibrated with an error of 5 px in f and 0.02 in k1, the
    GCPs as a similarity after the adjustment, no dense matching (the tie points' dome
    is measured)."""
    from designer.project.templates import template

    p = template("survey").project
    processing = m.Processing(
        calibration=m.Calibration("fixed", m.PreCalibrationError(focal_px=5.0, k1=0.02,
                                                                 seed=1)),
        gcps=m.GcpProcessing(mode="similarity", marking_sigma_px=0.5, seed=1),
        dense="none")
    return replace(p, render=replace(p.render, resolution_scale=0.0625),
                   processing=processing)


def write_template(name: str, path: Path) -> list[Path]:
    """Write the study ``path`` and its ``base.xml``; the files written."""
    from designer.atomic import write_text_atomic
    from designer.project import write_project

    description, body = STUDIES[name]
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    base = path.parent / f"{path.stem}-base.xml"
    write_project(replace(template_base(name), name=f"{name} study base"), base)
    write_text_atomic(path, _HEAD.format(name=name, description=description, base=base.name) + body
                      + "</study>\n")
    return [path, base]
