"""Effects panel: every effect of the model on and off, its fields bound through undo."""

from __future__ import annotations

import pytest
from PySide6.QtWidgets import QCheckBox, QDoubleSpinBox, QSpinBox

from designer.project import model as m
from tests.gui.helpers import field, set_field, wait_idle

pytestmark = pytest.mark.gui


def test_the_example_survey_shows_its_effects(qtbot, window):
    w = window
    assert w.file_actions.new("survey")
    wait_idle(qtbot, w)
    fx = w.document.project.effects
    groups = w.panels["Effects"].groups
    for name, group in groups.items():
        assert group.isChecked() == (getattr(fx, name) is not None), name
    assert groups["sensor"].isChecked()  # the physical sensor of the example
    full_well = w.findChild(QDoubleSpinBox, "sensor (photon shot noise, dark current, read "
                                            "noise, ADC) full well")
    assert full_well.value() == fx.sensor.full_well_e


def test_defocus_and_vignetting_terms(qtbot, window):
    w = window
    panel = w.panels["Effects"]
    w.docks["Effects"].raise_()
    panel.groups["defocus"].setChecked(True)
    assert w.document.project.effects.defocus == m.Defocus(2.8, 50.0)
    distance = field(w, QDoubleSpinBox, "defocus (thin lens) object distance")
    assert distance.text() == "each image's distance to the ground"  # None in the model
    set_field(qtbot, distance, "35")
    set_field(qtbot, field(w, QDoubleSpinBox, "defocus (thin lens) f-number"), "4")
    assert w.document.project.effects.defocus == m.Defocus(4.0, 50.0, 35.0)
    set_field(qtbot, distance, "0")
    assert w.document.project.effects.defocus.object_distance_m is None

    panel.groups["vignetting"].setChecked(True)
    set_field(qtbot, field(w, QDoubleSpinBox, "vignetting ρ⁴ term"), "0.1")
    field(w, QCheckBox, "vignetting natural_cos4").setChecked(True)
    assert w.document.project.effects.vignetting == m.Vignetting(0.2, 0.1, 0.0, True)
    set_field(qtbot, field(w, QSpinBox, "JPEG compression quality"), "80")  # off: no change
    assert w.document.project.effects.jpeg is None
    w.undo_stack.undo()
    assert w.document.project.effects.vignetting == m.Vignetting(0.2, 0.1)
    panel.groups["defocus"].setChecked(False)
    panel.groups["vignetting"].setChecked(False)
    assert w.document.project.effects is None
