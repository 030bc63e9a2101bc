"""`designer plan`'s footprint is the image at the flight's GSD, also where most images of
a high flight look past a small terrain (their centre rays would enter the terrain's
solid side far below its surface, :mod:`designer.core.raycast`)."""

from __future__ import annotations

from pathlib import Path

import pytest

from designer.checks.plan_report import plan_project
from designer.project.load import load_project

ROOT = Path(__file__).resolve().parents[2]
EXAMPLE = ROOT / "resources" / "examples" / "survey" / "survey.xml"


@pytest.mark.parametrize("height_m", [50.0, 120.0])
def test_the_footprint_is_the_rendered_image_at_the_nominal_gsd(height_m, tmp_path):
    text = EXAMPLE.read_text()
    text = text.replace("<altitude-agl-m>50.0</altitude-agl-m>",
                        f"<altitude-agl-m>{height_m}</altitude-agl-m>")
    text = text.replace("</terrain>", '  <surroundings mode="none"/>\n    </terrain>', 1)
    path = tmp_path / "survey.xml"
    path.write_text(text)
    project = load_project(path)
    result = plan_project(project, tmp_path)
    camera = project.cameras[0]
    scale = project.render.resolution_scale
    # the nominal GSD at the flight's height above the mean terrain (rendered pixels)
    pitch_mm = camera.sensor_width_mm / camera.image_width_px
    gsd_m = height_m * pitch_mm / scale / camera.focal_length_mm
    W, H = result.footprint_m
    width_px = round(camera.image_width_px * scale)
    assert W == pytest.approx(width_px * gsd_m, rel=0.05), (W, width_px * gsd_m)
    assert W / H == pytest.approx(1.5, rel=1e-3)
