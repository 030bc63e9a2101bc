"""``designer warmup`` compiles every kernel a comparison uses, with its argument types."""

import os
import subprocess
import sys
from pathlib import Path

import pytest

from designer.bench import compare as bench

ROOT = Path(__file__).resolve().parents[2]


def _cache_files(folder: Path) -> dict[str, int]:
    return {str(p.relative_to(folder)): p.stat().st_mtime_ns
            for p in folder.rglob("*") if p.suffix in (".nbi", ".nbc")}


@pytest.mark.slow
def test_compare_after_warmup_compiles_nothing(tmp_path):
    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path / "numba"),
               MPLCONFIGDIR=str(tmp_path / "mpl"),
               PYTHONPATH=os.pathsep.join(p for p in (str(ROOT), os.environ.get("PYTHONPATH"))
                                          if p))
    done = subprocess.run([sys.executable, "-m", "designer", "warmup"], env=env,
                          capture_output=True, text=True, timeout=900)
    assert done.returncode == 0, done.stderr
    assert "compiled kernels ready" in done.stdout
    after_warmup = _cache_files(tmp_path / "numba")
    names = {Path(f).name.split("-")[0] for f in after_warmup}
    for kernel in ("_bvh.query", "_bvh.build_bvh", "_topology.edge_neighbours",
                   "_grid.nearest_point_grid"):
        assert kernel in names

    hf, mesh = bench._terrain(24)
    from designer.scene.mesh import write_mesh_ply

    write_mesh_ply(mesh, tmp_path / "mesh.ply")
    bench._write_cloud(tmp_path / "cloud.ply", bench._cloud(hf, 3000, 0.05, 0.01, seed=1))
    done = subprocess.run([sys.executable, "-m", "designer", "compare",
                           str(tmp_path / "cloud.ply"), str(tmp_path / "mesh.ply"),
                           "-o", str(tmp_path / "out"), "--max-distance", "0.5"],
                          env=env, capture_output=True, text=True, timeout=900)
    assert done.returncode == 0, done.stderr
    assert (tmp_path / "out" / "error_map.png").is_file()
    # nothing was compiled (no new or rewritten cache file): the first comparison after
    # installation loads what warmup compiled
    assert _cache_files(tmp_path / "numba") == after_warmup
