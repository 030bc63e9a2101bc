"""``designer bench study --template``: CPU seconds of each stage per run, from a real
(tiny) study."""

from __future__ import annotations

import pytest

from designer.bench import study as bench_study
from designer.cli.main import main

pytestmark = [pytest.mark.blender, pytest.mark.slow]


def test_stage_table_of_a_study_splits_each_runs_cpu_seconds():
    rows = bench_study.run_stages("tiny")
    runs = [r for r in rows if "label" in r]
    whole = [r for r in rows if "wall_s" in r]
    assert [r["status"] for r in runs] == ["ok"] * 4 and len(whole) == 1
    assert whole[0]["failed"] == 0 and whole[0]["wall_s"] > 0
    # two image sets (the render factor's two levels): each rendered once, by one run
    rendered = [r for r in runs if r["render"] is not None]
    assert len(rendered) == 2 and all(r["render"] > 0 for r in rendered)
    # features are computed once per image set and taken from the cache by the others
    computed = [r for r in runs if r["features"] is not None]
    assert 1 <= len(computed) < len(runs) and all(r["features"] > 0 for r in computed)
    assert all(r["adjust+rest"] is not None and r["adjust+rest"] > 0 for r in runs)
    table = bench_study.format_table(rows)
    assert "CPU seconds of each stage per run" in table and "whole command (4 runs" in table
    assert "marking-sigma 2 px" in table  # variants named by their levels


def test_template_is_refused_for_other_benchmarks_and_unknown_templates(capsys):
    assert main(["bench", "core", "--template", "gcp-count"]) != 0
    assert "--template: only 'designer bench study' takes it" in capsys.readouterr().err
    assert main(["bench", "study", "--template", "nonesuch"]) != 0
    assert "--template nonesuch: give one of gcp-count, example-processing" \
        in capsys.readouterr().err
