"""Render-time estimates read right in every panel: an estimate from the reference figures
says it is uncalibrated, and short times are given in seconds (never '0.0 min' or
'0.0 s')."""

from __future__ import annotations

import re

import pytest

from tests.gui.helpers import open_panel, wait_idle
from tests.gui.study_helpers import _add, _checked, _tiny_base

pytestmark = pytest.mark.gui

#: a time that reads as nothing: 0.0 min, 0 min, 0.0 s, 0 s, 0.0 h
ZERO_TIME = re.compile(r"(?<![\d.])0(\.0+)? ?(min|s|h)\b")


def test_estimates_say_uncalibrated_and_short_times_read_in_seconds(qtbot, window,
                                                                   tmp_path):
    w = window
    study, _ = _tiny_base(qtbot, w, tmp_path)
    assert w.sync.stations is not None and w.sync.stations.render_costs

    flight = open_panel(w, "Flight")
    wait_idle(qtbot, w)
    flight_text = flight.time_label.text()
    render = open_panel(w, "Render")
    wait_idle(qtbot, w)
    render_text = render.cost.text()
    open_panel(w, "Study")
    _add(qtbot, study, "marking-sigma-px", "0.2 2")
    study_text = _checked(qtbot, w, study)

    for name, text in (("Flight", flight_text), ("Render", render_text),
                       ("Study", study_text)):
        assert "uncalibrated" in text, (name, text)
        assert not ZERO_TIME.search(text), (name, text)


@pytest.mark.parametrize("seconds, text", [
    (0.0, "< 0.1 s"), (0.04, "< 0.1 s"), (0.4, "0.4 s"), (3.0, "3.0 s"), (12.4, "12 s"),
    (89.0, "89 s"), (216.0, "3.6 min"), (8640.0, "2.4 h"), (float("nan"), "–")])
def test_times_are_written_in_seconds_when_short(seconds, text):
    from designer.gui.state.study_data import duration_text
    from designer.gui.state.wording import duration

    assert duration(seconds) == text
    assert duration_text(seconds) == text  # the Study panel's times read the same
