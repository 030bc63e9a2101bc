"""The study report of replicates with no spread (every replicate the same value) or a
single replicate, from made-up results through results.csv, summary.json and the report
with its figures; a figure that cannot be drawn is reported and the rest written, and
``designer study run`` exits 0 when every run is ok. No render, no reconstruction."""

from __future__ import annotations

import json
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from designer.study.design import plan_study
from designer.study.run import StudyRunReport
from designer.study.spec import Replicates
from designer.study.templates import write_template
from designer.study.xml import read_study

#: per variant, one value every replicate repeats; their mean over 5 replicates, summed in
#: floats, is not the value (0.87 → 0.8699999999999999, 0.007 → 0.007000000000000001)
SAME_VALUES = (0.87, 0.007, 1.71, 0.105)


def _plan(folder: Path, replicates: int):
    study = read_study(write_template("tiny", folder / "tiny.xml")[0])
    vary = ("marking-error",) if replicates > 1 else ()
    return plan_study(replace(study, replicates=Replicates(replicates, vary),
                              metrics=("check_rmse_z_m", "cloud_nmad_m", "registered")))


def _rows(plan) -> list[dict]:
    """Finished runs whose metrics and costs are equal over a variant's replicates."""
    rows = []
    for run in plan.runs:
        same = SAME_VALUES[run.variant % len(SAME_VALUES)]
        rows.append({"run": run.run_id, "variant": run.variant, "replicate": run.replicate,
                     **{f"factor:{k}": v for k, v in run.levels.items()},
                     "status": "ok", "registered": 9, "images": 9, "gsd_m": 0.1,
                     "flight_min": 0.7, "gcps": 10, "control_gcps": 5,
                     "check_rmse_z_m": same, "cloud_nmad_m": 0.1,
                     "render_s": 0.7, "reconstruct_s": 1.71, "compare_s": 0.105,
                     "reconstruct_cpu_s": 1.71, "render_cpu_s": 0.87})
    return rows


def _write(plan, out: Path) -> list[str]:
    """The results, summary and report of :func:`_rows` in ``out``; the report's problems."""
    from designer.study.results import write_results

    out.mkdir(parents=True, exist_ok=True)
    rows = _rows(plan)
    return write_results(plan, StudyRunReport(out, rows, {
        "variants": plan.n_variants, "renders": 2, "reconstructions": len(rows),
        "cache_hits": 0, "failed": 0}, 10.0))


def _enclosed(spread: dict) -> bool:
    return spread["low"] <= spread["mean"] <= spread["high"]


@pytest.mark.parametrize("replicates", [5, 1])
def test_replicates_without_spread_give_the_whole_report(tmp_path, replicates):
    plan = _plan(tmp_path, replicates)
    out = tmp_path / "out"
    assert _write(plan, out) == []
    summary = json.loads((out / "summary.json").read_text())
    for factor in summary["factors"].values():
        for level in factor["levels"]:
            for metric in ("check_rmse_z_m", "cloud_nmad_m", "flight_min", "cpu_s"):
                s = level["metrics"][metric]
                assert _enclosed(s), (metric, s)
            # one variant per level (one factor at a time): one value, its own interval
            s = level["metrics"]["check_rmse_z_m"]
            assert s["low"] == s["mean"] == s["high"] in SAME_VALUES
    # each variant's replicates all give the one value: its mean and range are that value
    for v in summary["cost"]["variants"]:
        same = SAME_VALUES[v["variant"] % len(SAME_VALUES)]
        assert v["error"] == {"mean": same, "low": same, "high": same}
        assert v["cost"] == {"mean": 0.7, "low": 0.7, "high": 0.7}
    html = (out / "report.html").read_text()
    names = ["factor-marking-sigma-px.png", "factor-sun-elevation-deg.png", "pareto.png"]
    for name in names:
        assert f"figures/{name}" in html
        assert (out / "figures" / name).stat().st_size > 5000
    assert "not drawn" not in html
    assert "## Which factors matter" in (out / "report.md").read_text()


def test_a_level_chart_with_its_mean_outside_its_interval_draws_its_bar_from_the_mean():
    """A summary.json of an earlier version (the GUI draws its charts from it) may hold
    a mean a rounding outside its interval: the bar is drawn, of no negative length."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from designer.study.report import draw_level_chart

    fig, ax = plt.subplots()
    try:
        draw_level_chart(ax, "k1", ["0", "0.1"],
                         [{"mean": 0.8699999999999999, "low": 0.87, "high": 0.87},
                          {"mean": 0.007000000000000001, "low": 0.007, "high": 0.007}],
                         [[0.87] * 5, [0.007] * 5], "check RMSE Z")
        assert len(ax.containers) == 2
    finally:
        plt.close(fig)


def test_a_figure_that_cannot_be_drawn_is_reported_and_the_rest_written(tmp_path,
                                                                         monkeypatch):
    from designer.study import cost_figure

    def broken(*_args, **_kw):
        raise ValueError("no room for the labels")

    monkeypatch.setattr(cost_figure, "write_figure", broken)
    plan = _plan(tmp_path, 2)
    out = tmp_path / "out"
    assert _write(plan, out) == [
        "report: figure figures/pareto.png (accuracy against cost) not drawn: ValueError: "
        "no room for the labels; the rest of the report is written"]
    md = (out / "report.md").read_text()
    assert "not drawn: ValueError: no room for the labels" in md
    assert "](figures/pareto.png)" not in md
    # the other figures, the tables and the ANOVA are there
    for name in ("factor-marking-sigma-px.png", "factor-sun-elevation-deg.png"):
        assert f"](figures/{name})" in md
        assert (out / "figures" / name).is_file()
    assert not (out / "figures" / "pareto.png").exists()
    assert "## Accuracy against cost" in md and "## Which factors matter" in md
    assert (out / "report.html").is_file()


def test_a_table_that_cannot_be_computed_is_reported_and_the_rest_written(tmp_path,
                                                                          monkeypatch):
    from designer.study import report

    def broken(*_args, **_kw):
        raise np.linalg.LinAlgError("Singular matrix")

    monkeypatch.setattr(report, "factor_effects", broken)
    plan = _plan(tmp_path, 2)
    out = tmp_path / "out"
    assert _write(plan, out) == [
        "report: table 'which factors matter' not computed: LinAlgError: Singular matrix; "
        "the rest of the report is written"]
    md = (out / "report.md").read_text()
    section = md.split("## Which factors matter", 1)[1]
    assert "Table 'which factors matter' not computed: LinAlgError: Singular matrix." \
        in section and "| factor | metric |" not in section
    assert (out / "figures" / "pareto.png").is_file()


def test_a_report_that_cannot_be_written_leaves_the_results_and_no_stale_report(
        tmp_path, monkeypatch):
    from designer.study import report

    def broken(*_args, **_kw):
        raise KeyError("title")

    plan = _plan(tmp_path, 1)
    out = tmp_path / "out"
    out.mkdir()
    (out / "report.html").write_text("an earlier session's report")
    monkeypatch.setattr(report, "_html", broken)
    assert _write(plan, out) == [
        "report: report.md and report.html not written: KeyError: 'title'; results.csv "
        "and summary.json are"]
    assert not (out / "report.html").exists() and not (out / "report.md").exists()
    assert (out / "results.csv").is_file() and (out / "summary.json").is_file()


def test_study_run_exits_0_when_every_run_is_ok_and_a_figure_is_not_drawn(
        tmp_path, monkeypatch, capsys):
    """``designer study run`` on a study whose runs are all finished and ok: a figure
    that raises is one line on stderr, and the command exits 0."""
    from designer.cli.main import build_parser
    from designer.study import cost_figure
    from designer.study import run as study_run

    plan = _plan(tmp_path, 1)  # the runs of the study file as written
    out = tmp_path / "out"
    for row in _rows(plan):
        (out / "runs" / row["run"]).mkdir(parents=True)
        (out / "runs" / row["run"] / "result.json").write_text(json.dumps(row))

    def planned(plan, _out, _progress):  # every run finished: nothing to plan or run
        return {r.run_id: {"image_hash": "i", "processing_hash": f"p{r.variant}"}
                for r in plan.runs}

    def broken(*_args, **_kw):
        raise ValueError("'yerr' must not contain negative values")

    monkeypatch.setattr(study_run, "_plan_runs", planned)
    monkeypatch.setattr(cost_figure, "write_figure", broken)
    args = build_parser().parse_args(["study", "run", str(tmp_path / "tiny.xml"), "-o",
                                      str(out), "--resume", "--progress", "none"])
    assert args.func(args) == 0
    err = capsys.readouterr().err.strip().splitlines()
    assert err == ["designer: report: figure figures/pareto.png (accuracy against cost) "
                   "not drawn: ValueError: 'yerr' must not contain negative values; the rest "
                   "of the report is written"]
    assert (out / "report.html").is_file() and (out / "summary.json").is_file()
