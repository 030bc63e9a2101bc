"""The study model: what a study file says, as frozen dataclasses (lxml-free).

Positions (``line``, ``column``) of the elements are kept so that a value the project
rejects can be reported as ``STUDY:LINE:COL: <element>: message``. The study XSD is
written from these classes (``python -m designer.study.xsd_gen``; their XML form is
declared as the project model's, designer.project.declare_structure).
"""

from __future__ import annotations

import typing
from dataclasses import MISSING, dataclass
from pathlib import Path
from typing import Literal

from designer.project.declare_structure import (
    Choice,
    OneOf,
    Restricted,
    XsdAttr,
    nested,
    schema_attrs,
    unwritten,
    xml_type,
)

Design = Literal["one-at-a-time", "full-factorial"]

#: metrics reported when the study names none (columns of results.csv)
DEFAULT_METRICS = ("check_rmse_xy_m", "check_rmse_z_m", "cloud_nmad_m", "registered")


@dataclass(frozen=True)
class Where:
    """Line and column (1-based) of an element in the study file."""

    line: int = 0
    column: int = 0


@dataclass(frozen=True)
class BaseProject:
    """The base project: a file (relative to the study file) or inline project XML."""

    file: str | None = schema_attrs(None, XsdAttr(
        "file", "path of the base project file, relative to the study file", "xs:string"))
    inline_xml: bytes | None = nested(None, any_element=True)
    where: Where = unwritten(factory=Where)


@xml_type(content=("description", Choice(("values", "range_spec"))))
@dataclass(frozen=True)
class FactorSpec:
    """A factor: a named parameter (designer.study.factors) and its levels as text."""

    name: str = schema_attrs(MISSING, XsdAttr(
        "name", "a factor name, e.g. altitude-m, control-count, calibration", "d:Name", True))
    values: tuple[str, ...] = nested(
        doc="the levels, separated by spaces (numbers, true/false or names)",
        xsd="d:ValueList")
    description: str | None = nested(None, doc="why the factor is varied, in words",
                                     xsd="xs:string")
    where: Where = unwritten(factory=Where)
    values_where: Where = unwritten(factory=Where)
    #: (start, stop, step) when the levels were given as a ``<range>``, kept so the
    #: study is written back as the range it was
    range_spec: tuple[float, float, float] | None = nested(
        None, doc="levels start, start + step, ... up to stop (inclusive)", tag="range",
        optional=False, item_attrs=(
            XsdAttr("start", "first level", "d:FiniteDecimal", True),
            XsdAttr("stop", "last level (included when reached)", "d:FiniteDecimal", True),
            XsdAttr("step", "a positive step between levels",
                    Restricted("d:FiniteDecimal", (("minExclusive", "0"),)), True)))


@dataclass(frozen=True)
class Replicates:
    """``count`` replicates; ``vary``: the random draws re-seeded per replicate."""

    count: int = schema_attrs(1, XsdAttr(
        "count", "replicates per variant, 1 to 1000",
        Restricted("xs:int", (("minInclusive", "1"), ("maxInclusive", "1000"))), True))
    vary: tuple[str, ...] = schema_attrs((), XsdAttr(
        "vary", "space-separated names of replicate draws (the Draw type)", "d:DrawList"))
    where: Where = unwritten(factory=Where)


@xml_type(tag="study", content=("description", "base", "factors", "design", "replicates",
                                 "metrics", "cost"),
          extra_attrs=(XsdAttr("schema-version", "the schema version, 1.0", "xs:string",
                               True),))
@dataclass(frozen=True)
class Study:
    """A study: a base project, factors, a design, replicates and metrics."""

    name: str = schema_attrs(MISSING, XsdAttr(
        "name", "the study's name (letters, digits, '_', '.', '+', '-')", "d:Name", True))
    base: BaseProject = nested(
        doc="the project every variant starts from: file=\"PATH\" (relative to the study "
        "file) or a complete <project> inside", tag="base-project")
    factors: tuple[FactorSpec, ...] = nested(
        doc="a parameter to vary: name=\"...\" (see 'designer study factors') with <values> "
        "or <range>", tag="factor", optional=True)
    design: Design = nested(
        "one-at-a-time", doc="one-at-a-time (each factor varied around the base, the "
        "default) or full-factorial (every combination)",
        xsd=OneOf((), typing.get_args(Design)))
    replicates: Replicates = nested(
        factory=Replicates, doc="count=\"N\" replicates of every variant; vary=\"...\" the "
        "random draws re-seeded per replicate")
    metrics: tuple[str, ...] = nested(
        DEFAULT_METRICS, doc="results.csv columns plotted in the report, e.g. "
        "check_rmse_z_m cloud_nmad_m", xsd="d:MetricList")
    description: str | None = nested(None, doc="what the study asks, in words",
                                     xsd="xs:string")
    #: what the report plots accuracy against (a name of designer.study.cost.COSTS, the
    #: schema's Cost type)
    cost: str = nested(
        "flight-minutes", doc="the cost the report plots accuracy against: flight-minutes "
        "(the default), images, gcps (control and check targets surveyed), control-gcps, "
        "cpu-seconds (processing CPU) or wall-seconds", xsd="d:Cost")
    #: the study file (None for a study built in code); relative paths start at its folder
    source: Path | None = unwritten(None)
    where: Where = unwritten(factory=Where)

    @property
    def folder(self) -> Path:
        return self.source.parent if self.source is not None else Path.cwd()


#: most levels a range may produce
MAX_LEVELS = 1000


def range_levels(start: float, stop: float, step: float) -> tuple[str, ...]:
    """The levels of ``<range start stop step>``: start, start + step, … up to stop
    (inclusive), as text. ValueError says what is wrong with the three numbers."""
    if not step > 0:
        raise ValueError(f"step {step:g}: give a step greater than 0")
    if stop < start:
        raise ValueError(f"stop {stop:g} is below start {start:g}; give stop >= start")
    n = int((stop - start) / step + 1e-9) + 1
    if n > MAX_LEVELS:
        raise ValueError(f"{n} levels are too many (at most {MAX_LEVELS}); use a larger step")
    return tuple(f"{round(start + k * step, 10):g}" for k in range(n))
