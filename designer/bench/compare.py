"""Cloud-to-mesh distances side by side: designer, CloudCompare 2.11 C2M and VTK
(``designer bench compare``).

One run measures all three on the same files: a 1 M-triangle procedural terrain
(708 × 708 nodes, 0.125 m spacing, at UTM-sized coordinates) and 1 M points on it
with Gaussian noise — SfM-like (3 cm, 1 % outliers of up to ±1 m), rough (30 cm), and
30 cm over a rugged variant of the mesh (5 cm noise on every node, so the nearest
feature of many points is an edge or a vertex of a crease). Every coordinate is
float32-exact after CloudCompare's global shift, so CloudCompare (which computes in
float32) sees exactly the geometry designer sees and any difference is arithmetic.

Figures per tool (best of ``repeats``, CloudCompare and designer interleaved so both
see the same machine load):

* compute: designer = mesh index + distances; CloudCompare = its "computeApproxDistances"
  + "ComputeDistances" times from its log; VTK = ``vtkImplicitPolyDataDistance`` over
  all points (one run);
* total: designer = read both PLY files + compute + write the result PLY, in-process;
  CloudCompare = its "Processed finished in" time (load, compute, save; process
  start-up excluded on both sides);
* agreement: max |Δd| of the signed distances where the signs agree, max |Δ|d||, and
  sign disagreements, each tool's sign checked against the truth (is the point above
  the terrain surface at its X, Y?).
"""

from __future__ import annotations

import re
import shutil
import subprocess
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


def _designer_once(cloud_ply: Path, mesh_ply: Path, out_ply: Path) -> dict:
    from plyfile import PlyData

    from designer.evaluate.distance import build_mesh_index, signed_distances
    from designer.evaluate.writers import write_distances_ply
    from designer.scene.mesh import load_mesh

    t0 = time.perf_counter()
    mesh = load_mesh(mesh_ply)
    vert = PlyData.read(str(cloud_ply))["vertex"].data
    xyz = np.column_stack([vert["x"], vert["y"], vert["z"]])
    t1 = time.perf_counter()
    index = build_mesh_index(mesh)
    d = signed_distances(xyz, index)
    t2 = time.perf_counter()
    write_distances_ply(out_ply, xyz, d)
    t3 = time.perf_counter()
    return {"compute": t2 - t1, "total": t3 - t0, "d": d}


def _cloudcompare_once(cloud_ply: Path, mesh_ply: Path, out_ply: Path) -> dict:
    from plyfile import PlyData

    shift = [str(-v) for v in SHIFT]
    cmd = ["xvfb-run", "-a", "CloudCompare", "-SILENT", "-AUTO_SAVE", "OFF",
           "-O", "-GLOBAL_SHIFT", *shift, str(cloud_ply),
           "-O", "-GLOBAL_SHIFT", *shift, str(mesh_ply),
           "-C2M_DIST", "-C_EXPORT_FMT", "PLY", "-SAVE_CLOUDS", "FILE", str(out_ply)]
    t0 = time.perf_counter()
    log = subprocess.run(cmd, capture_output=True, text=True, check=True, timeout=600).stdout
    wall = time.perf_counter() - t0

    def seconds(pattern: str) -> float:
        found = re.findall(pattern + r"\s*([0-9.]+) s", log)
        if not found:
            raise RuntimeError(f"CloudCompare log has no '{pattern}':\n{log[-2000:]}")
        return float(found[-1])

    compute = (seconds(r"\[computeApproxDistances\] Time:")
               + seconds(r"\[ComputeDistances\] Time:"))
    d = PlyData.read(str(out_ply))["vertex"].data["scalar_C2M_signed_distances"]
    return {"compute": compute, "total": seconds(r"Processed finished in"), "wall": wall,
            "d": np.asarray(d, np.float64)}


def _vtk_once(xyz: np.ndarray, mesh) -> dict:
    import pyvista as pv

    faces = np.column_stack([np.full(len(mesh.faces), 3), mesh.faces]).ravel()
    # VTK stores float32 by default: give it the same shifted coordinates as CloudCompare
    surface = pv.PolyData((mesh.vertices_world - SHIFT).astype(np.float64), faces)
    points = pv.PolyData(xyz - SHIFT)
    t0 = time.perf_counter()
    result = points.compute_implicit_distance(surface)
    seconds = time.perf_counter() - t0
    return {"compute": seconds, "total": float("nan"),
            "d": np.asarray(result["implicit_distance"], np.float64)}


def _agreement(d: np.ndarray, ref: np.ndarray, truth_sign: np.ndarray) -> dict:
    same = np.sign(d) == np.sign(ref)
    return {"max_abs_diff": float(np.max(np.abs(d[same] - ref[same]))) if same.any() else 0.0,
            "max_abs_diff_unsigned": float(np.max(np.abs(np.abs(d) - np.abs(ref)))),
            "sign_disagreements": int((~same).sum()),
            "sign_errors": int((np.sign(d) != truth_sign).sum())}


def run(repeats: int = 3, scale: float = 1.0) -> list[dict]:
    """Rows of the side-by-side table; ``scale`` shrinks the data for tests."""
    have_cc = shutil.which("CloudCompare") is not None and shutil.which("xvfb-run") is not None
    try:
        import pyvista  # noqa: F401
        have_vtk = True
    except ImportError:
        have_vtk = False
    n_side = max(8, round(708 * np.sqrt(scale)))
    n_points = max(100, int(1_000_000 * scale))
    rows = []
    with tempfile.TemporaryDirectory(prefix="designer-bench-compare-") as tmp:
        tmp = Path(tmp)
        from designer.scene.mesh import write_mesh_ply

        meshes: dict[float, tuple] = {}
        for k, (label, sigma, outliers, node_noise) in enumerate(CASES):
            if node_noise not in meshes:
                hf, mesh = _terrain(n_side, node_noise)
                mesh_ply = tmp / f"mesh{len(meshes)}.ply"
                write_mesh_ply(mesh, mesh_ply)
                if not meshes:  # compile (or load) the kernels before timing anything
                    _designer_once(mesh_ply, mesh_ply, tmp / "warm.ply")
                meshes[node_noise] = hf, mesh, mesh_ply
            hf, mesh, mesh_ply = meshes[node_noise]
            xyz = _cloud(hf, n_points, sigma, outliers, seed=k)
            cloud_ply = tmp / f"cloud{k}.ply"
            _write_cloud(cloud_ply, xyz)
            truth_sign = np.sign(xyz[:, 2] - _surface_z(hf, xyz[:, 0], xyz[:, 1]))
            best: dict[str, dict] = {}
            for _ in range(repeats):
                runs = [("designer", _designer_once(cloud_ply, mesh_ply, tmp / "out.ply"))]
                if have_cc:
                    runs.append(("CloudCompare", _cloudcompare_once(cloud_ply, mesh_ply,
                                                                     tmp / "cc.ply")))
                for tool, r in runs:
                    total = min(r["total"], best[tool]["total"]) if tool in best else r["total"]
                    if tool not in best or r["compute"] < best[tool]["compute"]:
                        best[tool] = r
                    best[tool]["total"] = total
            if have_vtk:
                best["VTK"] = _vtk_once(xyz, mesh)
            ref = best["designer"]["d"]
            for tool, r in best.items():
                agree = _agreement(r["d"], ref, truth_sign)
                rows.append({"case": label, "tool": tool, "points": n_points,
                             "triangles": len(mesh.faces), "compute_s": r["compute"],
                             "total_s": r["total"], **agree})
    return rows


def format_table(rows: list[dict]) -> str:
    lines = [f"{'case':<36} {'tool':<13} {'compute s':>9} {'M pts/s':>8} {'total s':>8} "
             f"{'x designer':>10} {'max|Δd| m':>10} {'max|Δ|d|| m':>11} {'sign≠':>6} "
             f"{'sign wrong':>10}", "-" * 132]
    by_case: dict[str, dict] = {}
    for r in rows:
        by_case.setdefault(r["case"], {})[r["tool"]] = r
    for case, tools in by_case.items():
        base = tools["designer"]["compute_s"]
        for tool, r in tools.items():
            total = "-" if np.isnan(r["total_s"]) else f"{r['total_s']:.2f}"
            diff = "(ref)" if tool == "designer" else f"{r['max_abs_diff']:.1e}"
            diff_u = "(ref)" if tool == "designer" else f"{r['max_abs_diff_unsigned']:.1e}"
            lines.append(
                f"{case:<36} {tool:<13} {r['compute_s']:>9.2f} "
                f"{r['points'] / r['compute_s'] / 1e6:>8.2f} {total:>8} "
                f"{r['compute_s'] / base:>9.1f}x {diff:>10} {diff_u:>11} "
                f"{r['sign_disagreements']:>6} {r['sign_errors']:>10}")
    n = rows[0]
    lines += [
        f"{n['points']:,} points vs {n['triangles']:,} triangles; compute = index + distances "
        "(CloudCompare: its log's approx + exact C2M times); total = read PLYs + compute + write "
        "PLY (process start-up excluded); x designer = compute time / designer's; max|Δd| over "
        "points whose signs agree; sign wrong = sign against the true above/below of the "
        "terrain surface. Best of the repeats (VTK: one run)."]
    return "\n".join(lines)
