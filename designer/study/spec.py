"""The study model: what a study file says, as frozen dataclasses (lxml-free).

Positions (``line``, ``column``) of the elements are kept so that a value the project
rejects can be reported as ``STUDY:LINE:COL: <element>: message``.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Literal

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

    file: str | None = None
    inline_xml: bytes | None = None
    where: Where = field(default_factory=Where)


@dataclass(frozen=True)
class FactorSpec:
    """A factor: a named parameter (designer.study.factors) and its levels as text."""

    name: str
    values: tuple[str, ...]
    description: str | None = None
    where: Where = field(default_factory=Where)
    values_where: Where = field(default_factory=Where)
    #: (start, stop, step) when the levels were given as a ``<range>``, kept so the
    #: study is written back as the range it was
    range_spec: tuple[float, float, float] | None = None


@dataclass(frozen=True)
class Replicates:
    """``count`` replicates; ``vary``: the random draws re-seeded per replicate."""

    count: int = 1
    vary: tuple[str, ...] = ()
    where: Where = field(default_factory=Where)


@dataclass(frozen=True)
class Study:
    name: str
    base: BaseProject
    factors: tuple[FactorSpec, ...]
    design: Design = "one-at-a-time"
    replicates: Replicates = field(default_factory=Replicates)
    metrics: tuple[str, ...] = DEFAULT_METRICS
    description: str | None = None
    #: what the report plots accuracy against (a name of designer.study.cost.COSTS)
    cost: str = "flight-minutes"
    #: the study file (None for a study built in code); relative paths start at its folder
    source: Path | None = None
    where: Where = field(default_factory=Where)

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
