"""The project I/O benchmark runs (at a small scale here; it never asserts a time)."""

from __future__ import annotations

from designer.bench.project_io import format_table, large_project, run


def test_benchmark_runs_and_prints_its_table():
    rows = run(repeats=1, scale=0.01)
    assert [r["stage"] for r in rows][-1] == "read + validate (load_project)"
    table = format_table(rows)
    assert "100 poses + 10 GCPs" in table and "seconds" in table


def test_the_large_project_has_the_requested_size():
    project = large_project(50, 7)
    assert len(project.trajectory.exterior_orientations) == 50
    assert len(project.targets) == 7
