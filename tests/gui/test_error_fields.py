"""A library error that carries its fields (designer.errors.ParameterError: parameter,
value, what it must be) is worded by the window from them, not by re-reading its message;
the command line's message stays the library's (Qt-free)."""

from __future__ import annotations

import pickle

import pytest

from designer.errors import DesignerError, ParameterError
from designer.gui.state.wording import error_text, humanize
from designer.scene.terrain import procedural_terrain
from designer.survey import area as area_mod
from designer.survey import gcp_layout
from designer.survey.flight import plan_flight
from tests.synthetic import phantom4

SQUARE = area_mod.rectangle(0, 0, 100, 100)


def _raised(call, *args, **kwargs) -> ParameterError:
    with pytest.raises(ParameterError) as caught:
        call(*args, **kwargs)
    return caught.value


def test_a_size_that_is_not_whole_grid_cells_is_worded_from_its_fields():
    error = _raised(procedural_terrain, 100.0, 100.0, 3.0, 5.0, 1)
    assert str(error) == ("procedural terrain: size_x_m=100.0 is not a whole number of "
                          "spacing_m=3.0 cells; choose a spacing that divides the size")
    assert (error.name, error.value, error.unit) == ("size_x_m", 100.0, "m")
    assert error_text(error) == ("terrain width (X) 100 m must be a whole number of 3 m grid "
                                 "cells; choose a grid spacing that divides it")


@pytest.mark.parametrize(("call", "args", "kwargs", "text"), [
    (procedural_terrain, (100.0, 100.0, 0.0, 5.0, 1), {},
     "grid spacing 0 m must be greater than 0 m"),
    (procedural_terrain, (100.0, 100.0, 1.0, -2.0, 1), {},
     "relief -2 m must be at least 0 m"),
    (procedural_terrain, (100.0, 100.0, 1.0, 2.0, 1), {"roughness": 1.5},
     "roughness 1.5 must be from 0 to 1"),
    (gcp_layout.assign_roles, (5, 7), {"pattern": "interleaved"},
     "number of check points 7 must be from 0 to the 5 GCPs"),
    (gcp_layout.assign_roles, (5, 2.5), {"pattern": "interleaved"},
     "number of check points 2.5 must be a whole number"),
    (area_mod.inset, (SQUARE, -1.0), {}, "margin -1 m must be at least 0 m"),
    (plan_flight, (SQUARE, phantom4()), {"altitude_agl_m": 50.0, "forward_tilt_deg": 95.0},
     "forward tilt 95 ° must be from -80 to 80 °"),
    (plan_flight, (SQUARE, phantom4()), {"altitude_agl_m": 50.0,
                                         "grid_angle_deg": float("nan")},
     "line azimuth not a number must be a finite number of degrees"),
])
def test_parameter_errors_are_worded_from_their_fields(call, args, kwargs, text):
    error = _raised(call, *args, **kwargs)
    assert error_text(error) == text
    assert "_" not in error_text(error)


def test_the_fields_survive_pickling_and_other_errors_are_humanized():
    error = _raised(gcp_layout.assign_roles, 5, 7, pattern="interleaved")
    copy = pickle.loads(pickle.dumps(error))
    assert (str(copy), copy.name, copy.value, copy.must) == (
        str(error), error.name, error.value, error.must)
    plain = DesignerError("cell_m = 1e+06 is too large")
    assert error_text(plain) == humanize(str(plain)) == "coverage grid cell = 1000000 is too large"
