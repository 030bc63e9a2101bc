"""Replicate draws: which random seeds a replicate re-draws is declared on the seed
(designer.project.declare, ``draw=``); DRAWS and the study schema follow from it."""

from __future__ import annotations

import dataclasses
from pathlib import Path

from lxml import etree

from designer.project import model as m
from designer.project import write_project
from designer.project.declare import declared, declared_elements
from designer.study.design import plan_study, replicate_seed
from designer.study.factors import DRAWS
from designer.study.templates import base_project
from designer.study.xml import read_study, study_schema_path

XS = "{http://www.w3.org/2001/XMLSchema}"

STUDY = """<?xml version="1.0"?>
<study xmlns="urn:designer:project:1" schema-version="1.0" name="exposure">
  <base-project file="base.xml"/>
  <factor name="exposure-sigma-ev">
    <values>0.1 0.3</values>
  </factor>
  <design>full-factorial</design>
  <replicates count="3" vary="exposure-variation"/>
  <metrics>check_rmse_z_m</metrics>
</study>
"""


def _exposure_study(folder: Path) -> Path:
    base = base_project()
    base = dataclasses.replace(base, effects=m.Effects(
        exposure_variation=m.ExposureVariation(seed=7)))
    write_project(base, folder / "base.xml")
    (folder / "study.xml").write_text(STUDY)
    return folder / "study.xml"


def test_replicates_of_an_exposure_variation_study_redraw_it(tmp_path):
    plan = plan_study(read_study(_exposure_study(tmp_path)))
    assert len(plan.runs) == 6
    for variant in (0, 1):
        seeds = {r.replicate: r.project.effects.exposure_variation.seed
                 for r in plan.runs if r.variant == variant}
        assert seeds == {r: replicate_seed("exposure-variation", r) for r in range(3)}
        assert len(set(seeds.values())) == 3
    # the same draw in every variant (common random numbers), only the factor differs
    first = [r.project.effects.exposure_variation for r in plan.runs if r.replicate == 0]
    assert first[0].seed == first[1].seed
    assert {f.exposure_sigma_ev for f in first} == {0.1, 0.3}


def test_draws_are_every_declared_draw_and_the_hand_written_ones():
    declared_draws = {d.attr.draw for cls in declared_elements(m.Project)
                      for d in declared(cls) if d.attr.draw}
    assert {"exposure-variation", "clouds", "marking-error", "position-prior",
            "pre-calibration", "sensor-noise", "pose-noise", "survey-error"} <= declared_draws
    assert declared_draws <= set(DRAWS)
    assert set(DRAWS) - declared_draws == {"gcp-selection"}


def test_a_draw_declared_on_two_elements_reseeds_both_and_an_absent_one_is_left_out():
    base = dataclasses.replace(base_project(), effects=m.Effects(
        sensor_noise=m.SensorNoise(sigma_dn=1.0, seed=1),
        sensor=m.Sensor(full_well_e=2e4, read_noise_e=3.0, seed=2)))
    seeded = DRAWS["sensor-noise"][1](base, 11)
    assert seeded.effects.sensor_noise.seed == seeded.effects.sensor.seed == 11
    assert DRAWS["exposure-variation"][1](base, 11) == base  # nothing to re-draw


def test_the_study_schema_lists_every_draw():
    xsd = etree.parse(str(study_schema_path()))
    enum = xsd.getroot().find(f"{XS}simpleType[@name='Draw']/{XS}restriction")
    assert sorted(e.get("value") for e in enum.iter(f"{XS}enumeration")) == sorted(DRAWS)


def test_the_study_schema_is_generated_from_the_model():
    """The committed study XSD is what the generator makes of the study model and DRAWS
    (no part kept by hand), and a draw the XSD lacks or has too many is found."""
    from designer.study.xsd_gen import generate

    text = study_schema_path().read_text(encoding="utf-8")
    assert generate() == text, ("the study XSD differs from the model: "
                                "python -m designer.study.xsd_gen")
    fewer = {name: doc for name, (doc, _) in DRAWS.items() if name != "exposure-variation"}
    assert generate(fewer) != text
    assert 'value="exposure-variation"' not in generate(fewer)
