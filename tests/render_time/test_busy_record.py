"""A render on a busy machine records the idle machine's speed: its wall seconds outside
Cycles (the files, the effects, the preparation, the waits) are scaled by the share of
the cores its Cycles threads had."""

from __future__ import annotations

import pytest

from designer.render.job import prepare_job
from designer.render.runner import RenderReport
from designer.render_time.record import core_share, record_render_speed
from tests import synthetic


def _report(prepared, share: float, threads: int) -> RenderReport:
    """Frames as a machine renders them when its Cycles threads have ``share`` of
    their cores: Cycles' CPU-seconds as idle, every wall second stretched by 1/share."""
    report = RenderReport(peak_rss_mb=[500.0], first_frames={0})
    wall = 0.0
    for i in range(len(prepared.job.frames)):
        cpu = 2.0 + 0.1 * i
        cycles_s = cpu / threads / share
        post = 0.3 / share
        report.rendered[i] = cycles_s + post
        report.stages[i] = {"cycles_s": cycles_s, "cycles_cpu_s": cpu}
        wall += cycles_s + post
    report.wall_seconds = wall + 4.0 / share  # the worker's start and scene, stretched
    return report


@pytest.fixture
def prepared(tmp_path):
    project = synthetic.small_survey()
    return prepare_job(project, tmp_path, tmp_path / "out")


def test_the_record_of_a_busy_render_is_the_idle_machines(prepared, tmp_path, monkeypatch):
    monkeypatch.setenv("DESIGNER_CACHE_DIR", str(tmp_path / "cache"))
    threads = 2
    idle = record_render_speed(prepared, _report(prepared, 1.0, threads), 3.0, cores=2)
    busy = record_render_speed(prepared, _report(prepared, 0.3, threads), 3.0 / 0.3,
                               cores=2)
    assert busy.terrain_cpu_s_per_mp_sample == pytest.approx(idle.terrain_cpu_s_per_mp_sample)
    assert busy.post_s_per_mp == pytest.approx(idle.post_s_per_mp)
    assert busy.fixed_s == pytest.approx(idle.fixed_s)
    assert idle.fixed_s > 3.0  # the preparation and the worker's start are in it


def test_the_share_of_the_cores_is_cycles_cpu_over_its_wall_and_threads():
    assert core_share({"cycles_s": 2.0, "cycles_cpu_s": 3.96}, 2) == pytest.approx(0.99)
    assert core_share({"cycles_s": 10.0, "cycles_cpu_s": 6.0}, 2) == pytest.approx(0.3)
    assert core_share({"cycles_s": 1.0, "cycles_cpu_s": 2.5}, 2) == 1.0
    assert core_share({}, 2) == 1.0  # not measured: taken as idle
