"""Greyed fields show what switching their setting on gives, never their minimum (issue 53,
finding 9; docs/gui.md, "Greyed fields"): an imported flight (photos, no flight plan)
greys the Flight panel's grid fields, which show the default plan's 50 m and 80/70 %
and the GSD those 50 m give; a project without plants greys the plant fields, which show
the group switching plants on makes. (A flight by height already showed, greyed, the GSD
the height gives: the Flight panel's readouts.)"""

from __future__ import annotations

import pytest
from PySide6.QtWidgets import QDoubleSpinBox

from designer.gui.state.switched_on import FIRST_PLANT_KIND, NEW_DENSITY_PER_M2
from designer.project import model as m
from designer.project.interiors import interior_from_camera
from designer.survey.flight import camera_calc
from tests.gui.helpers import field, open_panel, problems, wait_idle
from tests.synthetic import small_survey, write_project_file

pytestmark = pytest.mark.gui


def _gsd_cm(project, altitude_m: float) -> float:
    interior = interior_from_camera(project.cameras[0])
    return 100 * camera_calc(interior, altitude_agl_m=altitude_m, front_overlap_fraction=0.8,
                             side_overlap_fraction=0.7).gsd_m


def test_greyed_flight_and_plant_fields_show_what_switching_on_gives(qtbot, window,
                                                                      tmp_path):
    w = window
    project = small_survey(n_photos=3)
    assert project.trajectory.flight_plan is None and project.scene.vegetation is None
    assert w.file_actions.open(write_project_file(project, tmp_path / "photos")), problems(w)
    flight = open_panel(w, "Flight")
    wait_idle(qtbot, w)
    shown = {}
    for name in ("altitude_agl_m", "front_overlap_percent", "side_overlap_percent"):
        box = field(flight, QDoubleSpinBox, f"trajectory.flight_plan.{name}")
        assert not box.isEnabled(), name
        shown[name] = box.value()
    assert shown == {"altitude_agl_m": 50.0, "front_overlap_percent": 80.0,
                     "side_overlap_percent": 70.0}, shown
    assert not flight.gsd_spin.isEnabled()
    assert flight.gsd_spin.value() == pytest.approx(_gsd_cm(project, 50.0), abs=1e-3)

    plants = open_panel(w, "Vegetation")
    wait_idle(qtbot, w)
    density = field(plants, QDoubleSpinBox, "Plant density")
    assert not density.isEnabled()
    assert density.value() == NEW_DENSITY_PER_M2[FIRST_PLANT_KIND]
    height = field(plants, QDoubleSpinBox, "Plant height")
    assert height.value() == m.PLANT_KINDS[FIRST_PLANT_KIND][0]
    assert not plants.kind.isEnabled() and plants.kind.currentData() == FIRST_PLANT_KIND



def test_greyed_defocus_object_distance_says_each_images_own(qtbot, window, tmp_path):
    """Defocus off: its object distance, greyed, shows what switching it on gives (each
    image's own distance to the ground), not the field's old minimum of 0.1 m."""
    w = window
    project = small_survey(n_photos=3)
    assert project.effects is None or project.effects.defocus is None
    assert w.file_actions.open(write_project_file(project, tmp_path / "plain")), problems(w)
    effects = open_panel(w, "Effects")
    wait_idle(qtbot, w)
    [box] = [b for b in effects.findChildren(QDoubleSpinBox)
             if b.objectName().endswith(" object distance")]
    assert not box.isEnabled()
    assert box.text() == box.specialValueText() == "each image's distance to the ground"
