"""Which factors matter: a linear model of each metric on all the study's factors.

For every metric, ordinary least squares (statsmodels) of the metric on every factor as
a categorical variable, over the finished runs (``ok``) of the study::

    metric ~ C(factor_1) + C(factor_2) + …

Both designs fit this additive main-effects model: a full factorial crosses the levels;
one factor at a time puts every other factor at its base level, so each level is
estimated against the base runs. The type II ANOVA table of the fit gives, per factor,
its degrees of freedom, F, p and the partial η² (the share of the variance left after
the other factors that the factor explains). Replicates give the residual degrees of
freedom; without them (one run per level and no replicate) no test is possible and the
row says so.

For a numeric factor (altitude, overlap, σ …) the table adds the slope of the metric
per unit of the factor, with its 95 % interval, from the same model with that factor
entered as a number (the other factors stay categorical).
"""

from __future__ import annotations

import math
import warnings

import numpy as np


def _numeric(values: list) -> list[float] | None:
    try:
        xs = [float(v) for v in values]
    except (TypeError, ValueError):
        return None
    return xs if all(math.isfinite(x) for x in xs) else None


def _fit_table(frame, y: str, names: list[str], numeric: str | None = None):
    import statsmodels.formula.api as smf
    from statsmodels.stats.anova import anova_lm

    terms = [(f"{n}" if n == numeric else f"C({n})") for n in names
             if frame[n].nunique() > 1]
    if not terms:
        return None, None
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        model = smf.ols(f"{y} ~ " + " + ".join(terms), data=frame).fit()
        if model.df_resid < 1:
            return model, None
        return model, anova_lm(model, typ=2)


def factor_effects(factors: list[str], rows: list[dict], metrics: list[str]) -> list[dict]:
    """Per factor and metric: levels, df, F, p, partial η², and the slope per unit of a
    numeric factor with its 95 % interval (``None`` where the data allow no test)."""
    import pandas as pd

    ok = [r for r in rows if r.get("status") == "ok"]
    codes = {f: f"f{i}" for i, f in enumerate(factors)}
    out = []
    for metric in metrics:
        data = [r for r in ok if r.get(metric) is not None
                and math.isfinite(float(r[metric]))]
        frame = pd.DataFrame({"y": [float(r[metric]) for r in data],
                              **{codes[f]: [str(r.get(f"factor:{f}")) for r in data]
                                 for f in factors}})
        table = _fit_table(frame, "y", list(codes.values()))[1] if data else None
        for f in factors:
            code = codes[f]
            row = {"factor": f, "metric": metric,
                   "levels": int(frame[code].nunique()) if len(data) else 0,
                   "runs": len(data), "df": None, "F": None, "p": None, "eta2": None,
                   "slope": None, "slope_low": None, "slope_high": None}
            term = f"C({code})"
            if table is not None and term in table.index:
                ss, df, F, p = (table.loc[term, k] for k in ("sum_sq", "df", "F", "PR(>F)"))
                ss_res = table.loc["Residual", "sum_sq"]
                if math.isfinite(F):
                    row.update(df=int(df), F=float(F), p=float(p),
                               eta2=float(ss / (ss + ss_res)) if ss + ss_res > 0 else None)
            row.update(_slope(frame, code, list(codes.values())))
            out.append(row)
    return out


def _slope(frame, code: str, names: list[str]) -> dict:
    xs = _numeric(list(frame[code])) if len(frame) else None
    if xs is None or len(set(xs)) < 2:
        return {}
    numeric = frame.copy()
    numeric[code] = np.asarray(xs)
    model, _ = _fit_table(numeric, "y", names, numeric=code)
    if model is None or model.df_resid < 1 or code not in model.params.index:
        return {}
    low, high = model.conf_int(0.05).loc[code]
    return {"slope": float(model.params[code]), "slope_low": float(low),
            "slope_high": float(high)}
