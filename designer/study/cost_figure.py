"""The report's accuracy-against-cost figure and its section of report.md.

Every variant is a point at its replicates' mean cost and error, with bars from the
smallest to the largest replicate (cost bars only where the cost varies), labelled by
its factor levels (:mod:`designer.study.labels`); each run is a grey dot; the front of
:mod:`designer.study.front` is drawn in red, its rule written under the axes. Up to
:data:`MAX_DIRECT_LABELS` variants carry their labels beside them; more are numbered,
with a key beside the axes. Variants of equal cost (a count no factor changes) are drawn
side by side.
"""

from __future__ import annotations

import itertools
import textwrap
from pathlib import Path

from designer.atomic import atomic_path
from designer.study.cost import COSTS, Cost
from designer.study.front import VariantPoint, front, front_rule, variant_points
from designer.study.labels import short_labels, variant_labels
from designer.study.levels import bar_lengths

#: more variants than this are numbered in the figure, with a key beside it
MAX_DIRECT_LABELS = 10
FRONT_COLOUR = "C3"
LABEL_SIZE = 8.5


def cost_of(plan) -> Cost:
    return COSTS[plan.study.cost]


def analyse(plan, rows: list[dict], metric: str) -> dict:
    """The variants' points, the front and its rule for the study's cost and ``metric``,
    and the figure's labels (``figure_labels``; with ``key``: the factors they name)."""
    cost = cost_of(plan)
    factors = [f.name for f in plan.study.factors]
    labels = variant_labels(rows, factors, plan.study.design)
    points = variant_points(rows, cost.column, metric, labels)
    drawn, rule = front_rule(points, cost.planned)
    runs = [(int(r["variant"]), float(r[cost.column]), float(r[metric])) for r in rows
            if r.get("status") == "ok" and r.get(cost.column) not in (None, "")
            and r.get(metric) not in (None, "")]
    figure_labels, key = labels, ""
    if plan.study.design == "full-factorial":
        short, names = short_labels(rows, factors)
        if " · " in names:  # several factors: their levels alone, named once
            figure_labels, key = short, f"labels: {names}"
    return {"cost": cost, "metric": metric, "points": points, "runs": runs,
            "front": front(points) if drawn else [], "drawn": drawn, "rule": rule,
            "figure_labels": figure_labels, "key": key}


def write_figure(analysis: dict, metric_label: str, path: Path) -> None:
    """The figure of :func:`analyse`'s ``analysis`` as a PNG at ``path``."""
    import matplotlib.pyplot as plt

    numbered = len(analysis["points"]) > MAX_DIRECT_LABELS
    fig, ax = plt.subplots(figsize=(11.5 if numbered else 8.5, 5.8))
    try:
        _draw(fig, ax, analysis, metric_label, numbered)
        with atomic_path(path) as tmp:
            fig.savefig(tmp, dpi=110, bbox_inches="tight", format="png")
    finally:
        plt.close(fig)


def _draw(fig, ax, analysis: dict, metric_label: str, numbered: bool) -> None:
    """The figure of :func:`write_figure` on ``fig`` and ``ax``."""
    from matplotlib.lines import Line2D

    cost, points, on_front = analysis["cost"], analysis["points"], analysis["front"]
    x_of = _dodged(points, ax)
    for p in points:
        colour = FRONT_COLOUR if p in on_front else "C0"
        x = x_of[p.variant]
        left, right = bar_lengths(p.cost.mean, p.cost.low, p.cost.high)
        below, above = bar_lengths(p.error.mean, p.error.low, p.error.high)
        xerr = [[left], [right]] if p.cost.varies else None
        yerr = [[below], [above]]
        ax.errorbar(x, p.error.mean, xerr=xerr, yerr=yerr, fmt="o", ms=6, color=colour,
                    ecolor=colour, elinewidth=1.2, capsize=4, zorder=3)
        runs = [(c, e) for v, c, e in analysis["runs"] if v == p.variant]
        # a cost that does not vary: the runs at the variant's (side-by-side) place
        ax.plot([c if p.cost.varies else x for c, _ in runs], [e for _, e in runs], ".",
                color="0.6", ms=4, zorder=2)
    if _apart(on_front):
        # a line from cost to cost, when the front's costs differ beyond their spread
        ax.plot([x_of[p.variant] for p in on_front], [p.error.mean for p in on_front], "--",
                color=FRONT_COLOUR, lw=1, zorder=1)
    handles = [Line2D([], [], marker="o", ls="", color="C0",
                      label="variant: mean, bars: replicate range"),
               Line2D([], [], marker=".", ls="", color="0.6", label="each run")]
    if on_front:
        handles.append(Line2D([], [], marker="o", ls="--", color=FRONT_COLOUR, label="front"))
    legend = ax.legend(handles=handles, fontsize=8, loc="best", framealpha=0.9)
    texts = analysis["figure_labels"]
    if numbered:
        names = {p.variant: str(k + 1) for k, p in enumerate(points)}
        _key(fig, ax, points, on_front, names, texts, analysis["key"])
        _place_labels(fig, ax, points, on_front, names, x_of, legend)
    else:
        _place_labels(fig, ax, points, on_front, texts, x_of, legend)
    ax.set_xlabel(cost.label, fontsize=10)
    ax.set_ylabel(metric_label, fontsize=10)
    ax.set_title(f"accuracy against {cost.label}", fontsize=11)
    ax.grid(alpha=0.3)
    notes = [analysis["rule"]]
    if cost.name == "wall-seconds":
        notes.insert(0, "wall seconds count the machine's other jobs and the study's order: "
                        "a run that reuses another's cached features is faster; cpu-seconds "
                        "counts the work")
    if analysis["key"] and not numbered:
        notes.insert(0, analysis["key"])
    if points and not any(p.cost.varies for p in points) \
            and len({p.cost.mean for p in points}) == 1:
        notes.insert(0, f"every variant costs the same ({points[0].cost.mean:.4g}); they "
                        "are drawn side by side")
    fig.text(0.01, 0.005, "\n".join(textwrap.fill(n, 130 if numbered else 105)
                                    for n in notes),
             fontsize=8, ha="left", va="bottom", color="0.25")
    fig.subplots_adjust(bottom=0.1 + 0.035 * len(notes))


def _apart(on_front: list[VariantPoint]) -> bool:
    """Whether the front's costs, in order, each lie beyond the spread of the one before."""
    costs = sorted((p.cost for p in on_front), key=lambda c: c.mean)
    return len(costs) > 1 and all(b.low > a.high for a, b in itertools.pairwise(costs))


def _dodged(points: list[VariantPoint], ax) -> dict[int, float]:
    """Each variant's x: its mean cost, variants of one equal cost spread side by side;
    and the axis limits, with room for labels. When every variant costs the same, the
    axis has that one tick."""
    if not points:
        return {}
    groups: dict[float, list[VariantPoint]] = {}
    for p in points:
        groups.setdefault(p.cost.mean, []).append(p)
    xs = [v for p in points for v in (p.cost.low, p.cost.high)]
    x0, x1 = min(xs), max(xs)
    biggest = max(len(g) for g in groups.values())
    if x1 > x0:
        # costs within a few per cent of each other look as close as they are
        step = (x1 - x0) / 60
        span = max(x1 - x0, 0.2 * max(abs(x0), abs(x1)))
        middle = (x0 + x1) / 2
        x0, x1 = min(x0, middle - span / 2), max(x1, middle + span / 2)
    else:
        span = max(abs(x0) * 0.1, 0.5)
        step = min(0.15 * span, 0.6 * span / max(biggest - 1, 1))
        ax.set_xticks([x0])
    out = {}
    for cost, group in groups.items():
        for k, p in enumerate(group):  # in variant order: no made-up trend
            out[p.variant] = cost + (k - (len(group) - 1) / 2) * step
    lo, hi = min(min(out.values()), x0), max(max(out.values()), x1)
    ax.set_xlim(lo - 0.12 * span, hi + 0.4 * span)
    ys = [v for p in points for v in (p.error.low, p.error.high)]
    y0, y1 = min(ys), max(ys)
    dy = (y1 - y0) or max(abs(y0) * 0.2, 1e-3)
    ax.set_ylim(y0 - 0.1 * dy, y1 + 0.2 * dy)
    return out


#: where a label may sit around its point (offset in points) and its alignment
_SPOTS = [((7, 4), "left", "bottom"), ((7, -4), "left", "top"), ((-7, 4), "right", "bottom"),
          ((-7, -4), "right", "top"), ((9, 0), "left", "center"),
          ((-9, 0), "right", "center"), ((0, 9), "center", "bottom"),
          ((0, -9), "center", "top"), ((16, 12), "left", "bottom"),
          ((16, -12), "left", "top"), ((-16, 12), "right", "bottom"),
          ((-16, -12), "right", "top"), ((24, 0), "left", "center"),
          ((-24, 0), "right", "center")]


def _place_labels(fig, ax, points, on_front, texts: dict[int, str],
                  x_of: dict[int, float], legend) -> None:
    """Each point's label at the first spot around it that overlaps no label placed
    before and no point and stays inside the axes (else the spot overlapping least);
    the front's labels first."""
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    inside = ax.get_window_extent(renderer)
    obstacles = []
    for p in points:
        x, y = ax.transData.transform((x_of[p.variant], p.error.mean))
        obstacles.append((x - 5, y - 5, x + 5, y + 5))
    box = legend.get_window_extent(renderer)
    obstacles.append((box.x0, box.y0, box.x1, box.y1))
    for p in sorted(points, key=lambda q: q not in on_front):
        best = None
        for offset, ha, va in _SPOTS:
            text = ax.annotate(texts.get(p.variant, f"v{p.variant}"),
                               (x_of[p.variant], p.error.mean), textcoords="offset points",
                               xytext=offset, ha=ha, va=va, fontsize=LABEL_SIZE,
                               color=FRONT_COLOUR if p in on_front else "0.1", zorder=4,
                               bbox={"boxstyle": "round,pad=0.12", "fc": "white",
                                     "ec": "none", "alpha": 0.8})
            box = text.get_window_extent(renderer)
            b = (box.x0, box.y0, box.x1, box.y1)
            score = sum(_overlap(b, o) for o in obstacles)
            if not (b[0] >= inside.x0 and b[2] <= inside.x1 and b[1] >= inside.y0
                    and b[3] <= inside.y1):
                score += (b[2] - b[0]) * (b[3] - b[1])
            if best is None or score < best[0]:
                if best is not None:
                    best[1].remove()
                best = (score, text, b)
            else:
                text.remove()
            if score == 0:
                break
        obstacles.append(best[2])


def _key(fig, ax, points, on_front, names, texts, key: str) -> None:
    """The numbered variants' labels in a column beside the axes."""
    lines = [key] if key else []
    lines += [f"{names[p.variant]:>3}  {texts.get(p.variant, f'v{p.variant}')}"
              + ("  (front)" if p in on_front else "") for p in points]
    fig.subplots_adjust(right=0.62)
    ax.text(1.02, 1.0, "\n".join(lines), transform=ax.transAxes, fontsize=8, va="top",
            ha="left", family="monospace")


def _overlap(a, b) -> float:
    w = min(a[2], b[2]) - max(a[0], b[0])
    h = min(a[3], b[3]) - max(a[1], b[1])
    return w * h if w > 0 and h > 0 else 0.0


def markdown(analysis: dict, metric_label: str, rows: list[dict],
             figure_note: str | None = None) -> list[str]:
    """The report's section: the figure (or ``figure_note`` in its place: why it is not
    drawn), the rule, and a table of every variant in the surveyor's units with its place
    on the front."""
    cost, on_front = analysis["cost"], analysis["front"]
    by_variant: dict[int, list[dict]] = {}
    for r in rows:
        if r.get("status") == "ok":
            by_variant.setdefault(int(r["variant"]), []).append(r)
    rule = analysis["rule"]
    md = ["## Accuracy against cost", "",
          f"Cost: **{cost.label}** (`<cost>{cost.name}</cost>`, column `{cost.column}`). "
          f"{rule[0].upper()}{rule[1:]}.", "",
          figure_note or "![accuracy against cost](figures/pareto.png)", "",
          f"| variant | runs | {metric_label}: mean [range] | flight min | images | GCPs "
          "(control) | processing CPU s | wall s | front |", "|---" * 9 + "|"]
    for p in sorted(analysis["points"], key=lambda q: (q.cost.mean, q.error.mean)):
        good = by_variant.get(p.variant, [])
        error = f"{p.error.mean:.4g}" + (f" [{p.error.low:.4g}, {p.error.high:.4g}]"
                                         if p.runs > 1 else "")
        md.append(f"| {p.label} | {p.runs} | {error} | {_mean(good, 'flight_min', '.3g')} | "
                  f"{_mean(good, 'images', '.0f')} | {_mean(good, 'gcps', '.0f')} "
                  f"({_mean(good, 'control_gcps', '.0f')}) | "
                  f"{_mean(good, 'reconstruct_cpu_s', '.3g')} | "
                  f"{_mean(good, 'total_s', '.3g')} | "
                  f"{'yes' if p in on_front else ''} |")
    md.append("")
    if on_front:
        md += ["Front, by cost:", ""] + [
            f"- {p.label} — {cost.label}: {p.cost.mean:.4g}; {metric_label}: "
            f"{p.error.mean:.4g}" for p in on_front] + [""]
    return md


def _mean(rows: list[dict], column: str, fmt: str) -> str:
    xs = []
    for r in rows:
        try:
            xs.append(float(r.get(column)))
        except (TypeError, ValueError):
            pass
    return format(sum(xs) / len(xs), fmt) if xs else "–"
