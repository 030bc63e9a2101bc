"""Accuracy statistics of signed distances (or any error sample), as surveyors report them.

All values in metres. ``d`` is a 1-D array of signed errors; NaN entries (points beyond
a search limit) are counted as excluded and left out of every statistic.

* classical: mean, standard deviation (n − 1), RMSE = sqrt(mean(d²)), min, max;
* robust (Höhle & Höhle 2009): median, NMAD = 1.4826 · median(|d − median(d)|), and the
  68.3 % and 95 % quantiles of |d|;
* ASPRS (2014) non-vegetated vertical accuracy at 95 % confidence = 1.96 · RMSE;
* the share of |d| within each tolerance, and a histogram of d.
"""

from __future__ import annotations

import numpy as np

from designer.errors import DesignerError

#: default tolerances (m) whose share of |d| is reported
DEFAULT_TOLERANCES_M = (0.01, 0.02, 0.05, 0.10, 0.20)
NMAD_FACTOR = 1.4826
HISTOGRAM_BINS = 60


def distance_statistics(
    d,
    tolerances=DEFAULT_TOLERANCES_M,
    *,
    bins: int = HISTOGRAM_BINS,
    histogram_range: tuple[float, float] | None = None,
) -> dict:
    """Statistics of the signed errors ``d`` (N,), as a JSON-ready dict (metres).

    The histogram spans ``histogram_range`` or, by default, ±(99.5 % quantile of |d|),
    so a few outliers do not squash it; values outside are counted in ``below``/``above``.
    """
    d = np.asarray(d, dtype=np.float64).ravel()
    finite = d[np.isfinite(d)]
    n = int(finite.size)
    out: dict = {"n": n, "n_excluded": int(d.size - n)}
    if n == 0:
        raise DesignerError("no finite distances to summarise (every point was beyond the "
                            "maximum distance?)")
    absd = np.abs(finite)
    median = float(np.median(finite))
    q68, q95, q995 = (float(q) for q in np.quantile(absd, [0.683, 0.95, 0.995]))
    rmse = float(np.sqrt(np.mean(finite * finite)))
    out.update({
        "mean": float(np.mean(finite)),
        "std": float(np.std(finite, ddof=1)) if n > 1 else 0.0,
        "rmse": rmse,
        "mean_abs": float(np.mean(absd)),
        "min": float(finite.min()),
        "max": float(finite.max()),
        "median": median,
        "nmad": NMAD_FACTOR * float(np.median(np.abs(finite - median))),
        "abs_q68_3": q68,
        "abs_q95": q95,
        "asprs_vertical_95": 1.96 * rmse,
        "share_positive": float(np.mean(finite > 0)),
    })
    out["within_tolerance"] = [
        {"tolerance": float(t), "share": float(np.mean(absd <= t))} for t in tolerances]
    if histogram_range is None:
        top = q995 if q995 > 0 else max(float(absd.max()), 1e-3)
        histogram_range = (-top, top)
    lo, hi = histogram_range
    counts, edges = np.histogram(finite, bins=bins, range=(lo, hi))
    out["histogram"] = {
        "edges": edges.tolist(), "counts": counts.tolist(),
        "below": int(np.count_nonzero(finite < lo)), "above": int(np.count_nonzero(finite > hi)),
    }
    return out


def format_statistics(stats: dict) -> list[tuple[str, str]]:
    """(label, value) rows of the headline figures (metres to 0.1 mm)."""
    def m(key: str) -> str:
        return f"{stats[key]:.4f} m"

    rows = [("points", f"{stats['n']:,}")]
    if stats.get("n_excluded"):
        rows.append(("beyond max distance (left out)", f"{stats['n_excluded']:,}"))
    rows += [("mean (bias)", m("mean")), ("std", m("std")), ("RMSE", m("rmse")),
             ("median", m("median")), ("NMAD", m("nmad")),
             ("68.3 % quantile of abs. error", m("abs_q68_3")),
             ("95 % quantile of abs. error", m("abs_q95")),
             ("ASPRS 95 % (1.96 RMSE)", m("asprs_vertical_95")),
             ("min / max", f"{stats['min']:.4f} / {stats['max']:.4f} m")]
    for t in stats["within_tolerance"]:
        rows.append((f"share within ±{t['tolerance']:g} m", f"{100 * t['share']:.1f} %"))
    return rows
