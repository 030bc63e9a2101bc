"""The Effects panel is made from the effects' declarations: a declared effect gets its
group and fields (limits, unit) with no panel code of its own, in a real window."""

from __future__ import annotations

import pytest

from designer.project import model as m

#: effect name → (title starts with, value when switched on, fields, first field's
#: minimum, maximum and suffix)
DECLARED = {
    "exposure_variation": ("auto exposure and white balance", m.ExposureVariation(),
                           ["exposure_sigma_ev", "white_balance_sigma_k", "reference_k",
                            "seed"], (0.0, 2.0, " EV")),
    "chromatic_aberration": ("lateral chromatic aberration", m.ChromaticAberration(),
                             ["red_scale_ppm", "blue_scale_ppm"], (-5000.0, 5000.0, " ppm")),
}


@pytest.mark.parametrize("name", DECLARED)
def test_the_effects_panel_has_its_group_and_fields(qtbot, name):
    from designer.gui.qt.panels.effects import EFFECTS

    title, default, fields = EFFECTS[name]
    start, on, names, limits = DECLARED[name]
    assert title.startswith(start)
    assert default == on
    assert [f[1] for f in fields] == names
    box = fields[0][2]()
    assert (box.minimum(), box.maximum(), box.suffix()) == limits
