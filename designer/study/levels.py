"""A study's runs by factor level: which runs sit at a level (:func:`level_rows`), the
factor's levels in order (:func:`factor_levels`), and the mean of a metric over them with
its 95 % interval (:func:`interval95`). Used by the tables (:mod:`.results`) and the
report (:mod:`.report`)."""

from __future__ import annotations

import math


def interval95(values: list[float]) -> dict:
    """Mean and 95 % confidence interval of the mean (Student t) of finite values."""
    xs = [float(v) for v in values if v is not None and math.isfinite(float(v))]
    if not xs:
        return {"n": 0, "mean": None, "low": None, "high": None}
    n = len(xs)
    mean = sum(xs) / n
    if n == 1:
        return {"n": 1, "mean": mean, "low": mean, "high": mean}
    from scipy import stats

    sd = math.sqrt(sum((x - mean) ** 2 for x in xs) / (n - 1))
    half = float(stats.t.ppf(0.975, n - 1)) * sd / math.sqrt(n)
    return {"n": n, "mean": mean, "low": mean - half, "high": mean + half}


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
