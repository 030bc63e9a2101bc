"""The Render panel's figures read right for a one-image render (issue 53, finding 12):
"the rendered image is up to date", never "the 1 rendered images"; and each quality's
cost gives the set-up (scene, bake, Blender's start: paid once) apart from the seconds
per image, so a render whose set-up dominates does not show draft, survey and metrology
as equally expensive per image."""

from __future__ import annotations

import re

import pytest

from designer.gui.state.output_state import RenderState
from designer.render_time.model import RenderSpeed, save_speed
from tests.gui.helpers import open_panel, problems, wait_idle
from tests.synthetic import small_survey, write_project_file

pytestmark = pytest.mark.gui

#: as a render of one image on this machine measured it: 21 s of set-up
SPEED = RenderSpeed(terrain_cpu_s_per_mp_sample=0.3, background_cpu_s_per_mp_sample=0.1,
                    post_s_per_mp=0.2, fixed_s=21.0, source="render",
                    measured="2026-12-06 06:00", images=1)


def test_one_image_reads_in_the_singular_and_costs_show_the_set_up_apart(qtbot, window,
                                                                         tmp_path):
    save_speed(SPEED)
    path = write_project_file(small_survey(n_photos=1), tmp_path / "one")
    w = window
    assert w.file_actions.open(path), problems(w)
    panel = open_panel(w, "Render")
    wait_idle(qtbot, w)
    assert w.sync.stations.n_images == 1

    lines = panel.cost.text().splitlines()
    per_image = []
    for line, preset in zip(lines[:3], ("draft", "survey", "metrology"), strict=True):
        assert line.startswith(f"{preset}: "), line
        assert line.endswith("for 1 image"), line
        per_image.append(float(re.search(r"([\d.]+) s per image", line).group(1)))
    assert per_image[0] < per_image[1] < per_image[2] < 21, lines
    assert lines[3].startswith("each total includes 21 s of set-up"), lines

    panel.show_render_state(RenderState(True, 1, {}, [], "up to date"))
    assert panel.out_of_date.text() == "the rendered image is up to date with the project"
    panel.show_render_state(RenderState(True, 60, {}, [], "up to date"))
    assert panel.out_of_date.text() == "the 60 rendered images are up to date with the project"


def test_the_flight_estimate_line_closes_each_bracket_once():
    """Uncalibrated figures: the basis sits inside the line's own brackets, so it opens
    none of its own (the walk of 12-06 read "…measures this machine))")."""
    from designer.gui.state.render_figures import flight_estimate_line
    from designer.gui.state.wording import estimate_basis
    from designer.render_time.model import REFERENCE, ImageCost, estimate_render

    estimate = estimate_render([ImageCost(megapixels=0.3072, samples=16)], 1,
                               speed=REFERENCE)
    line = flight_estimate_line(estimate, 16, estimate_basis(REFERENCE))
    assert "uncalibrated" in line
    assert line.count("(") == line.count(")") == 1, line
