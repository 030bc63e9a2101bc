"""Templates and the bundled examples: schema-valid for two validators, semantically valid."""

from __future__ import annotations

from pathlib import Path

import cv2
import numpy as np
import pytest
import xmlschema

from designer.project import load_project, project_to_bytes, template
from designer.project.model_to_xml import write_project
from designer.project.schema import schema_path
from designer.project.templates import TEMPLATE_NAMES

EXAMPLES = Path(__file__).resolve().parents[2] / "resources" / "examples"


@pytest.fixture(scope="module")
def second_validator():
    return xmlschema.XMLSchema10(str(schema_path()))


@pytest.mark.parametrize("name", TEMPLATE_NAMES)
def test_bundled_example_is_the_template_written_out(name):
    tpl = template(name)
    assert (EXAMPLES / name / f"{name}.xml").read_bytes() == project_to_bytes(tpl.project), (
        f"regenerate: designer new resources/examples/{name}/{name}.xml --template {name} "
        "--force")
    for rel, data in tpl.files.items():
        on_disk = (EXAMPLES / name / rel).read_bytes()
        if rel.endswith(".png"):  # FFT rounding may differ by one level between platforms
            a = cv2.imdecode(np.frombuffer(on_disk, np.uint8), cv2.IMREAD_UNCHANGED)
            b = cv2.imdecode(np.frombuffer(data, np.uint8), cv2.IMREAD_UNCHANGED)
            assert a.shape == b.shape and np.abs(a.astype(int) - b).max() <= 1
        else:
            assert on_disk == data


@pytest.mark.parametrize("name", TEMPLATE_NAMES)
def test_examples_pass_the_independent_validator(name, second_validator):
    second_validator.validate(str(EXAMPLES / name / f"{name}.xml"))


@pytest.mark.parametrize("name", TEMPLATE_NAMES)
def test_examples_load_with_every_check(name):
    project = load_project(EXAMPLES / name / f"{name}.xml")
    assert project == template(name).project


def test_the_example_survey_is_what_the_issue_asks_for():
    p = template("survey").project
    e = p.scene.terrain.extent
    assert (e.width_m, e.length_m) == (100.0, 100.0)
    src = p.scene.terrain.source
    assert (src.min_height_m, src.max_height_m) == (-10.0, 10.0)
    assert (p.scene.texture.repeat_X, p.scene.texture.repeat_Y) == (5, 5)
    assert p.scene.texture.source.pattern == "grass"
    assert len(p.targets) == 10
    cam = p.cameras[0]
    assert (cam.sensor_width_mm, cam.sensor_height_mm, cam.focal_length_mm) == (13.2, 8.8, 8.8)
    assert cam.image_width_px * cam.image_height_px > 19e6
    assert p.render.resolution_scale < 1 and p.render.workers == 1  # docs/benchmarks.md
    plan = p.trajectory.flight_plan
    assert plan is not None and plan.pose_noise is not None
    assert min(vars(plan.pose_noise).values()) > 0


def test_write_project_is_atomic_and_leaves_no_temporary_files(tmp_path):
    path = tmp_path / "p.xml"
    write_project(template("psf").project, path)
    assert [p.name for p in tmp_path.iterdir()] == ["p.xml"]
    assert load_project(path) == template("psf").project


def test_the_dynamic_survey_switches_on_every_changing_element_lightly():
    base, p = template("survey").project, template("survey-dynamic").project
    assert p.trajectory.time_line is not None and p.trajectory.time_line.speed_m_s > 0
    assert type(p.scene.lighting.sun).__name__ == "SunOverTime"
    clouds = p.scene.lighting.clouds
    assert clouds is not None and 0 < clouds.cover <= 0.3 and clouds.depth <= 0.6
    assert {o.shape for o in p.scene.moving_objects} == {"car", "person"}
    assert p.scene.texture.variation is not None
    # everything else is the example survey's
    assert p.trajectory.flight_plan == base.trajectory.flight_plan
    assert (p.cameras, p.effects, p.render) == (base.cameras, base.effects, base.render)


def test_the_structures_survey_has_buildings_plants_a_rig_and_a_rolling_shutter():
    from designer.core.rig import PENTA_MOUNTS
    from designer.scene.build import build_heightfield
    from designer.survey.project_poses import project_images

    base, p = template("survey").project, template("survey-structures").project
    assert {b.roof for b in p.scene.buildings} == {"flat", "gable", "hip"}
    assert {g.kind for g in p.scene.vegetation.plants} == {"grass-tuft", "shrub", "tree"}
    assert p.scene.vegetation.wind.amplitude_deg > 0 and p.trajectory.time_line is not None
    (orbit,) = p.trajectory.patterns
    drone = p.camera(orbit.camera)
    assert drone.readout_s > 0 and drone.distortion is None  # rolling shutter, exactly
    (rig,) = p.trajectory.rigs
    assert p.trajectory.flight_plan.camera == rig.name
    assert [m.suffix for m in rig.mounts] == [s for s, *_ in PENTA_MOUNTS]
    focal = {p.camera(m.camera).focal_length_mm for m in rig.mounts}
    assert len(focal) == 2  # the obliques have their own interior orientation
    assert all(p.camera(m.camera).readout_s == 0 for m in rig.mounts)
    # five images per station of the grid, then one per orbit station
    hf = build_heightfield(p.scene.terrain, EXAMPLES / "survey", p.crs)
    images = project_images(p, hf)
    n_orbit = sum(c == drone.id for c in images.camera_ids)
    assert n_orbit == orbit.n_stations
    assert (len(images.stations) - n_orbit) % len(rig.mounts) == 0
    assert len(images.stations) - n_orbit > len(project_images(base, hf).stations)
    assert (p.scene.terrain, p.scene.targets) == (base.scene.terrain, base.scene.targets)


def test_the_survey_block_is_a_real_surveys_size_with_practitioners_gcp_density():
    """Issue 52 item 5: about 12 ha and 700 images with the example's camera, overlaps and
    texture; 2–3 control GCPs per 100 images (Sanz-Ablanedo et al. 2018) and check points,
    spread over the block."""
    from designer.scene.build import build_heightfield
    from designer.survey.project_poses import project_images

    base, p = template("survey").project, template("survey-block").project
    plan = p.trajectory.flight_plan
    xy = np.array(plan.area)
    area_ha = (np.ptp(xy[:, 0]) * np.ptp(xy[:, 1])) / 1e4
    assert 11.0 <= area_ha <= 13.0
    assert p.cameras == base.cameras and p.effects == base.effects and p.render == base.render
    for name in ("altitude_agl_m", "front_overlap_percent", "side_overlap_percent"):
        assert getattr(plan, name) == getattr(base.trajectory.flight_plan, name), name
    assert p.scene.texture.source == base.scene.texture.source
    assert p.scene.texture.variation == base.scene.texture.variation
    hf = build_heightfield(p.scene.terrain, EXAMPLES / "survey-block", p.crs)
    n_images = len(project_images(p, hf).stations)
    assert 650 <= n_images <= 750, n_images
    control = [t for t in p.targets if t.role == "control"]
    check = [t for t in p.targets if t.role == "check"]
    assert 2.0 <= 100 * len(control) / n_images <= 3.0, (len(control), n_images)
    assert len(check) >= 5
    # spread over the block: every quarter of the area holds control and check points
    E0, N0 = p.origin.E0, p.origin.N0
    for points in (control, check):
        quarters = {(t.true.X > E0, t.true.Y > N0) for t in points
                    if abs(t.true.X - E0) > 1 and abs(t.true.Y - N0) > 1}
        assert len(quarters) == 4
        inside = [(xy[:, 0].min() < t.true.X < xy[:, 0].max()
                   and xy[:, 1].min() < t.true.Y < xy[:, 1].max()) for t in points]
        assert all(inside)
