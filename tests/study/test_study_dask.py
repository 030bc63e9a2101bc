"""A study through a real (local) Dask cluster: the same runs, hashes and counts.

The cluster is started from the command line (``dask scheduler``, ``dask worker``), as on
cluster nodes; the study goes through the same ``run_study(scheduler=...)`` a
``distributed.LocalCluster`` would reach, so one cluster and one tiny study check both
the counts and the working directories (a LocalCluster renders in
tests/render/test_cluster.py)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from designer.errors import DesignerError
from designer.study.design import plan_study
from designer.study.run import run_study
from designer.study.templates import write_template
from designer.study.xml import read_study

pytestmark = [pytest.mark.blender, pytest.mark.slow]

ROOT = Path(__file__).resolve().parents[2]


def test_an_unreachable_scheduler_is_a_clear_error(tmp_path):
    plan = plan_study(read_study(write_template("tiny", tmp_path / "tiny.xml")[0]))
    with pytest.raises(DesignerError, match=r"--scheduler tcp://127\.0\.0\.1:1: cannot connect"):
        run_study(plan, tmp_path / "out", scheduler="tcp://127.0.0.1:1")
    assert not (tmp_path / "out").exists()


def test_command_line_workers_in_other_directories_and_a_relative_output(tmp_path):
    """As on cluster nodes: `dask scheduler` and two `dask worker` processes started from
    the command line, each in a working directory of its own; the study and a render are
    given a relative -o in a third."""
    import os
    import shutil
    import subprocess
    import sys
    import time

    dask = shutil.which("dask", path=str(Path(sys.executable).parent)) or "dask"
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    for name in ("sched", "w1", "w2", "client"):
        (tmp_path / name).mkdir()
    info = tmp_path / "sched" / "scheduler.json"
    procs = [subprocess.Popen([dask, "scheduler", "--port", "0", "--no-dashboard",
                               "--scheduler-file", str(info)], cwd=tmp_path / "sched",
                              env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)]
    try:
        deadline = time.monotonic() + 60
        while not info.is_file() and time.monotonic() < deadline:
            time.sleep(0.2)
        address = json.loads(info.read_text())["address"]
        for w in ("w1", "w2"):
            procs.append(subprocess.Popen(
                [dask, "worker", address, "--nthreads", "1", "--no-dashboard"],
                cwd=tmp_path / w, env=env, stdout=subprocess.DEVNULL,
                stderr=subprocess.DEVNULL))
        client = tmp_path / "client"
        write_template("tiny", client / "tiny.xml")
        run = subprocess.run([sys.executable, "-m", "designer", "study", "run", "tiny.xml",
                              "-o", "S", "--scheduler", address, "--progress", "none"],
                             cwd=client, env=env, capture_output=True, text=True,
                             timeout=900)
        assert run.returncode == 0, run.stderr
        rows = [json.loads(p.read_text()) for p in sorted((client / "S").glob(
            "runs/*/result.json"))]
        assert [r["status"] for r in rows] == ["ok"] * 4
        # each image set rendered once, each run reconstructed, through the cluster
        summary = json.loads((client / "S" / "summary.json").read_text())
        assert (summary["renders_this_session"], summary["reconstructions_this_session"]
                ) == (2, 4)
        assert (summary["renders"], summary["cache_hits"]) == (2, 2)
        assert [r["status"] for r in summary["rows"]] == ["ok"] * 4
        # a render with a relative -o on the same workers: the images of a local render
        remote = subprocess.run([sys.executable, "-m", "designer", "render", "tiny-base.xml",
                                 "-o", "R", "--scheduler", address, "--progress", "none"],
                                cwd=client, env=env, capture_output=True, text=True,
                                timeout=600)
        assert remote.returncode == 0, remote.stderr
        local = subprocess.run([sys.executable, "-m", "designer", "render", "tiny-base.xml",
                                "-o", "L", "--progress", "none"], cwd=client, env=env,
                               capture_output=True, text=True, timeout=600)
        assert local.returncode == 0, local.stderr
        names = sorted(p.name for p in (client / "L" / "images").iterdir())
        assert names and names == sorted(p.name for p in (client / "R" / "images").iterdir())
        for name in names:
            assert ((client / "R" / "images" / name).read_bytes()
                    == (client / "L" / "images" / name).read_bytes()), name
        assert not list((tmp_path / "w1").iterdir()) and not list((tmp_path / "w2").iterdir())
    finally:
        for p in procs:
            p.terminate()
        for p in procs:
            p.wait(timeout=30)
