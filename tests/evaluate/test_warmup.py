"""The comparison's kernels are compiled at installation: ``designer warmup`` checks them,
and a comparison loads neither numba nor a compiler."""

import os
import subprocess
import sys
from pathlib import Path

import pytest

from designer.bench import compare as bench

ROOT = Path(__file__).resolve().parents[2]


def _env(tmp_path: Path) -> dict:
    return dict(os.environ, MPLCONFIGDIR=str(tmp_path / "mpl"),
                PYTHONPATH=os.pathsep.join(p for p in (str(ROOT), os.environ.get("PYTHONPATH"))
                                           if p))


@pytest.mark.slow
def test_warmup_then_compare_imports_no_numba(tmp_path):
    env = _env(tmp_path)
    # without the probe render (six example frames), as `make install` (which `make test`
    # and `make demo` run first) runs it; `make setup` runs the whole `designer warmup`
    done = subprocess.run([sys.executable, "-m", "designer", "warmup", "--no-probe"],
                          env=env, capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    assert "compiled kernels ready" in done.stdout
    assert "render speed measured" not in done.stdout

    hf, mesh = bench._terrain(24)
    from designer.scene.mesh import write_mesh_ply

    write_mesh_ply(mesh, tmp_path / "mesh.ply")
    bench._write_cloud(tmp_path / "cloud.ply", bench._cloud(hf, 3000, 0.05, 0.01, seed=1))
    done = subprocess.run([sys.executable, "-X", "importtime", "-m", "designer", "compare",
                           str(tmp_path / "cloud.ply"), str(tmp_path / "mesh.ply"),
                           "-o", str(tmp_path / "out"), "--max-distance", "0.5"],
                          env=env, capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    assert (tmp_path / "out" / "error_map.png").is_file()
    imported = {line.split("|")[-1].strip() for line in done.stderr.splitlines()
                if line.startswith("import time:")}
    assert "designer.evaluate._ckernels" in imported  # the list is complete
    assert not {name for name in imported if name.split(".")[0] in ("numba", "llvmlite")}


def test_missing_extension_is_a_one_line_error():
    code = ("import sys; sys.modules['designer.evaluate._ckernels'] = None\n"
            "from designer.errors import DesignerError\n"
            "from designer.evaluate._native import ckernels\n"
            "try:\n    ckernels()\nexcept DesignerError as e:\n    print(e)\n")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          timeout=60, env=_env(Path("/nonexistent")))
    assert done.returncode == 0, done.stderr
    message = done.stdout.strip()
    assert "\n" not in message
    assert "compiled kernels are missing" in message and "pip install -e ." in message


def test_threads_setting(monkeypatch):
    from designer.errors import DesignerError
    from designer.evaluate._native import threads

    monkeypatch.setenv("DESIGNER_THREADS", "3")
    assert threads() == 3
    monkeypatch.delenv("DESIGNER_THREADS")
    assert threads() == len(os.sched_getaffinity(0))
    for bad in ("0", "two", "-1"):
        monkeypatch.setenv("DESIGNER_THREADS", bad)
        with pytest.raises(DesignerError, match="DESIGNER_THREADS"):
            threads()
