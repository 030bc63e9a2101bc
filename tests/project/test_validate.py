"""Semantic checks on models built in code (no file, so no positions)."""

from __future__ import annotations

import dataclasses

import pytest

from designer.project import ProjectError, template, validate_project
from designer.project import model as m
from designer.project.geometry import (
    polygon_area,
    polygon_is_degenerate,
    polygon_self_intersection,
)
from designer.project.validate import semantic_problems


def survey() -> m.Project:
    return template("survey").project


def with_camera(project: m.Project, **changes) -> m.Project:
    return dataclasses.replace(project, cameras=(dataclasses.replace(project.cameras[0],
                                                                     **changes),))


def messages(project: m.Project) -> list[str]:
    return [p.message for p in semantic_problems(project)]


def test_templates_are_valid():
    for name in ("survey", "validation-cube", "psf", "texture"):
        assert semantic_problems(template(name).project) == []


@pytest.mark.parametrize("changes, expected", [
    ({"focal_length_mm": -8.8}, "<focal-length-mm>: focal-length-mm = -8.8 must be greater than 0"),
    ({"focal_length_mm": float("nan")}, "<focal-length-mm>: focal-length-mm = nan must be greater "
                                        "than 0 and at most 1000 mm"),
    ({"sensor_height_mm": 9.0}, "<sensor>: pixels are not square"),
    ({"sensor_height_mm": 9.0, "pixel_aspect": 1.0}, "<pixel-aspect>: pixel aspect 1.0 disagrees"),
    ({"image_width_px": 0}, "<image>: width-px = 0 must be from 1 to 100000 px"),
    ({"principal_point_x_mm": 7.0}, "<principal-point>: the principal point (7.0, 0.0) mm lies"),
    ({"distortion": m.BrownConradyDistortion(k1=-0.9)}, "<brown-conrady>: BrownConrady"),
])
def test_camera_problems(changes, expected):
    found = messages(with_camera(survey(), **changes))
    assert any(msg.startswith(expected) for msg in found), found


def test_all_problems_are_listed_not_only_the_first():
    p = survey()
    plan = dataclasses.replace(p.trajectory.flight_plan, front_overlap_percent=99.0,
                               side_overlap_percent=-1.0, camera="nope")
    p = dataclasses.replace(with_camera(p, focal_length_mm=0.0),
                            trajectory=m.Trajectory(flight_plan=plan))
    found = messages(p)
    assert len(found) == 4, found
    with pytest.raises(ProjectError) as error:
        validate_project(p, source="model")
    assert str(error.value).count("model:0:0: <") == 4


def test_nan_and_huge_values_are_refused():
    p = survey()
    bad = dataclasses.replace(p, origin=m.Origin(float("inf"), 1e308, 0.0))
    found = messages(bad)
    assert any("E0 = inf is not a finite number" in f for f in found)
    assert any("N0 = 1e+308 is not a finite number" in f for f in found)


def test_gcp_outside_terrain_and_duplicates():
    p = survey()
    targets = list(p.targets)
    targets[1] = dataclasses.replace(targets[1], id=targets[0].id)
    targets[2] = dataclasses.replace(targets[2], true=m.TruePosition(0.0, 0.0))
    scene = dataclasses.replace(p.scene, targets=m.Targets(tuple(targets),
                                                           p.scene.targets.survey_accuracy))
    found = messages(dataclasses.replace(p, scene=scene))
    assert any("GCP id 'GCP01' is used by 2 targets" in f for f in found)
    assert any("GCP 'GCP03' at X 0, Y 0 lies outside the terrain extent" in f
               for f in found)


def test_duplicate_and_unknown_photo_references():
    p = template("psf").project
    photos = list(p.trajectory.exterior_orientations)
    photos[1] = dataclasses.replace(photos[1], name=photos[0].name)
    photos[2] = dataclasses.replace(photos[2], camera="other")
    found = messages(dataclasses.replace(p, trajectory=m.Trajectory(tuple(photos))))
    assert any("image name 'PSF_01.png' is used by 2 photos" in f for f in found)
    assert any("camera 'other' is not defined; use the id of a camera (p4p)" in f
               for f in found)


def test_no_photos_at_all():
    p = dataclasses.replace(survey(), trajectory=m.Trajectory())
    assert any("no photos" in f for f in messages(p))


def test_effects_and_render_ranges():
    p = dataclasses.replace(
        survey(), effects=m.Effects(jpeg=m.Jpeg(0), sensor_noise=m.SensorNoise(-1.0)),
        render=dataclasses.replace(survey().render, samples=0, output_format="exr", bit_depth=8))
    found = messages(p)
    assert any("<jpeg>: quality = 0 must be from 1 to 100" in f for f in found)
    assert any("<sensor-noise>: sigma-dn = -1.0 must be from 0 to 100" in f for f in found)
    assert any("<samples>: samples = 0 must be from 1 to 65536" in f for f in found)
    assert any("exr images cannot have 8 bits per channel" in f for f in found)


def test_vignetting_gain_must_stay_between_0_and_1():
    ok = m.Effects(vignetting=m.Vignetting(0.4, 0.1, -0.05, natural_cos4=True),
                   defocus=m.Defocus(2.8, 50.0))
    assert messages(dataclasses.replace(survey(), effects=ok)) == []
    brighter = m.Effects(vignetting=m.Vignetting(0.0, 0.5))
    darker = m.Effects(vignetting=m.Vignetting(0.9, 0.0, -0.5))
    for fx, value in ((brighter, "1.5 at ρ = 1"), (darker, "-0.4 at ρ = 1")):
        found = messages(dataclasses.replace(survey(), effects=fx))
        assert any(value in f and "between 0 and 1" in f for f in found), found
    bad = m.Effects(defocus=m.Defocus(0.1, 50.0, 0.0))
    found = messages(dataclasses.replace(survey(), effects=bad))
    assert any("f-number = 0.1 must be from 0.5 to 64" in f for f in found)
    assert any("object-distance-m = 0.0 must be from 0.1" in f for f in found)


def test_polygon_geometry():
    square = [(0.0, 0.0), (10.0, 0.0), (10.0, 10.0), (0.0, 10.0)]
    assert polygon_area(square) == 100.0
    assert polygon_self_intersection(square) is None
    bowtie = [(0.0, 0.0), (10.0, 0.0), (0.0, 10.0), (10.0, 8.0)]
    assert polygon_self_intersection(bowtie) == (1, 3)
    assert polygon_is_degenerate([(0.0, 0.0), (1.0, 1.0), (5.0, 5.0)])
    utm = [(x + 512000.0, y + 5406000.0) for x, y in square]
    assert polygon_area(utm) == 100.0


@pytest.mark.parametrize("changes, expected", [
    ({"strength": 1.5}, "<variation>: strength = 1.5 must be from 0 to 1"),
    ({"strength": -0.1}, "<variation>: strength = -0.1 must be from 0 to 1"),
    ({"scale_m": 0.0}, "<variation>: scale-m = 0.0 must be greater than 0 and at most 1e+06 m"),
    ({"octaves": 0}, "<variation>: octaves = 0 must be from 1 to 8"),
])
def test_texture_variation_ranges(changes, expected):
    p = survey()
    tex = p.scene.texture
    assert tex.variation is not None and messages(p) == []
    bad = dataclasses.replace(tex, variation=dataclasses.replace(tex.variation, **changes))
    p = dataclasses.replace(p, scene=dataclasses.replace(p.scene, texture=bad))
    assert any(msg.startswith(expected) for msg in messages(p)), messages(p)


def test_building_and_area_vertices_outside_the_terrain_read_in_plain_numbers():
    p = survey()  # extent X 511950..512050, Y 5405950..5406050
    square = tuple(m.PathPoint(X, Y) for X, Y in ((512000.0, 5406000.0), (512060.5, 5406000.0),
                                                  (512060.5, 5406010.0),
                                                  (512000.0, 5406010.0)))
    mesh = m.Building("shed", file="shed.obj", position=m.PathPoint(511940.25, 5406000.0))
    scene = dataclasses.replace(p.scene, buildings=(m.Building("hall", footprint=square),
                                                    mesh))
    area = ((511965.0, 5405965.0), (512070.0, 5405965.0), (512035.0, 5406035.0),
            (511965.0, 5406035.0))
    trajectory = dataclasses.replace(p.trajectory, flight_plan=dataclasses.replace(
        p.trajectory.flight_plan, area=area))
    found = messages(dataclasses.replace(p, scene=scene, trajectory=trajectory))
    extent = "(X 511950..512050, Y 5405950..5406050)"
    assert any(f"vertex 2 (X 512060.5, Y 5406000) lies outside the terrain extent {extent}"
               in f for f in found), found
    assert any(f"building 'shed' at X 511940.25, Y 5406000 lies outside the terrain extent "
               f"{extent}" in f for f in found), found
    assert any(f"vertex 2 (X 512070, Y 5405965) lies outside the terrain extent {extent}"
               in f for f in found), found
    assert not any(".000" in f or "e+06" in f for f in found), found
