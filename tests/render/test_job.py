"""The render job: the distortion render's oversampling and the per-frame effect context
(no Blender needed)."""

from __future__ import annotations

from dataclasses import replace

import pytest

from designer.effects.distortion_render import DistortionWarp
from designer.project import load_project
from designer.project import model as m
from designer.project.interiors import render_interior
from designer.render.job import prepare_job
from designer.render.job_spec import RenderJob
from tests.synthetic import small_survey, write_project_file


@pytest.mark.parametrize("oversample", [1, 2])
def test_distortion_oversample_renders_finer(tmp_path, oversample):
    project = small_survey(n_photos=2, distortion=m.BrownConradyDistortion(k1=-0.05),
                           effects=m.Effects(defocus=m.Defocus(2.8, 25.0)))
    project = replace(project, render=replace(project.render,
                                              distortion_oversample=oversample))
    path = write_project_file(project, tmp_path / "p")
    prepared = prepare_job(load_project(path), path.parent, tmp_path / "out")
    job = RenderJob.read(prepared.job_path)
    assert job == prepared.job
    # the job carries the effects model and the camera as rendered: the worker builds the
    # chain from it alone (no project file beside the job)
    loaded = load_project(path)
    assert job.effects.model == loaded.effects
    assert job.effects.cameras["cam"].interior == render_interior(
        loaded.camera("cam"), loaded.render.resolution_scale)
    assert not job.effects.rig
    assert not (prepared.job_path.parent / "project.xml").exists()
    warp = DistortionWarp.load(prepared.job_path.parent / job.effects.cameras["cam"].warp)
    assert warp.oversample == oversample
    assert warp.output_size_px == (640, 480)
    # the pinhole render covers the distorted field at oversample × the output's pixels
    assert warp.render_size_px[0] > 640 * oversample
    assert warp.render_size_px[0] < 1.1 * 640 * oversample
    # every frame knows its distance to the ground (for defocus): ~30 m flying height
    for frame in job.frames:
        assert frame.distance_m == pytest.approx(30.0, abs=2.0)


def test_scene_objects_are_in_the_render_job(tmp_path):
    """The validation cube's mesh is placed (scale 4, on the plane) and each face lit by
    the sun and sky: the top brighter than the shaded side."""
    import numpy as np

    from designer.project import template, write_project

    folder = tmp_path / "cube"
    folder.mkdir()
    tpl = template("validation-cube")
    path = folder / "validation-cube.xml"
    write_project(tpl.project, path)
    for name, data in tpl.files.items():
        (folder / name).write_bytes(data)
    prepared = prepare_job(load_project(path), path.parent, tmp_path / "out")
    job = RenderJob.read(prepared.job_path)
    spec = next(o for o in job.objects if o.name == "scene_objects")
    data = np.load(prepared.job_path.parent / spec.mesh)
    v = data["vertices_local"]
    assert v.min(axis=0) == pytest.approx([-2.0, -2.0, 0.0], abs=1e-9)  # unit cube × 4
    assert v.max(axis=0) == pytest.approx([2.0, 2.0, 4.0], abs=1e-9)
    brightness = np.array([m.color[0] for m in spec.materials])
    face_light = brightness[data["material_index"]]
    f = data["faces"]
    normal_z = np.cross(v[f[:, 1]] - v[f[:, 0]], v[f[:, 2]] - v[f[:, 0]])[:, 2]
    top = face_light[normal_z > 0].mean()
    assert top > face_light.min() and top == pytest.approx(face_light.max(), rel=0.05)
