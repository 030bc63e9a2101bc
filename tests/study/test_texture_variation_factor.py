"""The study factor ``texture-variation-strength``: 0 is the plain tiled texture."""

from __future__ import annotations

import dataclasses

from designer.project import template
from designer.project.validate import semantic_problems
from designer.study.factors import FACTORS


def test_strength_sets_removes_and_adds_the_variation():
    f = FACTORS["texture-variation-strength"]
    assert f.stage == "render"
    example = template("survey").project
    assert f.get(example) == 0.35
    stronger = f.set(example, f.parse("0.6"))
    assert stronger.scene.texture.variation == dataclasses.replace(
        example.scene.texture.variation, strength=0.6)  # seed and scale kept
    off = f.set(example, f.parse("0"))
    assert off.scene.texture.variation is None and f.get(off) == 0.0
    # a base without a variation gets one scaled to two tiles (20 m tiles here)
    on = f.set(off, 0.3)
    assert (on.scene.texture.variation.scale_m, on.scene.texture.variation.strength) == (
        40.0, 0.3)
    assert semantic_problems(on) == []
    # a level outside 0..1 is refused by the project's own validation
    assert any("strength = 1.5 must be from 0 to 1" in p.message
               for p in semantic_problems(f.set(example, 1.5)))
