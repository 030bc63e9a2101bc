"""Cloud-to-mesh distances side by side: designer, CloudCompare 2.11 C2M and VTK
(``designer bench compare``).

One run measures all three on the same files: a 1 M-triangle procedural terrain
(708 × 708 nodes, 0.125 m spacing, at UTM-sized coordinates) and 1 M points on it
with Gaussian noise — SfM-like (3 cm, 1 % outliers of up to ±1 m), rough (30 cm), and
30 cm over a rugged variant of the mesh (5 cm noise on every node, so the nearest
feature of many points is an edge or a vertex of a crease). Both files are binary PLY
with double x, y, z. Every coordinate is float32-exact after CloudCompare's global
shift, so CloudCompare (which computes in float32) sees exactly the geometry designer
sees and any difference is arithmetic.

Both tools run as the commands a user types, as new processes, interleaved so both see
the same machine load (best of ``repeats``):

* designer: ``python -m designer compare CLOUD MESH -o DIR`` — reads both files, writes
  every product (distances.ply, statistics, histogram, error map PNG/GeoTIFF/npy,
  report);
* CloudCompare: ``CloudCompare -SILENT -AUTO_SAVE OFF -O -GLOBAL_SHIFT … CLOUD -O
  -GLOBAL_SHIFT … MESH -C2M_DIST -C_EXPORT_FMT PLY -SAVE_CLOUDS FILE OUT`` with
  ``QT_QPA_PLATFORM=offscreen`` (no display needed) — reads, computes, writes the cloud
  with its distances.

Figures per tool:

* process: wall time of the whole process, start-up to exit;
* compute: designer = mesh index + distances (summary.json's timing); CloudCompare =
  its log's "computeApproxDistances" + "ComputeDistances" times; VTK =
  ``vtkImplicitPolyDataDistance`` over all points, in this process (one run);
* agreement: max |Δd| of the signed distances where the signs agree, max |Δ|d||, and
  sign disagreements, each tool's sign checked against the truth (is the point above
  the terrain surface at its X, Y?).

First run after installation: every designer process of the benchmark uses an empty
matplotlib configuration folder (``MPLCONFIGDIR``) of its own (matplotlib builds its
font cache there on first use; the comparison's kernels are C, compiled by ``pip
install``, so nothing else is built at run time). Installation is ``designer warmup``
(what ``make setup`` runs after ``pip install``), timed; the first ``designer compare``
after it is the cold run, compared with the best warm run of the same case.
"""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

SHIFT = np.array([500000.0, 5000000.0, 300.0])
#: (label, point noise σ (m), outlier share, terrain node noise σ (m))
CASES = (("SfM-like: 3 cm noise, 1 % outliers", 0.03, 0.01, 0.0),
         ("rough: 30 cm noise", 0.30, 0.0, 0.0),
         ("rugged mesh (5 cm node noise), 30 cm", 0.30, 0.0, 0.05))


def _terrain(n_side: int, node_noise_m: float = 0.0):
    from designer.core.heightfield import Heightfield
    from designer.scene.mesh import heightfield_to_mesh
    from designer.scene.terrain import procedural_terrain

    spacing = 0.125
    size = spacing * (n_side - 1)
    hf = procedural_terrain(size, size, spacing, 5.0, 7, roughness=0.5)
    # float32-exact local heights: CloudCompare stores float32 after the global shift
    z = hf.heights_m + np.random.default_rng(8).normal(0.0, node_noise_m, hf.heights_m.shape)
    z = z.astype(np.float32).astype(np.float64)
    hf = Heightfield(SHIFT[0], SHIFT[1], spacing, spacing, z + SHIFT[2])
    return hf, heightfield_to_mesh(hf)


def _surface_z(hf, x, y) -> np.ndarray:
    """Height of the triangulated surface (cells split SW–NE) at world x, y."""
    z = hf.heights_m
    fx, fy = (x - hf.x0_m) / hf.dx_m, (y - hf.y0_m) / hf.dy_m
    j = np.clip(fx.astype(int), 0, z.shape[1] - 2)
    i = np.clip(fy.astype(int), 0, z.shape[0] - 2)
    u, w = fx - j, fy - i
    sw, se, ne, nw = z[i, j], z[i, j + 1], z[i + 1, j + 1], z[i + 1, j]
    return np.where(u >= w, sw + u * (se - sw) + w * (ne - se), sw + w * (nw - sw) + u * (ne - nw))


def _cloud(hf, n: int, sigma: float, outliers: float, seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    x0, x1, y0, y1 = hf.extent_m
    local = np.column_stack([rng.uniform(0.5, x1 - x0 - 0.5, n),
                             rng.uniform(0.5, y1 - y0 - 0.5, n)])
    x, y = local[:, 0] + SHIFT[0], local[:, 1] + SHIFT[1]
    dz = rng.normal(0.0, sigma, n)
    out = rng.random(n) < outliers
    dz[out] = rng.uniform(-1.0, 1.0, out.sum())
    z = _surface_z(hf, x, y) + dz - SHIFT[2]
    local = np.column_stack([local, z]).astype(np.float32).astype(np.float64)
    return local + SHIFT


def _write_cloud(path: Path, xyz: np.ndarray) -> None:
    vertex = np.empty(len(xyz), dtype=[("x", "<f8"), ("y", "<f8"), ("z", "<f8")])
    vertex["x"], vertex["y"], vertex["z"] = xyz.T
    header = (f"ply\nformat binary_little_endian 1.0\nelement vertex {len(xyz)}\n"
              "property double x\nproperty double y\nproperty double z\nend_header\n")
    path.write_bytes(header.encode("ascii") + vertex.tobytes())


def _designer_env(tmp: Path) -> dict:
    """Environment of the designer processes: this package and a matplotlib
    configuration of their own (empty at first: a fresh installation)."""
    import designer

    env = dict(os.environ)
    root = str(Path(designer.__file__).resolve().parents[1])
    env["PYTHONPATH"] = os.pathsep.join(p for p in (root, env.get("PYTHONPATH")) if p)
    env["MPLCONFIGDIR"] = str(tmp / "mplconfig")
    return env


def _warmup(env: dict) -> float:
    """Seconds of the comparison's part of the installation: ``designer warmup`` without
    its probe render (which calibrates render estimates, not the comparison)."""
    t0 = time.perf_counter()
    subprocess.run([sys.executable, "-m", "designer", "warmup", "--no-probe"], env=env,
                   check=True, capture_output=True, timeout=900)
    return time.perf_counter() - t0


def _designer_once(cloud_ply: Path, mesh_ply: Path, out_dir: Path, env: dict) -> dict:
    from plyfile import PlyData

    cmd = [sys.executable, "-m", "designer", "compare", str(cloud_ply), str(mesh_ply),
           "-o", str(out_dir)]
    t0 = time.perf_counter()
    done = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=900)
    wall = time.perf_counter() - t0
    if done.returncode != 0:
        raise RuntimeError(f"designer compare failed:\n{done.stderr[-2000:]}")
    timing = json.loads((out_dir / "summary.json").read_text())["timing"]
    d = PlyData.read(str(out_dir / "distances.ply"))["vertex"].data["scalar_signed_distance"]
    return {"compute": timing["index_s"] + timing["distances_s"], "process": wall,
            "d": np.array(d, np.float64)}


def cloudcompare_skip_reason() -> str | None:
    """Why CloudCompare's column is left out, or None when it can run."""
    if shutil.which("CloudCompare") is None:
        return ("CloudCompare is not on PATH (Debian: apt-get install cloudcompare, "
                "which scripts/install-system-packages.sh does)")
    return None


def _cloudcompare_once(cloud_ply: Path, mesh_ply: Path, out_ply: Path) -> dict:
    from plyfile import PlyData

    shift = [str(-v) for v in SHIFT]
    cmd = ["CloudCompare", "-SILENT", "-AUTO_SAVE", "OFF",
           "-O", "-GLOBAL_SHIFT", *shift, str(cloud_ply),
           "-O", "-GLOBAL_SHIFT", *shift, str(mesh_ply),
           "-C2M_DIST", "-C_EXPORT_FMT", "PLY", "-SAVE_CLOUDS", "FILE", str(out_ply)]
    env = dict(os.environ, QT_QPA_PLATFORM="offscreen")  # headless, no X server needed
    t0 = time.perf_counter()
    done = subprocess.run(cmd, capture_output=True, text=True, timeout=900, env=env)
    wall = time.perf_counter() - t0
    log = done.stdout

    def seconds(pattern: str) -> float:
        found = re.findall(pattern + r"\s*([0-9.]+) s", log)
        if not found:
            raise RuntimeError(f"CloudCompare log has no '{pattern}' (exit code "
                               f"{done.returncode}):\n{log[-2000:]}{done.stderr[-1000:]}")
        return float(found[-1])

    compute = (seconds(r"\[computeApproxDistances\] Time:")
               + seconds(r"\[ComputeDistances\] Time:"))
    d = PlyData.read(str(out_ply))["vertex"].data["scalar_C2M_signed_distances"]
    return {"compute": compute, "process": wall, "d": np.asarray(d, np.float64)}


def _vtk_once(xyz: np.ndarray, mesh) -> dict:
    import pyvista as pv

    faces = np.column_stack([np.full(len(mesh.faces), 3), mesh.faces]).ravel()
    # VTK stores float32 by default: give it the same shifted coordinates as CloudCompare
    surface = pv.PolyData((mesh.vertices_world - SHIFT).astype(np.float64), faces)
    points = pv.PolyData(xyz - SHIFT)
    t0 = time.perf_counter()
    result = points.compute_implicit_distance(surface)
    seconds = time.perf_counter() - t0
    return {"compute": seconds, "process": float("nan"),
            "d": np.asarray(result["implicit_distance"], np.float64)}


def _agreement(d: np.ndarray, ref: np.ndarray, truth_sign: np.ndarray) -> dict:
    same = np.sign(d) == np.sign(ref)
    return {"max_abs_diff": float(np.max(np.abs(d[same] - ref[same]))) if same.any() else 0.0,
            "max_abs_diff_unsigned": float(np.max(np.abs(np.abs(d) - np.abs(ref)))),
            "sign_disagreements": int((~same).sum()),
            "sign_errors": int((np.sign(d) != truth_sign).sum())}


def run(repeats: int = 3, scale: float = 1.0, first_run: bool = True) -> list[dict]:
    """Rows of the side-by-side table, then (with ``first_run``) one row (``tool``
    "install") with the warm-up and first-run figures; ``scale`` shrinks the data for
    tests. Without ``first_run`` the warm-up runs untimed before the first case."""
    cc_skip = cloudcompare_skip_reason()
    try:
        import pyvista  # noqa: F401
        vtk_skip = None
    except ImportError:
        vtk_skip = "pyvista is not installed (pip install designer[all])"
    n_side = max(8, round(708 * np.sqrt(scale)))
    n_points = max(100, int(1_000_000 * scale))
    rows = []
    with tempfile.TemporaryDirectory(prefix="designer-bench-compare-") as tmp:
        tmp = Path(tmp)
        from designer.scene.mesh import write_mesh_ply

        env = _designer_env(tmp)
        install: dict = {"case": CASES[0][0], "tool": "install"}
        meshes: dict[float, tuple] = {}
        for k, (label, sigma, outliers, node_noise) in enumerate(CASES):
            if node_noise not in meshes:
                hf, mesh = _terrain(n_side, node_noise)
                mesh_ply = tmp / f"mesh{len(meshes)}.ply"
                write_mesh_ply(mesh, mesh_ply)
                meshes[node_noise] = hf, mesh, mesh_ply
            hf, mesh, mesh_ply = meshes[node_noise]
            xyz = _cloud(hf, n_points, sigma, outliers, seed=k)
            cloud_ply = tmp / f"cloud{k}.ply"
            _write_cloud(cloud_ply, xyz)
            truth_sign = np.sign(xyz[:, 2] - _surface_z(hf, xyz[:, 0], xyz[:, 1]))
            if k == 0:  # installation, then the first run after it
                install["warmup_s"] = _warmup(env)
                if first_run:
                    install["first_run_s"] = _designer_once(cloud_ply, mesh_ply, tmp / "out",
                                                            env)["process"]
            best: dict[str, dict] = {}
            for _ in range(repeats):
                runs = [("designer", _designer_once(cloud_ply, mesh_ply, tmp / "out", env))]
                if cc_skip is None:
                    runs.append(("CloudCompare", _cloudcompare_once(cloud_ply, mesh_ply,
                                                                     tmp / "cc.ply")))
                for tool, r in runs:
                    if tool not in best:
                        best[tool] = r
                    else:  # the best of each figure, the distances of the best compute
                        process = min(r["process"], best[tool]["process"])
                        if r["compute"] < best[tool]["compute"]:
                            best[tool] = r
                        best[tool]["process"] = process
            if vtk_skip is None:
                best["VTK"] = _vtk_once(xyz, mesh)
            if k == 0:
                install["warm_run_s"] = best["designer"]["process"]
            ref = best["designer"]["d"]
            for tool, r in best.items():
                agree = _agreement(r["d"], ref, truth_sign)
                rows.append({"case": label, "tool": tool, "points": n_points,
                             "triangles": len(mesh.faces), "compute_s": r["compute"],
                             "process_s": r["process"], **agree})
            for tool, reason in (("CloudCompare", cc_skip), ("VTK", vtk_skip)):
                if reason is not None:
                    rows.append({"case": label, "tool": tool, "skipped": reason})
        if first_run:
            rows.append(install)
    return rows


def format_table(rows: list[dict]) -> str:
    lines = [f"{'case':<36} {'tool':<13} {'compute s':>9} {'M pts/s':>8} {'process s':>9} "
             f"{'÷ CC':>6} {'max|Δd| m':>10} {'max|Δ|d|| m':>11} {'sign≠':>6} "
             f"{'sign wrong':>10}", "-" * 127]
    by_case: dict[str, dict] = {}
    skipped: dict[str, str] = {}
    install = None
    for r in rows:
        if r["tool"] == "install":
            install = r
        elif "skipped" in r:
            skipped[r["tool"]] = r["skipped"]
        else:
            by_case.setdefault(r["case"], {})[r["tool"]] = r
    ratios = []
    for case, tools in by_case.items():
        cc = tools.get("CloudCompare")
        for tool, r in tools.items():
            process = "-" if np.isnan(r["process_s"]) else f"{r['process_s']:.2f}"
            ratio = "-"
            if cc is not None and not np.isnan(r["process_s"]):
                ratio = f"{r['process_s'] / cc['process_s']:.2f}"
                if tool == "designer":
                    ratios.append((case, r["process_s"] / cc["process_s"]))
            diff = "(ref)" if tool == "designer" else f"{r['max_abs_diff']:.1e}"
            diff_u = "(ref)" if tool == "designer" else f"{r['max_abs_diff_unsigned']:.1e}"
            lines.append(
                f"{case:<36} {tool:<13} {r['compute_s']:>9.2f} "
                f"{r['points'] / r['compute_s'] / 1e6:>8.2f} {process:>9} {ratio:>6} "
                f"{diff:>10} {diff_u:>11} {r['sign_disagreements']:>6} {r['sign_errors']:>10}")
    n = next(iter(next(iter(by_case.values())).values()))
    lines += [
        f"{n['points']:,} points vs {n['triangles']:,} triangles, binary PLY (double x, y, z) "
        "at UTM coordinates. process = wall time of the whole command (start-up, reading, "
        "compute, every product written); ÷ CC = process / CloudCompare's process; compute "
        "= mesh index + distances (CloudCompare: its log's approx + exact C2M times); "
        "max|Δd| over points whose signs agree; sign wrong = sign against the true "
        "above/below of the terrain surface. Best of the repeats (VTK: one run, in-process)."]
    for case, ratio in ratios:
        lines.append(f"whole process, designer / CloudCompare: {ratio:.2f} ({case})")
    for tool, reason in skipped.items():
        lines.append(f"{tool} skipped: {reason}")
    if install is not None:
        lines.append(
            "installation (designer warmup --no-probe, empty matplotlib cache): "
            f"{install['warmup_s']:.1f} s; "
            f"first designer compare after it {install['first_run_s']:.2f} s, warm "
            f"{install['warm_run_s']:.2f} s: first / warm = "
            f"{install['first_run_s'] / install['warm_run_s']:.2f} ({install['case']})")
    return "\n".join(lines)
