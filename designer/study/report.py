"""The study report: ``report.md`` and ``report.html`` with figures in ``figures/``.

For each factor: the study's metrics against the factor's levels (mean and 95 %
interval over replicates) and what each level cost in the study's cost unit; across all
runs: accuracy against that cost, each variant labelled by its levels, with the front of
the variants that differ beyond the replicate spread (:mod:`designer.study.cost_figure`);
error maps (cloud − true surface) of the extreme levels side by side; which factors
matter: a least-squares model of each metric on all factors with its ANOVA table
(:mod:`designer.study.stats`).

Each figure is drawn on its own: one that cannot be drawn leaves a line in its place
(which figure, why) and in the problems :func:`write_report` returns, and the rest of
the report is written; so does the ANOVA table.
"""

from __future__ import annotations

import html
import textwrap
from pathlib import Path

from designer.atomic import atomic_path, write_text_atomic
from designer.study import cost_figure
from designer.study.cost import COSTS, accuracy_metric
from designer.study.levels import bar_lengths, factor_levels, interval95, level_rows
from designer.study.stats import factor_effects

_LABELS = {
    "check_rmse_z_m": "check-point RMSE Z (m)", "check_rmse_xy_m": "check-point RMSE XY (m)",
    "check_rmse_xyz_m": "check-point RMSE 3D (m)", "check_rmse_x_m": "check-point RMSE X (m)",
    "check_rmse_y_m": "check-point RMSE Y (m)", "check_rmse_z_gsd": "check RMSE Z (GSD)",
    "cloud_nmad_m": "cloud − surface NMAD (m)", "cloud_median_m": "cloud − surface median (m)",
    "cloud_rmse_m": "cloud − surface RMSE (m)",
    "dtm_cloud_median_m": "cloud − bare earth median (m)",
    "dtm_cloud_nmad_m": "cloud − bare earth NMAD (m)",
    "dtm_cloud_rmse_m": "cloud − bare earth RMSE (m)", "registered": "registered images",
    "control_rmse_xyz_m": "control-point RMSE 3D (m)", "focal_error_px": "focal error (px)",
    "k1_error": "k1 error", "dome_amplitude_m": "DoD dome amplitude (m)",
    "dome_amplitude_gsd": "DoD dome amplitude (GSD)",
    "sparse_dome_gsd": "tie-point dome amplitude (GSD)",
    "k1_error_beyond_focal": "k1 error beyond the focal trade",
    "total_s": "seconds per run (on its own)", "render_s": "render seconds",
}
_LABELS.update({c.column: c.label for c in COSTS.values()})


def label(metric: str) -> str:
    return _LABELS.get(metric, metric)


def _save(fig, path: Path) -> None:
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=110, bbox_inches="tight", format="png")


def draw_level_chart(ax, factor: str, levels: list[str], stats: list[dict],
                     points: list[list[float]], title: str, is_cost: bool = False) -> None:
    """One metric against a factor's levels on ``ax``: the mean and 95 % interval over
    replicates at each level (``stats``: :func:`interval95`), each run's value in grey
    (``points``, per level); the cost in red, its axis not narrower than 20 % of its
    values (costs within a few per cent of each other look that close)."""
    for k, s in enumerate(stats):
        if s.get("mean") is None:
            continue
        below, above = bar_lengths(s["mean"], s.get("low"), s.get("high"))
        ax.errorbar(k, s["mean"], yerr=[[below], [above]],
                    fmt="o", color="C3" if is_cost else "C0", capsize=4)
        ax.plot([k] * len(points[k]), points[k], ".", color="0.6", ms=4)
    ax.set_xticks(list(range(len(levels))), levels,
                  rotation=30 if max(map(len, levels), default=0) > 5 else 0)
    ax.set_xlabel(factor)
    ax.set_title("\n".join(textwrap.wrap(title, 34)), fontsize=9)
    ax.grid(alpha=0.3)
    if is_cost:
        lo, hi = ax.get_ylim()
        least = 0.2 * max(abs(lo), abs(hi))
        if hi - lo < least:
            ax.set_ylim((lo + hi) / 2 - least / 2, (lo + hi) / 2 + least / 2)


def _factor_figure(plan, rows, factor: str, metrics, path: Path) -> None:
    import matplotlib.pyplot as plt

    levels = factor_levels(plan, rows, factor)
    cost = COSTS[plan.study.cost].column
    panels = list(metrics) + [cost]
    fig, axes = plt.subplots(1, len(panels), figsize=(3.6 * len(panels), 3.3), squeeze=False)
    try:
        for ax, metric in zip(axes[0], panels, strict=True):
            ok = [[r for r in level_rows(plan, rows, factor, lv) if r["status"] == "ok"]
                  for lv in levels]
            draw_level_chart(ax, factor, levels, [interval95([r.get(metric) for r in at])
                                                  for at in ok],
                             [[r[metric] for r in at if r.get(metric) is not None]
                              for at in ok],
                             label(metric), is_cost=metric == cost)
        fig.suptitle(f"{factor}: mean and 95 % interval over replicates (grey: each run)",
                     fontsize=10, y=1.04)
        _save(fig, path)
    finally:
        plt.close(fig)


def _maps_figure(plan, rows, factor: str, path: Path) -> bool:
    """The error maps (cloud − true surface, the compare's GeoTIFF) of the factor's lowest
    and highest levels side by side, on one colour scale and one extent."""
    import matplotlib.pyplot as plt
    import numpy as np
    import rasterio

    levels = factor_levels(plan, rows, factor)
    chosen = []
    for level in (levels[0], levels[-1]):
        runs = [r for r in level_rows(plan, rows, factor, level)
                if r["status"] == "ok" and r.get("error_map")
                and Path(r["error_map"]).with_suffix(".tif").is_file()]
        if runs:
            chosen.append((level, runs[0]))
    if len(chosen) < 2 or chosen[0][0] == chosen[1][0]:
        return False
    grids = []
    for _level, r in chosen:
        with rasterio.open(Path(r["error_map"]).with_suffix(".tif")) as src:
            values = src.read(1, masked=True).astype(float).filled(np.nan)
            grids.append((values, src.bounds, src.res[0]))
    finite = np.concatenate([np.abs(g[np.isfinite(g)]) for g, _b, _r in grids])
    vmax = float(np.percentile(finite, 98)) if finite.size else 1.0
    x0 = min(b.left for _g, b, _r in grids)
    x1 = max(b.right for _g, b, _r in grids)
    y0 = min(b.bottom for _g, b, _r in grids)
    y1 = max(b.top for _g, b, _r in grids)
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.8), constrained_layout=True)
    try:
        _draw_maps(fig, axes, factor, chosen, grids, vmax, (x0, x1, y0, y1))
        _save(fig, path)
    finally:
        plt.close(fig)
    return True


def _draw_maps(fig, axes, factor: str, chosen, grids, vmax: float, extent) -> None:
    """The two levels' maps on ``axes``, on one colour scale (±``vmax``) and one extent
    (x0, x1, y0, y1), with their colour bar."""
    x0, x1, y0, y1 = extent
    for ax, (level, r), (values, b, cell) in zip(axes, chosen, grids, strict=True):
        image = ax.imshow(values, extent=(b.left - x0, b.right - x0, b.bottom - y0, b.top - y0),
                          cmap="RdBu_r", vmin=-vmax, vmax=vmax, interpolation="nearest")
        ax.set_xlim(0, x1 - x0)
        ax.set_ylim(0, y1 - y0)
        ax.set_facecolor("0.85")
        ax.set_title(f"{factor} = {level} ({r['run']}, {cell:g} m cells)", fontsize=9)
        ax.set_xlabel(f"easting − {x0:.0f} (m)", fontsize=8)
        ax.set_ylabel(f"northing − {y0:.0f} (m)", fontsize=8)
        ax.set_aspect("equal")
    fig.colorbar(image, ax=axes, shrink=0.85,
                 label="signed distance (m): + above the true surface")
    fig.suptitle("cloud − true surface, lowest and highest level (one colour scale; "
                 "grey: no points)", fontsize=10)


def _fmt(v) -> str:
    if v is None:
        return "–"
    if isinstance(v, float):
        return f"{v:.4g}"
    return str(v)


def one_line(error: BaseException, width: int = 200) -> str:
    """An exception as one line: its type and its message's words, at most ``width``
    characters."""
    text = f"{type(error).__name__}: {' '.join(str(error).split())}".rstrip(": ")
    return text if len(text) <= width else text[:width - 1] + "…"


def _figure(draw, path: Path, what: str, problems: list[str]) -> bool:
    """Draw one figure of the report (``draw(path)``); whether it was drawn. A figure that
    cannot be drawn adds one line to ``problems`` (which figure, why) and leaves no file
    (nor one of an earlier report): the rest of the report does not depend on it."""
    try:
        return draw(path) is not False
    except Exception as error:  # any failure of one figure: the others stand
        path.unlink(missing_ok=True)
        problems.append(f"figure figures/{path.name} ({what}) not drawn: {one_line(error)}")
        return False


def write_report(plan, rows: list[dict], summary: dict, out: Path) -> dict:
    """report.md and report.html, figures in ``out/figures``; their paths and
    ``problems``: one line per figure or table that could not be made (each also written
    in its place in the report)."""
    import matplotlib

    matplotlib.use("Agg")
    figures = out / "figures"
    figures.mkdir(exist_ok=True)
    problems: list[str] = []
    metrics = list(plan.study.metrics)
    accuracy = accuracy_metric(metrics)
    cost = COSTS[plan.study.cost]
    md = [f"# Study {plan.study.name}", ""]
    if plan.study.description:
        md += [plan.study.description, ""]
    md += [f"Design {plan.study.design}, {summary['variants']} variants × "
           f"{plan.study.replicates.count} replicates = {summary['runs']} runs "
           f"(re-drawn per replicate: {', '.join(plan.study.replicates.vary) or 'nothing'}). "
           f"Renders: {summary['renders']} (one per distinct image set); reconstructions: "
           f"{summary['reconstructions']}; cache hits: {summary['cache_hits']}; failed runs: "
           f"{summary['failed']}; wall time {summary.get('wall_s', 0):.0f} s.", ""]
    for f in plan.study.factors:
        name = f"factor-{f.name}.png"
        drawn = _figure(lambda path, f=f: _factor_figure(plan, rows, f.name, metrics, path),
                        figures / name, f"metrics against {f.name}", problems)
        md += [f"## Factor {f.name} ({summary['factors'][f.name]['stage']})", ""]
        if f.description:
            md += [f.description, ""]
        md += [f"![{f.name}](figures/{name})" if drawn else _capital(problems[-1]), "",
               "| level | runs | failed | " + " | ".join(label(m) for m in metrics)
               + f" | {cost.label} |",
               "|---" * (len(metrics) + 4) + "|"]
        for lv in summary["factors"][f.name]["levels"]:
            cells = []
            for m in metrics + [cost.column]:
                s = lv["metrics"][m]
                cells.append("–" if s["mean"] is None else
                             f"{s['mean']:.4g} [{s['low']:.4g}, {s['high']:.4g}]")
            md.append(f"| {lv['level']} | {lv['runs']} | {lv['failed']} | "
                      + " | ".join(cells) + " |")
        md.append("")
        maps = f"maps-{f.name}.png"
        before = len(problems)
        if _figure(lambda path, f=f: _maps_figure(plan, rows, f.name, path), figures / maps,
                   f"error maps of {f.name}", problems):
            md += [f"![error maps of {f.name}](figures/{maps})", ""]
        elif len(problems) > before:
            md += [_capital(problems[-1]), ""]
    analysis = cost_figure.analyse(plan, rows, accuracy)
    drawn = _figure(lambda path: cost_figure.write_figure(analysis, label(accuracy), path),
                    figures / "pareto.png", "accuracy against cost", problems)
    md += cost_figure.markdown(analysis, label(accuracy), rows,
                               figure_note=None if drawn else _capital(problems[-1]))
    md += _effects_section(plan, rows, metrics, problems)
    failed = [r for r in rows if r["status"] != "ok"]
    if failed:
        md += ["", "## Failed runs", ""] + [f"- {r['run']}: {r['status']}" for r in failed]
    md += ["", "All numbers: results.csv (one row per run) and summary.json.", ""]
    text = "\n".join(md)
    write_text_atomic(out / "report.md", text)
    write_text_atomic(out / "report.html", _html(text, plan.study.name))
    return {"markdown": out / "report.md", "html": out / "report.html", "problems": problems}


def _capital(line: str) -> str:
    """A problem line as a sentence of the report."""
    return line[:1].upper() + line[1:].rstrip(".") + "."


def _effects_section(plan, rows: list[dict], metrics: list[str],
                     problems: list[str]) -> list[str]:
    """The section "Which factors matter": the ANOVA table of :func:`factor_effects`, or
    one line saying why it could not be computed (also added to ``problems``)."""
    md = ["## Which factors matter", "",
           "Least squares of each metric on all factors (categorical; statsmodels), type II "
           "ANOVA: F, p and partial η² per factor; for a numeric factor, the metric's slope "
           "per unit of it with its 95 % interval.", "",
           "| factor | metric | levels | runs | df | F | p | partial η² | slope per unit "
           "[95 %] |", "|---" * 9 + "|"]
    try:
        effects = factor_effects([f.name for f in plan.study.factors], rows, metrics)
    except Exception as error:  # a model the data cannot fit: the rest of the report stands
        problems.append(f"table 'which factors matter' not computed: {one_line(error)}")
        return md[:-2] + [_capital(problems[-1])]
    for a in effects:
        slope = "–" if a["slope"] is None else \
            f"{a['slope']:.4g} [{a['slope_low']:.4g}, {a['slope_high']:.4g}]"
        md.append(f"| {a['factor']} | {a['metric']} | {a['levels']} | {a['runs']} | "
                  f"{_fmt(a['df'])} | {_fmt(a['F'])} | {_fmt(a['p'])} | {_fmt(a['eta2'])} | "
                  f"{slope} |")
    return md


def _html(markdown: str, title: str) -> str:
    """A small Markdown subset (headings, images, tables, lists, paragraphs) as HTML."""
    body, table = [], []

    def flush_table():
        if table:
            head, *rest = table
            body.append("<table><tr>" + "".join(f"<th>{c}</th>" for c in head) + "</tr>"
                        + "".join("<tr>" + "".join(f"<td>{c}</td>" for c in r) + "</tr>"
                                  for r in rest) + "</table>")
            table.clear()

    for line in markdown.splitlines():
        if line.startswith("|"):
            cells = [html.escape(c.strip()) for c in line.strip("|").split("|")]
            if not all(set(c) <= {"-"} for c in cells):
                table.append(cells)
            continue
        flush_table()
        if line.startswith("#"):
            level = len(line) - len(line.lstrip("#"))
            body.append(f"<h{level}>{html.escape(line.lstrip('# '))}</h{level}>")
        elif line.startswith("!["):
            alt, src = line[2:].split("](", 1)
            body.append(f'<p><img src="{html.escape(src.rstrip(")"))}" '
                        f'alt="{html.escape(alt)}" style="max-width:100%"></p>')
        elif line.startswith("- "):
            body.append(f"<li>{html.escape(line[2:])}</li>")
        elif line.strip():
            body.append(f"<p>{html.escape(line)}</p>")
    flush_table()
    style = ("body{font-family:sans-serif;max-width:1100px;margin:auto}"
             "table{border-collapse:collapse}td,th{border:1px solid #bbb;padding:3px 6px;"
             "font-size:90%}")
    return (f"<!DOCTYPE html><html><head><meta charset='utf-8'><title>"
            f"{html.escape(title)}</title><style>{style}</style></head><body>"
            + "\n".join(body) + "</body></html>\n")
