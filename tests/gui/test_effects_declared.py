"""The Effects panel is made from the effects' declarations: a declared effect gets its
group and fields (limits, unit) with no panel code of its own, in a real window."""

from __future__ import annotations

from designer.project import model as m


def test_the_effects_panel_has_its_group_and_fields(qtbot):
    from designer.gui.qt.panels.effects import EFFECTS

    title, default, fields = EFFECTS["exposure_variation"]
    assert title.startswith("auto exposure and white balance")
    assert default == m.ExposureVariation()
    assert [f[1] for f in fields] == ["exposure_sigma_ev", "white_balance_sigma_k",
                                      "reference_k", "seed"]
    box = fields[0][2]()
    assert (box.minimum(), box.maximum(), box.suffix()) == (0.0, 2.0, " EV")
