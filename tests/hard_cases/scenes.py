"""The projects of the hard-case tests (docs/hard-cases.md): tests/synthetic.py's small
survey made tiny (320 × 240 px, ≤ 16 samples) and pushed into one hard case each."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np

from designer.project import model as m
from tests.synthetic import small_survey

#: the south-hemisphere UTM edge: northing just under the false northing, easting near
#: the zone's edge at the equator
UTM_EDGE = dict(origin=(830000.0, 9999000.0, 250.0), crs="EPSG:32732")
#: 78.4° N (Svalbard), 330 km east of the central meridian
HIGH_LATITUDE = dict(origin=(830000.0, 8700000.0, 20.0), crs="EPSG:32633")


def tiny_survey(origin=(500000.0, 5000000.0, 250.0), crs="EPSG:32632", n_photos=6,
                focal_length_mm=3.0, pixel_pitch_mm=0.01, distortion=None, samples=8,
                ) -> m.Project:
    """small_survey at 320 × 240 px: 9 checker targets 1.5 m wide, 10 m apart, photos
    from 30 m (GSD 10 cm with the 3 mm lens)."""
    project = small_survey(origin=origin, n_photos=n_photos, samples=samples,
                           distortion=distortion, size_px=(320, 240),
                           focal_length_mm=focal_length_mm, pixel_pitch_mm=pixel_pitch_mm)
    return replace(project, crs=crs)


def with_photos(project: m.Project, photos) -> m.Project:
    """``project`` flown at the exterior orientations ``photos``: (name, dE, dN, dH, omega,
    phi, kappa) relative to the origin, angles in degrees."""
    E0, N0, H0 = (project.origin.E0, project.origin.N0, project.origin.H0)
    cam = project.cameras[0].id
    eos = tuple(m.ExteriorOrientation(name, cam, E0 + dE, N0 + dN, H0 + dH, o, p, k)
                for name, dE, dN, dH, o, p, k in photos)
    return replace(project, trajectory=m.Trajectory(exterior_orientations=eos))


def with_targets(project: m.Project, spots, size_m=1.5, control=None) -> m.Project:
    """``project`` with checker targets at ``spots`` (dE, dN) m from the origin, surveyed
    exactly; ``control``: the indices of the control targets (default: all)."""
    E0, N0 = project.origin.E0, project.origin.N0
    targets = tuple(
        m.Target(f"G{k}", "control" if control is None or k in control else "check",
                 "checker", size_m, m.TruePosition(E0 + x, N0 + y))
        for k, (x, y) in enumerate(spots))
    scene = replace(project.scene, targets=m.Targets(
        targets, m.SurveyAccuracy(m.Sigma3(0.0, 0.0, 0.0), seed=1)))
    return replace(project, scene=scene)


def horizontal_cameras() -> m.Project:
    """Cameras looking horizontally (φ = ±90°, the Euler singularity) 6 m above the
    ground, 12 m east and west of the nearest column of 3 m targets, the image top up.
    At φ = ±90° only ω ± κ is defined: the east photos give the roll as κ, the west ones
    as ω."""
    base = tiny_survey(focal_length_mm=1.6, n_photos=0)
    base = with_targets(base, [(10.0 * i, 10.0 * j) for i in (-1, 0, 1) for j in (-1, 0, 1)],
                        size_m=3.0)
    photos = []
    for k, dN in enumerate((-6.0, 0.0, 6.0)):
        # looking west (−X) from the east, and east (+X) from the west
        photos.append((f"EAST_{k}.png", 22.0, dN, 6.0, 0.0, 90.0, 90.0))
        photos.append((f"WEST_{k}.png", -22.0, dN, 6.0, -90.0, -90.0, 0.0))
    return with_photos(base, photos)


def kappa_wrap() -> m.Project:
    """Nearly nadir cameras (φ, ω within 0.01°) whose κ sits at ±180° and wraps."""
    base = tiny_survey(n_photos=0)
    photos = [(f"K_{k}.png", dE, dN, 30.0, o, p, kap) for k, (dE, dN, o, p, kap) in enumerate([
        (-3.0, 0.0, 0.0, 0.0, 180.0), (3.0, 0.0, 0.004, -0.007, -180.0),
        (0.0, -3.0, -0.01, 0.01, 179.9999), (0.0, 3.0, 0.0, 1e-6, -179.9999)])]
    return with_photos(base, photos)


def strong_brown() -> m.Project:
    """Barrel distortion whose inverse stops being monotonic just outside the image: the
    corner (1.0 normalised) is at 90 % of the radius the monotone map reaches (1.11);
    undistortion there magnifies radial errors 2.2×."""
    return tiny_survey(focal_length_mm=2.0, distortion=m.BrownConradyDistortion(k1=-0.12),
                       n_photos=4)


def fisheye_edge() -> m.Project:
    """An equidistant fisheye whose image corners see 74.5° off axis (a 149° field, at
    the edge of the 150° designer renders)."""
    return tiny_survey(focal_length_mm=1.52, n_photos=4,
                       distortion=m.FisheyeEquidistantDistortion(k1=0.01))


def gsd_family(gsd_m: float) -> m.Project:
    """One project family at two extremes of GSD over flat ground (H0): the 3 mm lens
    with 10 µm pixels 0.3 m above it (1 mm GSD, 5 cm checkers), or with 50 µm pixels
    at 30 m over a 240 m terrain (50 cm GSD, 8 m checkers). The texel follows the GSD
    (GSD/2, as docs/world.md advises)."""
    fine = gsd_m < 0.01
    base = tiny_survey(n_photos=0, pixel_pitch_mm=0.01 if fine else 0.05)
    E0, N0, H0 = base.origin.E0, base.origin.N0, base.origin.H0
    half = 20.0 if fine else 120.0
    terrain = m.Terrain(m.Extent(E0 - half, N0 - half, E0 + half, N0 + half),
                        m.FlatTerrain(H0))
    # 0.5 mm texels fit 8192-texel tiles on 1.25 m tiles (32 repeats; small: fast to bake)
    texture = replace(base.scene.texture, source=replace(
        base.scene.texture.source, texel_size_m=0.0005 if fine else 0.25),
        repeat_X=32 if fine else 1, repeat_Y=32 if fine else 1)
    project = replace(base, scene=replace(base.scene, terrain=terrain, texture=texture))
    if fine:
        project = with_targets(project, [(0.0, 0.0), (0.08, 0.05), (-0.08, -0.05)],
                               size_m=0.05)
        height, shifts = 0.3, [(0.0, 0.0, 0.0), (0.02, 0.01, 30.0), (-0.01, 0.02, -50.0)]
    else:
        project = with_targets(project, [(x, y) for x in (-40.0, 0.0, 40.0)
                                         for y in (-30.0, 0.0, 30.0)], size_m=8.0)
        height, shifts = 30.0, [(0.0, 0.0, 0.0), (5.0, -3.0, 40.0), (-4.0, 4.0, -120.0)]
    prefix = "MM" if fine else "CM"
    return with_photos(project, [(f"{prefix}_{k}.png", dE, dN, height, 0.0, 0.0, kap)
                                 for k, (dE, dN, kap) in enumerate(shifts)])


def collinear_control(width_m: float) -> m.Project:
    """tiny_survey with its five control targets on the line N = N0, all but the middle
    one shifted ``width_m`` north or south alternately; four check targets off it."""
    base = tiny_survey(n_photos=6)
    spots = [(-10.0, width_m), (-5.0, -width_m), (0.0, 0.0), (5.0, width_m),
             (10.0, -width_m), (-10.0, 10.0), (10.0, 10.0), (-10.0, -10.0), (10.0, -10.0)]
    return with_targets(base, spots, control={0, 1, 2, 3, 4})


def flat_tiny() -> m.Project:
    """The study template "tiny" (18 images of 160 × 120 px from 12 m over a 14 m block,
    GSD 10 cm, 10 GCP targets G00…G09) over flat ground."""
    from designer.study.templates import template_base

    project = template_base("tiny")
    E0, N0, H0 = project.origin.E0, project.origin.N0, project.origin.H0
    terrain = m.Terrain(m.Extent(E0 - 30, N0 - 30, E0 + 30, N0 + 30), m.FlatTerrain(H0))
    return replace(project, scene=replace(project.scene, terrain=terrain))


def surveyed_at_true(project: m.Project) -> m.Project:
    """``project`` with each target surveyed exactly (σ 0) at its true X, Y and the
    origin's height: the control's surveyed coordinates do not depend on the terrain."""
    H0 = project.origin.H0
    targets = tuple(replace(t, surveyed=m.SurveyedPosition(
        m.Point3(t.true.X, t.true.Y, H0), m.Sigma3(0.0, 0.0, 0.0))) for t in project.targets)
    return replace(project, scene=replace(project.scene, targets=replace(
        project.scene.targets, targets=targets)))


def on_a_terrain_mesh(project: m.Project, folder: Path) -> Path:
    """``project`` on a flat terrain mesh (``folder/ground.ply``, at the origin's height
    over the terrain's extent), its targets placed at that height (a mesh drapes none):
    written to ``folder/project.xml``, whose path is returned."""
    from designer.core.heightfield import Heightfield
    from designer.scene.mesh import heightfield_to_mesh, write_mesh_ply
    from tests.synthetic import write_project_file

    E0, N0, H0 = project.origin.E0, project.origin.N0, project.origin.H0
    e = project.scene.terrain.extent
    targets = tuple(replace(t, true=replace(t.true, Z=H0)) for t in project.targets)
    scene = replace(project.scene, targets=replace(project.scene.targets, targets=targets),
                    terrain=replace(project.scene.terrain, source=m.MeshTerrain("ground.ply")))
    path = write_project_file(replace(project, scene=scene), folder)
    write_mesh_ply(heightfield_to_mesh(Heightfield(
        e.min_X - E0, e.min_Y - N0, e.max_X - e.min_X, e.max_Y - e.min_Y, np.zeros((2, 2)))),
        folder / "ground.ply")
    return path
