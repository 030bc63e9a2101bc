"""The study factor ``building-eave-height-m``: every extruded building's walls, the
roof's rise kept; refused for a base without buildings."""

from __future__ import annotations

import pytest

from designer.project.validate import semantic_problems
from designer.study.factors import FACTORS
from tests.world.building_helpers import building_project


def test_eave_height_sets_every_building_and_keeps_the_roof_rise():
    f = FACTORS["building-eave-height-m"]
    assert f.stage == "render"
    p = building_project()
    assert f.get(p) == 15.0
    taller = f.set(p, f.parse("7.5"))
    assert [b.eave_height_m for b in taller.scene.buildings] == [7.5, 7.5, 7.5]
    assert [b.ridge_height_m for b in taller.scene.buildings] == [None, 9.5, 9.0]
    assert f.get(taller) == 7.5 and semantic_problems(taller) == []
    assert any("eave-height-m = -1.0 must be greater than 0" in p.message
               for p in semantic_problems(f.set(p, -1.0)))
    bare = building_project(with_buildings=False)
    assert f.get(bare) is None
    with pytest.raises(ValueError, match="no building"):
        f.set(bare, 5.0)
