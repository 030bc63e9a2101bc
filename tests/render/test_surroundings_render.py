"""Rendered images see ground in every pixel below the horizon: the example's frames
that looked past its terrain, and an oblique that sees the horizon and the sky."""

from __future__ import annotations

import dataclasses
import json

import cv2
import numpy as np
import pytest

from designer.project import model as m
from designer.project.templates import template
from designer.render.job_spec import SKY_RGB
from designer.render.pipeline import render_project
from tests.synthetic import small_survey, write_project_file

pytestmark = [pytest.mark.blender, pytest.mark.slow]

#: the example's frames that saw most past its terrain before it had surroundings
#: (DJI_00060 78 % void): frame indices of DJI_00001, 00013, 00048, 00060
WORST_FRAMES = "0,12,47,59"


def _near_black(img: np.ndarray) -> float:
    return float((img.max(axis=2) <= 10).mean())


def test_the_examples_worst_frames_see_ground_to_their_corners(tmp_path):
    project = template("survey").project
    # small images: the geometry, not the detail, is under test; so is the texture's: the
    # example's variation, baked over the terrain and its surroundings (a 0.5 GB image,
    # three quarters of this test's time), is left out; that the bake reaches into the
    # surroundings with ground in every pixel: tests/render/test_texture_variation.py::
    # test_a_detail_and_a_coarse_bake_render_what_one_bake_renders
    texture = dataclasses.replace(project.scene.texture, variation=None)
    project = dataclasses.replace(
        project, effects=None,
        scene=dataclasses.replace(project.scene, texture=texture),
        render=dataclasses.replace(project.render, resolution_scale=0.0625, samples=4))
    path = write_project_file(project, tmp_path)
    summary = render_project(path, tmp_path / "out", frames=WORST_FRAMES, workers=1)
    manifest = json.loads((tmp_path / "out" / "manifest.json").read_text())
    for name in ("DJI_00001.png", "DJI_00013.png", "DJI_00048.png", "DJI_00060.png"):
        img = cv2.imread(str(summary.images_dir / name))
        assert _near_black(img) <= 0.001, name
        assert manifest["images"][name]["void_share"] <= 0.001, name
    assert manifest["background"] == "black"


def test_an_oblique_towards_the_horizon_sees_ground_below_it_and_sky_above(tmp_path):
    p = small_survey(n_photos=1, samples=4, size_px=(320, 240))
    # 82° from the nadir about X: the picture's top 5° are above the horizon
    photo = m.ExteriorOrientation("IMG_000.png", "cam", 0.0, 0.0, 30.0, 82.0, 0.0, 0.0)
    p = dataclasses.replace(p, effects=None,
                            trajectory=m.Trajectory(exterior_orientations=(photo,)))
    path = write_project_file(p, tmp_path)
    summary = render_project(path, tmp_path / "out", workers=1)
    assert summary.prepared.job.background_rgb == SKY_RGB
    img = cv2.imread(str(summary.images_dir / "IMG_000.png")).astype(float)
    assert _near_black(img.astype(np.uint8)) == 0.0
    b, g, r = img[..., 0], img[..., 1], img[..., 2]
    sky = (b > r + 20) & (b > g)  # blue above the horizon; the grass is green
    rows = sky.mean(axis=1)
    assert rows[:10].min() > 0.99 and rows[-60:].max() == 0.0  # sky on top, ground below
    horizon = int(np.argmax(rows < 0.5))
    assert 5 < horizon < 120  # the horizon crosses the upper half
    manifest = json.loads((tmp_path / "out" / "manifest.json").read_text())
    assert manifest["background"] == "sky"
    # the manifest's void is the sky's share, what the picture shows above the horizon
    share = manifest["images"]["IMG_000.png"]["void_share"]
    assert abs(share - sky.mean()) < 0.02
