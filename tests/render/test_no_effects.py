"""A project whose effects change nothing renders byte-identical images to the same
project without effects: the renderer's file is moved into place, never decoded."""

from __future__ import annotations

import pytest

from designer.project import model as m
from designer.render.pipeline import render_project
from tests.synthetic import small_survey, write_project_file

pytestmark = [pytest.mark.blender, pytest.mark.slow]


def test_identity_effects_leave_the_rendered_files_untouched(tmp_path):
    plain = small_survey(n_photos=2, samples=4, size_px=(320, 240))
    identity = m.Effects(vignetting=m.Vignetting(0.0), blur=m.Blur(0.0),
                         motion_blur=m.MotionBlur(0.0, 8.0), sensor_noise=m.SensorNoise(0.0, 1))
    nothing = small_survey(n_photos=2, samples=4, size_px=(320, 240), effects=identity)
    noisy = small_survey(n_photos=2, samples=4, size_px=(320, 240),
                         effects=m.Effects(sensor_noise=m.SensorNoise(1.0, 1)))
    images = {}
    for name, project in (("plain", plain), ("identity", nothing), ("noisy", noisy)):
        summary = render_project(write_project_file(project, tmp_path / name),
                                 tmp_path / name / "out",
                                 workers=1)
        images[name] = {p.name: p.read_bytes()
                        for p in sorted(summary.images_dir.glob("IMG_*.png"))}
    assert len(images["plain"]) == 2
    assert images["identity"] == images["plain"]
    # the comparison can fail: one effect that does change the pixels
    assert all(images["noisy"][k] != images["plain"][k] for k in images["plain"])
