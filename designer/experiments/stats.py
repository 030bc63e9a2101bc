"""Statistics of corner errors: summaries, correlations with p-values, variance tests.

All errors are detected − projected, in pixels; ``dr`` is the radial part: the change
in distance from the principal point, |uv_det − c| − |uv_proj − c|.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

import numpy as np
from scipy import stats


@dataclass(frozen=True)
class ErrorSummary:
    """Mean, standard deviation and 95 % confidence half-width of the mean of one error."""

    n: int
    mean_px: float
    std_px: float
    ci95_px: float
    rms_px: float

    def to_dict(self) -> dict:
        return asdict(self)


def summarise(values: np.ndarray) -> ErrorSummary:
    """Summary of a 1-D sample of errors (px)."""
    v = np.asarray(values, float)
    n = len(v)
    if n == 0:
        return ErrorSummary(0, math.nan, math.nan, math.nan, math.nan)
    std = float(v.std(ddof=1)) if n > 1 else math.nan
    half = float(stats.t.ppf(0.975, n - 1) * std / math.sqrt(n)) if n > 1 else math.nan
    return ErrorSummary(n, float(v.mean()), std, half, float(np.sqrt(np.mean(v * v))))


@dataclass(frozen=True)
class Correlation:
    """Pearson correlation of an error with a variable, its two-sided p-value, and the
    Bonferroni-corrected p-value over the whole table it belongs to."""

    error: str
    variable: str
    level: str  # "corner" or "image"
    n: int
    r: float
    p: float
    p_bonferroni: float

    def to_dict(self) -> dict:
        return asdict(self)


def correlations(errors: dict[str, np.ndarray], variables: dict[str, np.ndarray],
                 level: str) -> list[Correlation]:
    """Pearson r and p of every error against every variable (same length samples).

    A variable that does not vary (e.g. a principal point offset that all cameras share)
    has no correlation: it is left out.
    """
    out = []
    for e_name, e in errors.items():
        for v_name, v in variables.items():
            e, v = np.asarray(e, float), np.asarray(v, float)
            if len(e) < 3 or np.ptp(v) == 0 or np.ptp(e) == 0:
                continue
            res = stats.pearsonr(e, v)
            out.append((e_name, v_name, len(e), float(res.statistic), float(res.pvalue)))
    m = len(out)
    return [Correlation(e, v, level, n, r, p, min(1.0, p * m)) for e, v, n, r, p in out]


@dataclass(frozen=True)
class VarianceTest:
    """Is the variance of sample A (rendered) different from that of sample B (detector)?"""

    n_a: int
    n_b: int
    std_a_px: float
    std_b_px: float
    ratio: float  # std_a / std_b
    f_statistic: float
    f_p: float  # two-sided F-test (assumes normal errors)
    levene_statistic: float
    levene_p: float  # Brown–Forsythe (median-centred Levene): robust to heavy tails
    excess_std_px: float  # sqrt(max(0, var_a − var_b)): the noise A adds to B

    def to_dict(self) -> dict:
        return asdict(self)


def variance_test(a: np.ndarray, b: np.ndarray) -> VarianceTest:
    """F-test and Levene (Brown–Forsythe) test of equal variances of two error samples."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    va, vb = a.var(ddof=1), b.var(ddof=1)
    f = va / vb
    cdf = stats.f.cdf(f, len(a) - 1, len(b) - 1)
    f_p = float(min(1.0, 2 * min(cdf, 1 - cdf)))
    lev = stats.levene(a, b, center="median")
    return VarianceTest(len(a), len(b), float(np.sqrt(va)), float(np.sqrt(vb)),
                        float(np.sqrt(f)), float(f), f_p, float(lev.statistic),
                        float(lev.pvalue), float(np.sqrt(max(0.0, va - vb))))
