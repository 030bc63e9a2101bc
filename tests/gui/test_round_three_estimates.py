"""Render-time estimates name the records they use: those of the project's own kind of
image, not the latest record of any kind (round three)."""

from __future__ import annotations

import json

import pytest

from designer.render_time.model import SPEED_FILE, cache_dir, cost_key
from tests.gui.helpers import open_panel, wait_idle
from tests.gui.study_helpers import _add, _checked, _tiny_base

pytestmark = pytest.mark.gui


def _record(key: dict, images: int, measured: str) -> dict:
    return {**key, "terrain_cpu_s_per_mp_sample": 0.3, "background_cpu_s_per_mp_sample": 0.1,
            "post_s_per_mp": 0.2, "fixed_s": 9.0, "images": images, "measured": measured,
            "source": "render"}


def test_each_panel_names_the_records_of_the_projects_kind_of_image(qtbot, window,
                                                                   tmp_path):
    w = window
    study, _ = _tiny_base(qtbot, w, tmp_path)
    costs = w.sync.stations.render_costs
    assert costs
    own = cost_key(costs[0])
    other = {"scene": "terrain+buildings+plants", "effects": "other-effects",
             "samples_band": own["samples_band"] * 8, "size_band": own["size_band"] * 8}
    # this project's kind measured first, another kind since (the latest record)
    (cache_dir() / SPEED_FILE).write_text(json.dumps({"records": [
        _record(own, 7, "2026-01-01"), _record(other, 50, "2026-02-02")]}))
    names = "render of 7 images on 2026-01-01"

    flight = open_panel(w, "Flight")
    w.sync.stations_changed.emit()
    wait_idle(qtbot, w)
    render = open_panel(w, "Render")
    render.refresh()
    wait_idle(qtbot, w)
    open_panel(w, "Study")
    _add(qtbot, study, "marking-sigma-px", "0.2 2")
    study_text = _checked(qtbot, w, study)
    for name, text in (("Flight", flight.time_label.text()), ("Render", render.cost.text()),
                       ("Study", study_text)):
        assert names in text, (name, text)
        assert "2026-02-02" not in text, (name, text)
