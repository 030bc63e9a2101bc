"""The Study panel's time estimate against a study run for real: a tiny study of one
processing factor under one-at-a-time (one render, three reconstructions of which two
reuse the first one's SfM model), run with ``designer study run``; each stage the
estimate names is compared with the CPU and wall seconds results.csv measured, and the
whole with the study's wall time."""

from __future__ import annotations

import csv
import subprocess
import sys
import time
from pathlib import Path

import pytest

from designer.gui.state import derived
from designer.gui.state.study_data import plan_cost
from designer.study.design import plan_study
from designer.study.templates import write_template
from designer.study.xml import read_study

ROOT = Path(__file__).resolve().parents[2]

pytestmark = [pytest.mark.blender, pytest.mark.slow]

STUDY = """<?xml version="1.0" encoding="UTF-8"?>
<study xmlns="urn:designer:project:1" schema-version="1.0" name="control">
  <base-project file="tiny-template-base.xml"/>
  <factor name="control-count">
    <values>3 5</values>
  </factor>
  <design>one-at-a-time</design>
  <replicates count="1"/>
  <metrics>check_rmse_z_m registered</metrics>
</study>
"""


def test_the_estimate_of_a_tiny_study_follows_its_measured_stages_and_wall_time(tmp_path):
    write_template("tiny", tmp_path / "tiny-template.xml")
    study_path = tmp_path / "control.xml"
    study_path.write_text(STUDY)
    plan = plan_study(read_study(study_path))
    heightfield = derived.compute_terrain(plan.base, plan.base_dir).heightfield
    cost = plan_cost(plan, heightfield)
    assert (cost.runs, cost.renders, cost.reconstructions) == (3, 1, 3)

    out = tmp_path / "out"
    start = time.perf_counter()
    subprocess.run([sys.executable, "-m", "designer", "study", "run", str(study_path),
                    "-o", str(out), "--progress", "none"], cwd=ROOT, check=True,
                   capture_output=True, timeout=600)
    wall_s = time.perf_counter() - start
    with (out / "results.csv").open() as f:
        rows = list(csv.DictReader(f))
    assert [r["status"] for r in rows] == ["ok"] * 3
    # one shared render: every run carries its seconds. The stages' CPU seconds hardly
    # change with the machine's load, their wall seconds grow with it: the estimate lies
    # between the two (each within a factor 1.5)
    render_cpu_s, render_s = float(rows[0]["render_cpu_s"]), float(rows[0]["render_s"])
    reconstruct_cpu_s = sum(float(r["reconstruct_cpu_spent_s"]) + float(r["compare_cpu_s"])
                            for r in rows)
    reconstruct_s = sum(float(r["reconstruct_s"]) + float(r["compare_s"]) for r in rows)
    figures = (f"estimated render {cost.render_s:.1f} s, reconstruct {cost.reconstruct_s:.1f}"
               f" s, total {cost.total_s:.1f} s; measured render {render_cpu_s:.1f} s CPU, "
               f"{render_s:.1f} s wall, reconstruct + compare {reconstruct_cpu_s:.1f} s CPU, "
               f"{reconstruct_s:.1f} s wall, the study {wall_s:.1f} s wall")
    # the render's figure comes from the reference coefficients (fitted to the example's
    # render; its fixed part scaled to this render's small texture bake) and the run
    # overhead is a constant: within a factor 3
    assert render_cpu_s / 3 <= cost.render_s <= render_s * 3, figures
    assert reconstruct_cpu_s / 1.5 <= cost.reconstruct_s <= reconstruct_s * 1.5, figures
    assert wall_s / 3 <= cost.total_s <= wall_s * 3, figures
