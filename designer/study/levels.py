"""A study's runs by factor level: which runs sit at a level (:func:`level_rows`), the
factor's levels in order (:func:`factor_levels`), and the mean of a metric over them with
its 95 % interval (:func:`interval95`), and the lengths of an interval's bar either side
of its mean (:func:`bar_lengths`). Used by the tables (:mod:`.results`), the report
(:mod:`.report`) and its accuracy-against-cost figure (:mod:`.cost_figure`)."""

from __future__ import annotations

import math


def mean_within(xs: list[float]) -> float:
    """The mean of ``xs`` (not empty), never outside their smallest and largest value: a
    float sum can put the mean of equal values a rounding beside them (five times 0.87
    averages 0.8699999999999999), and an interval from their range would miss it."""
    return min(max(sum(xs) / len(xs), min(xs)), max(xs))


def interval95(values: list[float]) -> dict:
    """Mean and 95 % confidence interval of the mean (Student t) of finite values; equal
    values give that value as mean and both ends."""
    xs = [float(v) for v in values if v is not None and math.isfinite(float(v))]
    if not xs:
        return {"n": 0, "mean": None, "low": None, "high": None}
    n = len(xs)
    mean = mean_within(xs)
    if n == 1 or min(xs) == max(xs):
        return {"n": n, "mean": mean, "low": mean, "high": mean}
    from scipy import stats

    sd = math.sqrt(sum((x - mean) ** 2 for x in xs) / (n - 1))
    half = float(stats.t.ppf(0.975, n - 1)) * sd / math.sqrt(n)
    return {"n": n, "mean": mean, "low": mean - half, "high": mean + half}


def bar_lengths(mean: float, low: float | None, high: float | None) -> tuple[float, float]:
    """The lengths of an interval's error bar below and above ``mean`` (matplotlib's
    ``yerr``), never negative: an interval that misses its mean by a rounding (a
    summary.json of an earlier version) is drawn from the mean; a missing or non-finite
    end gives no bar on its side."""
    def length(d):
        return d if d is not None and math.isfinite(d) and d > 0 else 0.0

    return (length(None if low is None else mean - low),
            length(None if high is None else high - mean))


def level_rows(plan, rows: list[dict], factor: str, level: str) -> list[dict]:
    """Rows at ``factor`` = ``level``: one-at-a-time, the others at their base levels;
    full factorial, all of them (the factor's main effect)."""
    return rows_at_level(plan.study.design, rows, factor, level)


def rows_at_level(design: str, rows: list[dict], factor: str, level: str) -> list[dict]:
    """:func:`level_rows` of a study of ``design`` (one-at-a-time, full-factorial)."""
    key = f"factor:{factor}"
    out = [r for r in rows if str(r.get(key)) == level]
    if design == "one-at-a-time":
        base = {f"factor:{k}": v for k, v in _base_levels(rows).items()}
        out = [r for r in out if all(str(r.get(k)) == str(v) for k, v in base.items()
                                     if k != key)]
    return out


def _base_levels(rows: list[dict]) -> dict:
    base = [r for r in rows if r.get("variant") == 0]
    return {k.removeprefix("factor:"): v for k, v in (base[0] if base else {}).items()
            if k.startswith("factor:")}


def factor_levels(plan, rows: list[dict], factor: str) -> list[str]:
    """The factor's levels in the study's order, the base level among them."""
    spec = next(f for f in plan.study.factors if f.name == factor)
    levels = list(spec.values)
    base = str(_base_levels(rows).get(factor, ""))
    if base and base not in levels:
        levels.append(base)
        try:
            levels.sort(key=float)
        except ValueError:
            pass
    return levels
