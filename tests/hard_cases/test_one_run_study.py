"""A study of one run (docs/hard-cases.md): one factor at one level is one render, one
reconstruction and one comparison; ``designer study run`` writes results.csv, summary.json
and the report, claims no test (no degrees of freedom) and exits 0."""

from __future__ import annotations

import csv
import json
import re
import subprocess
import sys
from pathlib import Path

import pytest

from designer.study.templates import write_template

pytestmark = [pytest.mark.blender, pytest.mark.slow]

ROOT = Path(__file__).resolve().parents[2]

ONE_RUN = """<?xml version="1.0" encoding="UTF-8"?>
<study xmlns="urn:designer:project:1" schema-version="1.0" name="one-run">
  <base-project file="tiny-base.xml"/>
  <factor name="sun-elevation-deg">
    <values>50</values>
  </factor>
  <design>full-factorial</design>
  <replicates count="1"/>
  <metrics>check_rmse_z_m registered</metrics>
</study>
"""


def test_a_study_of_one_run_writes_its_results_summary_and_report(tmp_path):
    write_template("tiny", tmp_path / "tiny.xml")  # tiny-base.xml: 18 images, 160 × 120
    study = tmp_path / "one.xml"
    study.write_text(ONE_RUN)
    out = tmp_path / "out"
    run = subprocess.run([sys.executable, "-m", "designer", "study", "run", str(study),
                          "-o", str(out), "--workers", "1", "--progress", "none"],
                         cwd=ROOT, capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, run.stderr
    assert "Traceback" not in run.stderr and "1 runs of 1 variants" in run.stdout
    with (out / "results.csv").open() as table:
        (row,) = list(csv.DictReader(table))
    assert row["status"] == "ok" and row["factor:sun-elevation-deg"] == "50"
    assert float(row["registered"]) == float(row["images"]) >= 3
    assert 0 < float(row["check_rmse_z_m"]) < 0.5  # measured 0.04 m (GSD 10 cm)
    summary = json.loads((out / "summary.json").read_text())
    assert (summary["runs"], summary["variants"], summary["ok"], summary["failed"]) \
        == (1, 1, 1, 0)
    report = (out / "report.md").read_text()
    assert (out / "report.html").is_file()
    # one level, one run: the table of effects claims nothing (no F, no p)
    rows = [r for r in report.splitlines() if r.startswith("| sun-elevation-deg | check_rmse")]
    assert rows and re.fullmatch(r"\| sun-elevation-deg \| check_rmse_z_m \| 1 \| 1 "
                                 r"(\| – ){5}\|", rows[0]), rows
    for text in (report, (out / "summary.json").read_text(), (out / "results.csv").read_text()):
        assert not re.search(r"\bnan\b|\binf\b", text, re.IGNORECASE)
