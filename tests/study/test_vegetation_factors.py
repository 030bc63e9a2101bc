"""The study factors ``vegetation-density-per-m2`` and ``vegetation-wind-amplitude-deg``."""

from __future__ import annotations

import dataclasses

import pytest

from designer.project import model as m
from designer.project import template
from designer.project.validate import semantic_problems
from designer.study.factors import FACTORS


def test_density_scales_every_group_removes_and_adds_the_vegetation():
    f = FACTORS["vegetation-density-per-m2"]
    assert f.stage == "render"
    base = template("survey").project
    assert base.scene.vegetation is None and f.get(base) == 0.0
    on = f.set(base, f.parse("0.2"))  # a base without plants gets shrubs
    assert [g.kind for g in on.scene.vegetation.plants] == ["shrub"] and f.get(on) == 0.2
    assert semantic_problems(on) == []
    two = dataclasses.replace(on, scene=dataclasses.replace(on.scene, vegetation=(
        dataclasses.replace(on.scene.vegetation, plants=(
            m.PlantGroup(0.3, "grass-tuft"), m.PlantGroup(0.1, "tree"))))))
    denser = f.set(two, 0.8)
    assert [g.density_per_m2 for g in denser.scene.vegetation.plants] == pytest.approx(
        [0.6, 0.2])  # the groups' shares kept
    assert f.get(denser) == pytest.approx(0.8)
    off = f.set(two, 0.0)
    assert off.scene.vegetation is None
    # a level the project refuses is refused by its own validation
    assert any("density-per-m2" in p.message for p in semantic_problems(f.set(on, 500.0)))


def test_wind_amplitude_sets_and_adds_the_wind():
    f = FACTORS["vegetation-wind-amplitude-deg"]
    assert f.stage == "render"
    base = template("survey").project
    with pytest.raises(ValueError, match="no vegetation"):
        f.set(base, 5.0)
    plants = FACTORS["vegetation-density-per-m2"].set(base, 0.1)
    assert f.get(plants) == 0.0
    windy = f.set(plants, f.parse("12"))
    assert windy.scene.vegetation.wind == m.Wind(amplitude_deg=12.0)
    calmer = f.set(dataclasses.replace(windy, scene=dataclasses.replace(
        windy.scene, vegetation=dataclasses.replace(
            windy.scene.vegetation, wind=m.Wind(30.0, 2.0, 180.0)))), 3.0)
    assert calmer.scene.vegetation.wind == m.Wind(3.0, 2.0, 180.0)  # period, direction kept
    assert f.get(calmer) == 3.0
    assert any("amplitude-deg" in p.message for p in semantic_problems(f.set(plants, 60.0)))
