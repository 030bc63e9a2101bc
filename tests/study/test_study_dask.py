"""A study through a real (local) Dask cluster: the same runs, hashes and counts."""

from __future__ import annotations

import json
from pathlib import Path

import distributed
import pytest

from designer.errors import DesignerError
from designer.study.design import plan_study
from designer.study.run import run_study
from designer.study.templates import write_template
from designer.study.xml import read_study

pytestmark = [pytest.mark.blender, pytest.mark.slow]

ROOT = Path(__file__).resolve().parents[2]


def test_a_study_runs_on_a_dask_cluster(tmp_path, monkeypatch):
    monkeypatch.setenv("PYTHONPATH", str(ROOT))  # the workers import this designer
    plan = plan_study(read_study(write_template("tiny", tmp_path / "tiny.xml")[0]))
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster:
        report = run_study(plan, tmp_path / "out", scheduler=cluster.scheduler_address)
    assert [r["status"] for r in report.rows] == ["ok"] * 4
    assert (report.counts["renders_this_session"], report.counts["reconstructions_this_session"]
            ) == (2, 4)
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert (summary["renders"], summary["cache_hits"]) == (2, 2)


def test_an_unreachable_scheduler_is_a_clear_error(tmp_path):
    plan = plan_study(read_study(write_template("tiny", tmp_path / "tiny.xml")[0]))
    with pytest.raises(DesignerError, match=r"--scheduler tcp://127\.0\.0\.1:1: cannot connect"):
        run_study(plan, tmp_path / "out", scheduler="tcp://127.0.0.1:1")
    assert not (tmp_path / "out").exists()
