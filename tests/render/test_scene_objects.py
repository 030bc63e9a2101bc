"""Scene objects in real renders: the validation cube appears where the camera looks."""

from __future__ import annotations

import dataclasses

import cv2
import numpy as np
import pytest

from designer.project import template, write_project
from designer.render.pipeline import render_project

pytestmark = [pytest.mark.blender, pytest.mark.slow]


def render_first_photo(folder, project, files):
    folder.mkdir()
    path = folder / "project.xml"
    write_project(project, path)
    for name, data in files.items():
        (folder / name).write_bytes(data)
    summary = render_project(path, folder / "out", workers=1, frames="0", quality="draft")
    (image,) = sorted(summary.images_dir.iterdir())
    return cv2.imread(str(image)).astype(np.float64)


def test_the_cube_is_rendered_at_the_image_centre(tmp_path):
    tpl = template("validation-cube")
    small = dataclasses.replace(tpl.project, render=dataclasses.replace(
        tpl.project.render, resolution_scale=0.125))
    without = dataclasses.replace(small, scene=dataclasses.replace(small.scene, objects=()))
    with_cube = render_first_photo(tmp_path / "cube", small, tpl.files)
    plane_only = render_first_photo(tmp_path / "plane", without, tpl.files)
    h, w = with_cube.shape[:2]
    centre = (slice(h // 2 - h // 10, h // 2 + h // 10), slice(w // 2 - w // 10, w // 2 + w // 10))
    corner = (slice(0, h // 10), slice(0, w // 10))
    assert np.abs(with_cube[centre] - plane_only[centre]).mean() > 20  # the cube is there
    assert np.abs(with_cube[corner] - plane_only[corner]).mean() < 1  # the ground is not
    # where the cube is, an untextured grey (its faces flat-lit), not the brown ground
    cube = np.abs(with_cube - plane_only).max(axis=2) > 30
    assert cube.mean() > 0.02
    pixels = with_cube[cube]
    assert np.abs(pixels[:, 0] - pixels[:, 2]).mean() < 12  # B ≈ R: grey
    _, counts = np.unique(pixels.mean(axis=1).round(), return_counts=True)
    assert np.sort(counts)[-3:].sum() > 0.8 * len(pixels)  # ≤ 3 flat faces (+ edges)
