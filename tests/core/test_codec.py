"""The generic dataclass ↔ JSON codec: any frozen dataclass round-trips by its type hints,
and reading names the place of every problem."""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from typing import Literal

import pytest

from designer.core.codec import CodecError, from_data, reachable_dataclasses, to_data
from designer.project import model as m


@dataclass(frozen=True)
class Round:
    radius: float


@dataclass(frozen=True)
class Square:
    side: float = 1.0


@dataclass(frozen=True)
class Drawing:
    name: str
    shapes: tuple[Round | Square, ...]
    best: Round | Square | None = None
    kind: Literal["sketch", "plan"] = "sketch"
    size: tuple[int, int] = (1, 1)
    labels: dict[int, str | None] = field(default_factory=dict)
    note: str | float | None = None
    cache: dict = field(default_factory=dict, init=False, compare=False)


DRAWING = Drawing("d", (Round(2.5), Square()), best=Square(3.0), kind="plan", size=(4, 3),
                  labels={1: "one", 2: None}, note=4.5)


def test_any_dataclass_round_trips_through_json_text():
    data = json.loads(json.dumps(to_data(DRAWING)))
    assert "cache" not in data
    assert data["shapes"] == [{"Round": {"radius": 2.5}}, {"Square": {"side": 1.0}}]
    assert from_data(Drawing, data) == DRAWING


def test_an_integer_is_read_as_a_float_where_a_float_belongs():
    back = from_data(Round, {"radius": 2})
    assert back == Round(2.0) and isinstance(back.radius, float)


def test_a_model_that_gains_a_dataclass_needs_no_codec_change():
    @dataclass(frozen=True)
    class Glare:
        strength: float
        streaks: int = 4

    @dataclass(frozen=True)
    class Grown(m.Effects):
        glare: Glare | None = None

    grown = Grown(blur=m.Blur(0.5), glare=Glare(0.25, 6))
    local = {"Glare": Glare}
    assert from_data(Grown, json.loads(json.dumps(to_data(grown, None, local))), "",
                     local) == grown
    assert Glare in reachable_dataclasses(Grown, local)


def test_the_project_effects_model_round_trips():
    effects = m.Effects(vignetting=m.Vignetting(0.2, natural_cos4=True), jpeg=m.Jpeg(80),
                        defocus=m.Defocus(2.8, 20.0))
    assert from_data(m.Effects, json.loads(json.dumps(to_data(effects)))) == effects


@pytest.mark.parametrize(("data", "place", "fragment"), [
    ({"name": "d", "shapes": [], "colour": 1}, "colour", "Drawing has no field 'colour'"),
    ({"shapes": []}, "name", "Drawing needs this field"),
    ({"name": "d", "shapes": [{"Round": {"radius": 1, "r": 2}}]}, "shapes[0].Round.r",
     "Round has no field"),
    ({"name": "d", "shapes": [{"Oval": {}}]}, "shapes[0]", "one key of Round, Square"),
    ({"name": "d", "shapes": [], "kind": "map"}, "kind", "not one of 'sketch', 'plan'"),
    ({"name": "d", "shapes": [], "size": [1]}, "size", "1 items where 2 belong"),
    ({"name": "d", "shapes": [], "labels": {"x": "a"}}, "labels[x]", "whole number"),
    ({"name": "d", "shapes": [], "labels": {"1": 2}}, "labels[1]", "where text belongs"),
    ({"name": 3, "shapes": []}, "name", "3 where text belongs"),
    ({"name": "d", "shapes": [], "note": [1]}, "note", "a list"),
    ({"name": "d", "shapes": [], "size": [True, 1]}, "size[0]", "true where a whole number"),
])
def test_reading_names_the_place_of_the_problem(data, place, fragment):
    with pytest.raises(CodecError) as info:
        from_data(Drawing, data)
    assert info.value.place == place
    assert fragment in info.value.problem
