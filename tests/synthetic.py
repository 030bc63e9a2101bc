"""The seeded synthetic scenes of the whole test suite, defined once.

* :data:`ORIGIN_WORLD` — a UTM-sized world origin (float32 there would be off by
  decimetres); every synthetic scene sits around it unless a test says otherwise;
* cameras: :func:`phantom4` (the 1-inch 20 MP survey camera), :func:`interior_for`
  (the same sensor with each lens model designer supports), :func:`pixel_camera` (square
  pixels, focal length in pixels) and, for projects, :func:`model_camera`;
* ground truth: :func:`random_poses`, :func:`grid_poses`, :func:`random_gcps`,
  :func:`grid_gcps`, :func:`survey` (poses + GCPs + their image observations);
* terrain: :func:`flat_terrain`, :func:`hilly_terrain` (height fields);
* projects for real renders: :func:`small_survey`, :func:`small_flight_survey` and
  :func:`write_project_file`;
* bad values: :func:`assert_located_error` (a project file with one value changed is
  refused with one-line problems naming the place);
* :func:`count_calls` — how often a real function is called (it still does its work).

Every function takes its seed (or ``numpy.random.Generator``) explicitly.
"""

from __future__ import annotations

import re
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest

from designer.core.distortion import BrownConrady, FisheyeEquidistant
from designer.core.heightfield import Heightfield
from designer.core.interior import InteriorOrientation
from designer.core.rotation import rotation_from_heading_tilt_roll, rotation_from_opk
from designer.core.truth import CameraPose, GroundControlPoint, observe_gcps
from designer.project import load_project, write_project
from designer.project import model as m
from designer.project.problems import ProjectError

#: a UTM-sized world origin (E, N, H) in metres
ORIGIN_WORLD = np.array([500000.0, 5000000.0, 250.0])

LENSES = ("pinhole", "opencv", "full_opencv", "fisheye", "nonsquare")


def phantom4(**changes) -> InteriorOrientation:
    """The 13.2 x 8.8 mm, 5472 x 3648 px sensor behind an 8.8 mm lens (DJI P4P class)."""
    params = dict(focal_length_mm=8.8, sensor_width_mm=13.2, sensor_height_mm=8.8,
                  image_width_px=5472, image_height_px=3648)
    params.update(changes)
    return InteriorOrientation(**params)


def interior_for(lens: str) -> InteriorOrientation:
    """The phantom4 sensor with an offset principal point and the named lens model."""
    common = dict(principal_point_x_mm=0.0513, principal_point_y_mm=-0.0371)
    if lens == "pinhole":
        return phantom4(**common)
    if lens == "opencv":
        return phantom4(**common, distortion=BrownConrady(k1=-0.11, k2=0.023, p1=7e-4,
                                                            p2=-3e-4))
    if lens == "full_opencv":
        return phantom4(**common, distortion=BrownConrady(k1=-0.11, k2=0.023, k3=-0.004,
                                                            p1=7e-4, p2=-3e-4))
    if lens == "fisheye":
        return phantom4(**common, focal_length_mm=4.5,
                        distortion=FisheyeEquidistant(k1=0.02, k2=-0.004, k3=0.001, k4=-1e-4))
    if lens == "nonsquare":
        return phantom4(**common, sensor_height_mm=8.8 * 1.01, pixel_aspect=1.01,
                        distortion=BrownConrady(k1=-0.05, k3=0.002, p1=-4e-4, p2=9e-4))
    raise ValueError(lens)


def mapping_camera(distortion: bool = True) -> InteriorOrientation:
    """The phantom4 sensor with a small principal-point offset and mild Brown distortion."""
    return phantom4(principal_point_x_mm=0.012, principal_point_y_mm=-0.008,
                    distortion=BrownConrady(k1=-0.05, k2=0.01, k3=0.002, p1=1e-4, p2=-5e-5)
                    if distortion else None)


def pixel_camera(width, height, f_px, distortion, pp_px=(0.0, 0.0), f_mm=8.8
                 ) -> InteriorOrientation:
    """An interior orientation with square pixels, fx = f_px and the principal point
    ``pp_px`` (right, down) off the image centre."""
    pitch = f_mm / f_px
    return InteriorOrientation(f_mm, width * pitch, height * pitch, width, height,
                               pp_px[0] * pitch, -pp_px[1] * pitch, distortion=distortion)


def random_poses(rng: np.random.Generator, n: int = 6, height_m: float = 100.0):
    """Cameras over a 120 m square at ORIGIN_WORLD size, tilted up to 12 degrees, any heading."""
    poses = []
    for i in range(n):
        C = ORIGIN_WORLD + np.array([*rng.uniform(-60, 60, 2), height_m + rng.uniform(-5, 5)])
        R = rotation_from_heading_tilt_roll(
            rng.uniform(0, 2 * np.pi), *np.radians(rng.uniform(-12, 12, 2)))
        R = R @ rotation_from_opk(*np.radians(rng.uniform(-2, 2, 3)))
        poses.append(CameraPose(f"IMG_{i:04d}.png", C, R))
    return poses


def random_gcps(rng: np.random.Generator, n: int = 12, sigma_m: float = 0.02):
    gcps = []
    for i in range(n):
        true = ORIGIN_WORLD + np.array([*rng.uniform(-70, 70, 2), rng.uniform(-3, 3)])
        sigma = np.array([sigma_m, sigma_m, 1.5 * sigma_m])
        surveyed = true + rng.normal(0.0, sigma)
        role = "check" if i % 3 == 2 else "control"
        gcps.append(GroundControlPoint(f"GCP{i + 1:02d}", role, true, surveyed, sigma))
    return gcps


def survey(seed: int, lens: str = "opencv"):
    """(interior, poses, gcps, observations) of a seeded random survey."""
    rng = np.random.default_rng(seed)
    interior = interior_for(lens)
    poses = random_poses(rng)
    gcps = random_gcps(rng)
    return interior, poses, gcps, observe_gcps(gcps, poses, interior)


def grid_poses(seed=0, n=12) -> list[CameraPose]:
    """A 4-column grid of near-nadir images 80 m above the origin (names img_000.jpg…)."""
    rng = np.random.default_rng(seed)
    out = []
    for i in range(n):
        C = ORIGIN_WORLD + [(i % 4) * 25.0 - 37.5, (i // 4) * 30.0 - 30.0, 80.0 + rng.normal(0, 2)]
        R = rotation_from_opk(*np.radians(rng.normal(0, 3, 3)))
        out.append(CameraPose(f"img_{i:03d}.jpg", C, R))
    return out


def grid_gcps(seed=1) -> list[GroundControlPoint]:
    """Eight GCPs around the origin, five control and three check, 1 cm survey error."""
    rng = np.random.default_rng(seed)
    out = []
    for i in range(8):
        true = ORIGIN_WORLD + [rng.uniform(-40, 40), rng.uniform(-35, 35), rng.normal(0, 1)]
        out.append(GroundControlPoint(f"GCP{i}", "control" if i < 5 else "check", true,
                                      true + rng.normal(0, 0.01, 3), [0.01, 0.01, 0.02]))
    return out


def flat_terrain(x0=0.0, y0=0.0, size_m=600.0, spacing_m=5.0, height_m=50.0) -> Heightfield:
    n = round(size_m / spacing_m) + 1
    return Heightfield(x0, y0, spacing_m, spacing_m, np.full((n, n), height_m))


def hilly_terrain(x0=0.0, y0=0.0, size_m=400.0, spacing_m=2.0, relief_m=40.0) -> Heightfield:
    n = round(size_m / spacing_m) + 1
    x = np.linspace(0.0, size_m, n)
    X, Y = np.meshgrid(x, x)
    Z = 100.0 + relief_m * (0.6 * np.sin(X / 35.0) * np.cos(Y / 47.0)
                            + 0.4 * np.sin(X / 17.0 + Y / 23.0))
    return Heightfield(x0, y0, spacing_m, spacing_m, Z)


def model_camera(size_px=(640, 480), focal_length_mm=5.0, pixel_pitch_mm=0.01,
                 principal_point_mm=(0.0, 0.0), distortion=None, **changes) -> m.Camera:
    """The project camera "cam": ``size_px`` square pixels of ``pixel_pitch_mm``; other
    fields (a rolling shutter, ...) from ``changes``."""
    W, H = size_px
    return m.Camera(id="cam", focal_length_mm=focal_length_mm,
                    sensor_width_mm=W * pixel_pitch_mm, sensor_height_mm=H * pixel_pitch_mm,
                    image_width_px=W, image_height_px=H,
                    principal_point_x_mm=principal_point_mm[0],
                    principal_point_y_mm=principal_point_mm[1], distortion=distortion,
                    **changes)


def small_survey(
    origin=(0.0, 0.0, 0.0), principal_point_mm=(0.0, 0.0), n_photos=4, samples=16,
    effects=None, distortion=None, size_px=(640, 480), focal_length_mm=5.0,
    pixel_pitch_mm=0.01,
) -> m.Project:
    """A 40 x 40 m gentle terrain, 9 large checker targets, a few photos from 30 m."""
    E0, N0, H0 = origin
    cam = model_camera(size_px, focal_length_mm, pixel_pitch_mm, principal_point_mm,
                       distortion)
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


def write_project_file(project: m.Project, folder: Path) -> Path:
    """``folder/project.xml`` written from ``project`` (folder created)."""
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / "project.xml"
    write_project(project, path)
    return path


def assert_located_error(project: m.Project, folder: Path, edit: Callable[[str], str],
                         needle: str, words: str | tuple[str, ...], *,
                         any_located: bool = False) -> list[str]:
    """Write ``project`` to ``folder/project.xml``, change its text with ``edit`` (which
    must change something) and check that loading it is refused with one-line problems,
    the first of them located (``project.xml:LINE:COL: ``) on the first line that holds
    ``needle`` and containing ``words`` (each of them, when a tuple) — or, with
    ``any_located`` (an edit that makes more than one problem there), any of those
    located there. Returns all the lines."""
    path = write_project_file(project, folder)
    original = path.read_text()
    text = edit(original)
    assert text != original, "the edit changed nothing"
    path.write_text(text)
    with pytest.raises(ProjectError) as info:
        load_project(path)
    lines = info.value.lines
    line = next(i for i, x in enumerate(text.splitlines(), 1) if needle in x)
    located = [x for x in lines if re.match(rf".*project\.xml:{line}:\d+: ", x)]
    named = located if any_located else located[:1]
    wanted = (words,) if isinstance(words, str) else words
    assert any(all(w in x for w in wanted) for x in named), lines
    assert all("\n" not in x for x in lines), lines
    return lines


def count_calls(monkeypatch, module, name: str) -> list[tuple]:
    """Wrap ``module.name`` for the test so each call is recorded (its positional
    arguments, in the list returned) and then done by the real function."""
    real, calls = getattr(module, name), []

    def counted(*args, **kwargs):
        calls.append(args)
        return real(*args, **kwargs)

    monkeypatch.setattr(module, name, counted)
    return calls



def small_flight_survey(samples=16, origin=(500000.0, 5000000.0, 250.0), effects=None,
                        distortion=None) -> m.Project:
    """A 60 x 60 m hilly terrain flown at 30 m: a dozen 640 x 480 images for SfM tests.

    The texture's texel (3 cm) is half the GSD (6 cm), so the renderer resolves it without
    aliasing and SIFT finds repeatable features.
    """
    from dataclasses import replace

    from designer.study.templates import GCP_SPOTS_M, base_project

    E0, N0, _ = origin
    project = base_project(samples=samples, origin=origin)
    targets = tuple(  # seven of the study base's GCPs, two of them check points
        m.Target(f"G{k}", "check" if k in (1, 4) else "control", "checker", 1.5,
                 m.TruePosition(E0 + x, N0 + y))
        for k, (x, y) in enumerate(GCP_SPOTS_M[:7]))
    scene = replace(project.scene, targets=m.Targets(
        targets, m.SurveyAccuracy(m.Sigma3(0.0, 0.0, 0.0), seed=1)))
    return replace(
        project, name="SfM test survey", scene=scene,
        cameras=(replace(project.cameras[0], distortion=distortion),), effects=effects,
        render=replace(project.render, workers=2), processing=None,
        outputs=m.Outputs("output", ("colmap", "odm", "opk", "gcp")))


#: a five-camera oblique rig: (camera id, suffix, omega, phi, kappa deg, (W, H) px,
#: focal length mm, principal point offset mm) — each its own interior orientation
PENTA_MOUNTS = (
    ("nadir", "_N", 0.0, 0.0, 0.0, (200, 150), 2.5, (0.0, 0.0)),
    ("fwd", "_F", 45.0, 0.0, 0.0, (160, 120), 2.2, (0.05, -0.03)),
    ("back", "_B", -45.0, 0.0, 180.0, (160, 120), 2.2, (-0.04, 0.02)),
    ("left", "_L", 0.0, 45.0, 0.0, (180, 120), 2.0, (0.02, 0.04)),
    ("right", "_R", 0.0, -45.0, 0.0, (180, 120), 2.0, (-0.03, -0.01)),
)


def rig_survey(origin=(500000.0, 5000000.0, 250.0), n_stations=6, samples=16,
               tilt_deg=45.0) -> m.Project:
    """:func:`small_survey`'s terrain and 9 targets flown at 12 m by a nadir + four
    oblique rig (:data:`PENTA_MOUNTS`, obliques at ``tilt_deg``): tiny images of
    different sizes and focal lengths in one job."""
    from dataclasses import replace

    base = small_survey(origin=origin, n_photos=0, samples=samples)
    E0, N0, H0 = origin
    cameras, mounts = [], []
    for cam_id, suffix, omega, phi, kappa, (W, H), f_mm, (x0, y0) in PENTA_MOUNTS:
        cameras.append(m.Camera(id=cam_id, focal_length_mm=f_mm, sensor_width_mm=W * 0.01,
                                sensor_height_mm=H * 0.01, image_width_px=W,
                                image_height_px=H, principal_point_x_mm=x0,
                                principal_point_y_mm=y0))
        scale = tilt_deg / 45.0
        mounts.append(m.Mount(cam_id, suffix, omega * scale, phi * scale, kappa))
    rng = np.random.default_rng(7)
    photos = tuple(
        m.ExteriorOrientation(f"ST_{k:03d}.png", "penta",
                              E0 + float(rng.uniform(-4, 4)), N0 + float(rng.uniform(-4, 4)),
                              H0 + 12.0 + float(rng.uniform(-0.5, 0.5)),
                              float(rng.uniform(-3, 3)), float(rng.uniform(-3, 3)),
                              float(rng.uniform(-12, 12)))
        for k in range(n_stations))
    # 3 m targets: seen at 45 degrees from ~17 m by 2 mm lenses they stay ~15 px tall, so
    # the corner detector's window stays on the target
    scene = replace(base.scene, targets=replace(base.scene.targets, targets=tuple(
        replace(t, size_m=3.0) for t in base.scene.targets.targets)))
    return replace(base, name="rig test", cameras=tuple(cameras), scene=scene,
                   trajectory=m.Trajectory(exterior_orientations=photos,
                                           rigs=(m.Rig("penta", tuple(mounts)),)))


def two_camera_survey(samples=8, origin=(500000.0, 5000000.0, 250.0),
                      oblique_tilt_deg=20.0) -> m.Project:
    """:func:`small_flight_survey` flown by a two-camera rig: the 5 mm 640 × 480 nadir
    camera (``_N``) and a 6 mm 560 × 420 camera tilted ``oblique_tilt_deg`` forward with
    its principal point off centre (``_F``), 10 µm pixels both — two interior orientations,
    images of two sizes, overlapping footprints."""
    from dataclasses import replace

    base = small_flight_survey(samples=samples, origin=origin)
    nadir = replace(base.cameras[0], id="nadir")
    oblique = m.Camera(id="oblique", focal_length_mm=6.0, sensor_width_mm=5.6,
                       sensor_height_mm=4.2, image_width_px=560, image_height_px=420,
                       principal_point_x_mm=0.06, principal_point_y_mm=-0.04)
    rig = m.Rig("duo", (m.Mount("nadir", "_N"),
                        m.Mount("oblique", "_F", oblique_tilt_deg, 0.0, 0.0)))
    plan = replace(base.trajectory.flight_plan, camera=rig.name)
    return replace(base, name="two-camera SfM test survey", cameras=(nadir, oblique),
                   trajectory=m.Trajectory(flight_plan=plan, rigs=(rig,)),
                   render=replace(base.render, preset="draft", samples=samples))
