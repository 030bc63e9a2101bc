"""The render-time model: its formula, the fit to measured frames, the stored
coefficients and the terrain share of an image."""

from __future__ import annotations

import json
from dataclasses import replace

import numpy as np
import pytest

from designer.core.heightfield import Heightfield
from designer.core.interior import InteriorOrientation
from designer.render_time import model as rc

TRUE = rc.RenderSpeed(terrain_cpu_s_per_mp_sample=0.4, background_cpu_s_per_mp_sample=0.1,
                      post_s_per_mp=0.2, fixed_s=5.0, source="render")


def test_the_estimate_is_the_model():
    images = [rc.ImageCost(1.5, 16, 1.0), rc.ImageCost(1.5, 16, 0.0),
              rc.ImageCost(1.5, 16, 0.5)]
    cpu = 1.5 * 16 * (0.4 + 0.1 + 0.25)
    post = 3 * 1.5 * 0.2
    assert rc.estimate_render_s(images, workers=2, cores=2, speed=TRUE) == pytest.approx(
        5.0 + cpu / 2 + post / 2)
    # one worker on two cores: Cycles still uses both, the effects run one at a time
    assert rc.estimate_render_s(images, workers=1, cores=2, speed=TRUE) == pytest.approx(
        5.0 + cpu / 2 + post)


def test_the_fit_recovers_terrain_and_background_costs():
    rng = np.random.default_rng(0)
    f = rng.uniform(0.1, 1.0, 12)
    images = [rc.ImageCost(1.2, 16, float(x)) for x in f]
    cpu = [rc.frame_cpu_s(TRUE, i) * (1 + rng.normal(0, 0.01)) for i in images]
    post = [0.24] * len(images)
    fit = rc.fit_speed(images, cpu, post, 5.0, "render", prior=rc.REFERENCE)
    assert fit.terrain_cpu_s_per_mp_sample == pytest.approx(0.4, rel=0.03)
    assert fit.background_cpu_s_per_mp_sample == pytest.approx(0.1, rel=0.15)
    assert fit.post_s_per_mp == pytest.approx(0.2)
    assert fit.images == 12 and fit.calibrated
    # all frames alike (no spread of terrain share): the prior's ratio, one factor
    same = [rc.ImageCost(1.2, 16, 1.0)] * 3
    fit = rc.fit_speed(same, [rc.frame_cpu_s(TRUE, i) for i in same], [0.24] * 3, 5.0,
                       "render", prior=rc.REFERENCE)
    ratio = (rc.REFERENCE.background_cpu_s_per_mp_sample
             / rc.REFERENCE.terrain_cpu_s_per_mp_sample)
    assert fit.background_cpu_s_per_mp_sample / fit.terrain_cpu_s_per_mp_sample == \
        pytest.approx(ratio)
    assert rc.frame_cpu_s(fit, same[0]) == pytest.approx(rc.frame_cpu_s(TRUE, same[0]))


def test_stored_coefficients_round_trip_and_a_bad_file_is_uncalibrated(tmp_path,
                                                                        monkeypatch):
    monkeypatch.setenv("DESIGNER_CACHE_DIR", str(tmp_path))
    assert rc.load_speed() == rc.REFERENCE and not rc.load_speed().calibrated
    assert "uncalibrated" in rc.load_speed().describe()
    rc.save_speed(TRUE)
    assert rc.load_speed() == TRUE
    assert "this machine" in rc.load_speed().describe()
    (tmp_path / rc.SPEED_FILE).write_text(json.dumps({"terrain_cpu_s_per_mp_sample": -1}))
    assert rc.load_speed() == rc.REFERENCE
    (tmp_path / rc.SPEED_FILE).write_text("{not json")
    assert rc.load_speed() == rc.REFERENCE


def test_a_small_render_refines_a_large_one_in_proportion():
    stored = replace(TRUE, images=60)
    small = replace(TRUE, terrain_cpu_s_per_mp_sample=0.8, images=2)
    mixed = rc.refine(stored, small)
    k = rc.FULL_WEIGHT_IMAGES
    assert mixed.terrain_cpu_s_per_mp_sample == pytest.approx((k * 0.4 + 2 * 0.8) / (k + 2))
    large = replace(small, images=rc.FULL_WEIGHT_IMAGES)
    assert rc.refine(stored, large) == large
    assert rc.refine(rc.REFERENCE, small) == small  # nothing measured before


def test_terrain_fraction_of_an_image_half_over_the_edge():
    hf = Heightfield(0.0, 0.0, 1.0, 1.0, np.zeros((101, 101)))  # 100 × 100 m, flat
    interior = InteriorOrientation(focal_length_mm=10.0, sensor_width_mm=10.0,
                                   sensor_height_mm=10.0, image_width_px=100,
                                   image_height_px=100)
    R = np.eye(3)  # nadir: the camera frame is x east, y north, z up (looking down -z)
    C = np.array([[50.0, 50.0, 40.0], [100.0, 50.0, 40.0], [300.0, 50.0, 40.0]])
    f = rc.terrain_fractions(hf, C, np.array([R] * 3), interior, grid=(20, 20))
    assert f[0] == pytest.approx(1.0)
    assert f[1] == pytest.approx(0.5, abs=0.06)
    assert f[2] == 0.0
    assert np.all(rc.terrain_fractions(None, C, np.array([R] * 3), interior) == 1.0)


def test_image_costs_measure_each_image_with_its_own_interior():
    hf = Heightfield(0.0, 0.0, 1.0, 1.0, np.zeros((101, 101)))  # 100 × 100 m, flat
    big = InteriorOrientation(focal_length_mm=10.0, sensor_width_mm=10.0,
                              sensor_height_mm=10.0, image_width_px=100, image_height_px=100)
    small = InteriorOrientation(focal_length_mm=10.0, sensor_width_mm=10.0,
                                sensor_height_mm=8.0, image_width_px=50, image_height_px=40)
    R = np.array([np.eye(3)] * 3)
    C = np.array([[50.0, 50.0, 40.0], [100.0, 50.0, 40.0], [300.0, 50.0, 40.0]])
    costs = rc.image_costs(hf, C, R, [big, small, big], 16)
    assert [c.megapixels for c in costs] == [0.01, 0.002, 0.01]
    assert all(c.samples == 16 for c in costs)
    fractions = [c.terrain_fraction for c in costs]
    assert fractions[0] == pytest.approx(1.0)
    assert fractions[1] == pytest.approx(0.5, abs=0.06)
    assert fractions[2] == 0.0


def test_durations_never_read_zero():
    assert rc.format_duration(0.2) == "1 s"
    assert rc.format_duration(45) == "45 s"
    assert rc.format_duration(300) == "5.0 min"
    assert rc.format_duration(3 * 3600) == "3.0 h"


def test_an_estimate_uses_its_own_kind_and_one_slow_render_moves_no_median(tmp_path,
                                                                          monkeypatch):
    monkeypatch.setenv("DESIGNER_CACHE_DIR", str(tmp_path))
    survey = rc.ImageCost(1.25, 16, 0.8, scene="terrain", effects="jpeg")
    tiny = rc.ImageCost(0.003, 1, 1.0, scene="terrain", effects="none")
    town = rc.ImageCost(1.25, 16, 0.8, scene="terrain+buildings", effects="jpeg")
    for _ in range(3):
        rc.save_speed(replace(TRUE, images=8), survey)
    rc.save_speed(replace(TRUE, terrain_cpu_s_per_mp_sample=1.6, fixed_s=40.0, images=8),
                  survey)  # one render on a busy machine
    before = rc.estimate_render_s([survey] * 10, workers=1, cores=2)
    assert rc.load_speed(survey).terrain_cpu_s_per_mp_sample == pytest.approx(0.4)
    # other kinds render in between: the survey's estimate does not move
    rc.save_speed(replace(TRUE, terrain_cpu_s_per_mp_sample=9.0, background_cpu_s_per_mp_sample=
                          9.0, post_s_per_mp=5.0, fixed_s=1.0, images=8), tiny)
    rc.save_speed(replace(TRUE, terrain_cpu_s_per_mp_sample=0.9, fixed_s=30.0, images=8), town)
    assert rc.estimate_render_s([survey] * 10, workers=1, cores=2) == before
    # a kind never rendered borrows from its scene kind, then from every record
    assert rc.load_speed(town).terrain_cpu_s_per_mp_sample == pytest.approx(0.9)
    other = rc.ImageCost(5.0, 64, 0.5, scene="terrain+plants", effects="blur")
    assert rc.load_speed(other).calibrated


def test_the_description_counts_its_images_in_words():
    one = replace(TRUE, source="render", images=1, measured="2026-11-29 19:35")
    assert one.describe() == "this machine, render of 1 image on 2026-11-29 19:35"
    many = replace(one, source="probe", images=30)
    assert many.describe() == "this machine, probe render of 30 images on 2026-11-29 19:35"


def test_the_texture_path_is_the_renderers_choice():
    limit = 12288
    assert rc.texture_path(False, (50000, 50000), (50000, 50000), True, True) == "baked"
    assert rc.texture_path(True, (limit, limit), (limit, limit), False, True) == "baked"
    # surroundings too wide, the declared terrain not: a detail and a coarse bake
    assert rc.texture_path(True, (limit + 1, 100), (limit, 100), True, True) == "baked"
    assert rc.texture_path(True, (20000, 20000), (20000, 20000), True, True) == "tiled"
    assert rc.texture_path(True, (20000, 20000), (20000, 20000), False, False) == "node-graph"


def test_the_examples_texture_grown_to_500_m_is_tiled():
    from designer.project.templates import template

    project = template("survey").project
    assert rc.project_texture_path(project, (-110.0, 110.0, -110.0, 110.0)) == "baked"
    # 2.5 cm texels: 700 m are 28 000 px, the declared 100 m 4000
    assert rc.project_texture_path(project, (-350.0, 350.0, -350.0, 350.0)) == "baked"
    terrain = replace(project.scene.terrain, extent=replace(
        project.scene.terrain.extent, max_X=project.scene.terrain.extent.min_X + 500.0,
        max_Y=project.scene.terrain.extent.min_Y + 500.0))
    texture = replace(project.scene.texture, repeat_X=25, repeat_Y=25)
    wide = replace(project, scene=replace(project.scene, terrain=terrain, texture=texture))
    assert rc.project_texture_path(wide, (-270.0, 270.0, -270.0, 270.0)) == "tiled"


def test_a_texture_path_never_rendered_is_estimated_from_the_others_by_its_prior(
        tmp_path, monkeypatch):
    monkeypatch.setenv("DESIGNER_CACHE_DIR", str(tmp_path))
    baked = rc.ImageCost(1.25, 16, 1.0, texture="baked")
    nodes = replace(baked, texture="node-graph")
    tiled = replace(baked, texture="tiled")
    rc.save_speed(replace(TRUE, images=8), baked)
    prior = rc.TEXTURE_PATH_CYCLES["node-graph"]
    assert rc.load_speed(nodes).terrain_cpu_s_per_mp_sample == pytest.approx(0.4 * prior)
    assert rc.load_speed(nodes).background_cpu_s_per_mp_sample == pytest.approx(0.1)
    extra = rc.TEXTURE_PATH_POST_S["tiled"] / 1.25
    assert rc.load_speed(tiled).post_s_per_mp == pytest.approx(0.2 + extra)
    # once rendered, a path's own records
    rc.save_speed(replace(TRUE, terrain_cpu_s_per_mp_sample=1.5, images=8), nodes)
    assert rc.load_speed(nodes).terrain_cpu_s_per_mp_sample == pytest.approx(1.5)
    assert rc.load_speed(baked).terrain_cpu_s_per_mp_sample == pytest.approx(0.4)
    # a record from before the path was filed counts as baked
    path = tmp_path / rc.SPEED_FILE
    data = json.loads(path.read_text())
    for r in data["records"]:
        r.pop("texture")
    path.write_text(json.dumps(data))
    assert rc.load_speed(baked).terrain_cpu_s_per_mp_sample == pytest.approx(0.95)


def test_the_fixed_part_grows_with_the_texture_bake(tmp_path, monkeypatch):
    """A render's preparation is mostly its ground texture bake: the reference fixed part
    and a record's are counted for the bake of the render estimated."""
    monkeypatch.setenv("DESIGNER_CACHE_DIR", str(tmp_path))
    small = rc.ImageCost(0.02, 4, 1.0, bake_mp=1.44)
    large = replace(small, bake_mp=77.4)
    unknown = replace(small, bake_mp=None)
    per_mp = rc.REFERENCE.bake_s_per_mp
    fixed_small = rc.estimate_render([small], 1).setup_s
    assert fixed_small == pytest.approx(rc.REFERENCE.fixed_s + 1.44 * per_mp)
    assert rc.estimate_render([large], 1).setup_s == pytest.approx(fixed_small + 75.96 * per_mp)
    # a record measured with one bake, used for another
    rc.save_speed(replace(TRUE, fixed_bake_mp=1.44, images=8), small)
    assert rc.estimate_render([small], 1).setup_s == pytest.approx(5.0)
    assert rc.estimate_render([large], 1).setup_s == pytest.approx(5.0 + 75.96 * per_mp)
    # never below Blender's start; as measured where a bake is unknown
    assert rc.fixed_for(replace(TRUE, fixed_bake_mp=77.4), 0.0) == rc.MIN_FIXED_S
    assert rc.estimate_render([unknown], 1).setup_s == pytest.approx(5.0)


def test_the_bake_of_a_project_is_what_prepare_job_bakes(tmp_path):
    """project_bake_mp against the size of the bake the render job prepares."""
    from designer.project.load import load_project
    from designer.project.new import write_template
    from designer.render.job import project_surroundings
    from designer.render.texture_bake import bake_size_px
    from designer.scene.build import build_scene

    path = write_template(tmp_path / "p.xml", "survey")[0]
    project = load_project(path)
    growth, _ = project_surroundings(project, tmp_path)
    scene = build_scene(project, tmp_path, growth)
    W, H = bake_size_px(scene.texture_rgb.shape, scene.texture_tiles)
    assert rc.project_bake_mp(project, scene.heightfield.extent_m) == pytest.approx(W * H / 1e6)
