"""Helpers of the Study panel tests: a tiny base project, adding a factor, waiting for the check."""

from __future__ import annotations

from PySide6.QtCore import Qt

from designer.study.templates import write_template
from tests.gui.helpers import wait_idle


def _tiny_base(qtbot, w, folder):
    """The tiny study's base project (160 × 120 px images) open in the window."""
    write_template("tiny", folder / "tiny-template.xml")
    base = folder / "tiny-template-base.xml"
    assert w.open_project(base)
    wait_idle(qtbot, w)
    panel = w.panels["Study"]
    w.docks["Study"].raise_()
    return panel, base


def _add(qtbot, panel, name: str, levels: str):
    """Choose the factor in the list, press Add, type its levels."""
    choice = panel.factor_choice
    choice.setFocus()
    qtbot.keyClick(choice, Qt.Key.Key_Home)
    while choice.currentData() != name:
        index = choice.currentIndex()
        qtbot.keyClick(choice, Qt.Key.Key_Down)
        assert choice.currentIndex() != index, f"no factor {name} in the list"
    qtbot.mouseClick(panel.add_button, Qt.MouseButton.LeftButton)
    row = panel.rows[-1]
    assert row.name == name
    qtbot.keyClicks(row.levels, levels)
    return row


def _checked(qtbot, w, panel) -> str:
    """Wait for the check of the current study; the plan line (or the errors)."""
    qtbot.waitUntil(lambda: not panel._timer.isActive(), timeout=5000)
    wait_idle(qtbot, w)
    return panel.plan_label.text()


def finished_study(study_path, out, metrics=("check_rmse_z_m", "check_rmse_xy_m",
                                             "cloud_nmad_m", "registered"), seed=5):
    """A finished study folder of the study file ``study_path`` as ``designer study run``
    leaves it (study.json, each run's result.json, results.csv, summary.json, the report
    and its figures), from made-up results (seeded): no render, no reconstruction."""
    import json
    from dataclasses import replace

    import numpy as np

    from designer.study.design import plan_study
    from designer.study.results import write_results
    from designer.study.run import StudyRunReport
    from designer.study.xml import read_study

    rng = np.random.default_rng(seed)
    plan = plan_study(replace(read_study(study_path), metrics=tuple(metrics)))
    out.mkdir(parents=True)
    rows = []
    for run in plan.runs:
        row = {"run": run.run_id, "variant": run.variant, "replicate": run.replicate,
               **{f"factor:{k}": v for k, v in run.levels.items()},
               "status": "ok", "registered": 18, "images": 18, "gsd_m": 0.01,
               "flight_min": 2.0 + 0.1 * run.variant, "gcps": 4, "control_gcps": 4,
               "check_rmse_z_m": float(rng.uniform(0.01, 0.05)),
               "check_rmse_xy_m": float(rng.uniform(0.005, 0.02)),
               "cloud_nmad_m": float(rng.uniform(0.01, 0.03)),
               "render_s": 2.0, "reconstruct_s": 5.0, "compare_s": 1.0}
        (out / "runs" / run.run_id).mkdir(parents=True)
        (out / "runs" / run.run_id / "result.json").write_text(json.dumps(row))
        rows.append(row)
    (out / "study.json").write_text(json.dumps({
        "name": plan.study.name, "design": plan.study.design,
        "runs": [r.run_id for r in plan.runs]}))
    write_results(plan, StudyRunReport(out, rows, {"variants": plan.n_variants, "renders": 2,
                                                    "reconstructions": len(rows),
                                                    "cache_hits": 0, "failed": 0}, 10.0))
    return plan
