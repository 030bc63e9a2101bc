"""Accuracy against cost per variant, and the variants worth considering (the front).

Each variant is its replicates' mean cost and error with their spread, the smallest
and largest value over its finished replicates (one replicate: no spread).

The rule (:func:`front`): two variants differ in cost (or error) only when their
ranges do not overlap; where the ranges overlap, neither is better. Variant A is
*dominated* when another variant B is better beyond the spread in cost or in error and
not worse beyond it in the other — B's largest value below A's smallest in one, and B's
smallest not above A's largest in the other. The front is every variant not dominated.
With one replicate per variant the ranges are points and this is the plain Pareto front
of the means (equal costs: the smaller error wins). A measured cost (CPU or wall
seconds) with one replicate has no spread to tell noise from a difference:
:func:`front_rule` then draws no front.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from designer.study.levels import mean_within


@dataclass(frozen=True)
class Spread:
    """Mean, smallest and largest of a variant's replicates (the mean between them: equal
    replicates give their value three times)."""

    mean: float
    low: float
    high: float

    @classmethod
    def of(cls, values: list[float]) -> Spread | None:
        xs = [float(v) for v in values if v is not None and math.isfinite(float(v))]
        if not xs:
            return None
        return cls(mean_within(xs), min(xs), max(xs))

    @property
    def varies(self) -> bool:
        return self.high > self.low


@dataclass(frozen=True)
class VariantPoint:
    variant: int
    label: str
    runs: int  # finished replicates with both numbers
    cost: Spread
    error: Spread


def variant_points(rows: list[dict], cost_column: str, error_column: str,
                   labels: dict[int, str]) -> list[VariantPoint]:
    """Each variant with finished runs that have both numbers, in variant order."""
    out = []
    for v in sorted({int(r["variant"]) for r in rows}):
        good = [r for r in rows if int(r["variant"]) == v and r.get("status") == "ok"
                and _number(r.get(cost_column)) is not None
                and _number(r.get(error_column)) is not None]
        if good:
            out.append(VariantPoint(
                v, labels.get(v, f"v{v}"), len(good),
                Spread.of([_number(r[cost_column]) for r in good]),
                Spread.of([_number(r[error_column]) for r in good])))
    return out


def _number(v) -> float | None:
    if v is None or v == "":
        return None
    try:
        x = float(v)
    except (TypeError, ValueError):
        return None
    return x if math.isfinite(x) else None


def _better(b: Spread, a: Spread) -> bool:
    return b.high < a.low


def dominates(b: VariantPoint, a: VariantPoint) -> bool:
    """Whether ``b`` beats ``a`` beyond the replicate spread (module docstring)."""
    if _better(a.cost, b.cost) or _better(a.error, b.error):
        return False
    return _better(b.cost, a.cost) or _better(b.error, a.error)


def front(points: list[VariantPoint]) -> list[VariantPoint]:
    """The variants no other dominates, by cost (then error)."""
    kept = [a for a in points if not any(dominates(b, a) for b in points if b is not a)]
    return sorted(kept, key=lambda p: (p.cost.mean, p.error.mean))


def front_rule(points: list[VariantPoint], planned_cost: bool) -> tuple[bool, str]:
    """(whether to draw a front, the sentence that says which rule holds)."""
    replicated = any(p.runs > 1 for p in points)
    if not planned_cost and not replicated:
        return False, ("no front: a measured cost with one replicate per variant has no "
                       "spread to tell a difference from noise; give replicates")
    if replicated:
        return True, ("front: variants no other beats beyond the replicate spread — "
                      "better in cost or error with no overlap of the ranges (bars: smallest "
                      "to largest replicate), and not worse in the other")
    return True, "front: variants no other beats in both cost and error (one replicate)"
