import json
import shutil
import subprocess

import numpy as np
import pytest
from plyfile import PlyData

from designer.cli.main import main
from designer.core.heightfield import Heightfield
from designer.core.truth import observe_gcps
from designer.evaluate import reference_mesh
from designer.export.colmap import write_colmap_text_model
from designer.export.dispatch import write_all
from designer.scene.mesh import heightfield_to_mesh, write_mesh_ply
from tests.evaluate.helpers import EXAMPLE, points_on_mesh, write_cloud
from tests.synthetic import ORIGIN_WORLD, grid_gcps, grid_poses, mapping_camera


def test_compare_with_a_project_writes_the_report(tmp_path, capsys):
    rng = np.random.default_rng(0)
    terrain = reference_mesh(EXAMPLE, with_targets=False)
    xyz = points_on_mesh(terrain.vertices, terrain.faces, 20000, 0.02, rng)
    write_cloud(tmp_path / "cloud.ply", xyz)
    out = tmp_path / "out"
    assert main(["compare", str(tmp_path / "cloud.ply"), EXAMPLE, "-o", str(out),
                 "--no-targets", "--tolerance", "0.01", "0.021"]) == 0
    printed = capsys.readouterr().out
    assert "RMSE" in printed and "NMAD" in printed
    summary = json.loads((out / "summary.json").read_text())
    s = summary["distances"]
    assert s["n"] == 20000 and abs(s["median"] - 0.02) < 1e-9
    assert s["max"] <= 0.02 + 1e-9 and s["min"] > 0  # concave creases come closer
    assert [t["share"] for t in s["within_tolerance"]][1] == 1.0
    assert summary["inputs"]["crs"].startswith("EPSG:32632")
    d = PlyData.read(str(out / "distances.ply"))["vertex"].data
    assert np.array_equal(np.column_stack([d["x"], d["y"], d["z"]]), xyz)
    assert abs(np.median(d["scalar_signed_distance"]) - 0.02) < 1e-9
    for name in ("report.md", "report.html", "histogram.png", "error_map.png",
                 "error_map.tif", "error_map.npy"):
        assert (out / name).stat().st_size > 0, name
    report = (out / "report.md").read_text()
    assert "NMAD" in report and "error_map.png" in report and "histogram.png" in report
    # a ReferenceMesh is a mesh for signed_distances too
    from designer.evaluate import signed_distances
    assert np.allclose(signed_distances(xyz[:100], terrain), d["scalar_signed_distance"][:100])
    # with the GCP plates the mesh has more triangles
    with_targets = reference_mesh(EXAMPLE)
    assert len(with_targets.faces) > len(terrain.faces)


def small_terrain():
    rng = np.random.default_rng(3)
    z = ORIGIN_WORLD[2] + np.cumsum(rng.normal(0, 0.05, (41, 41)), axis=0)
    hf = Heightfield(ORIGIN_WORLD[0] - 60, ORIGIN_WORLD[1] - 60, 3.0, 3.0, z)
    return heightfield_to_mesh(hf)


def test_compare_a_colmap_model_with_ground_truth(tmp_path, capsys):
    """A perfect reconstruction in local coordinates: zero GCP and camera errors."""
    mesh = small_terrain()
    write_mesh_ply(mesh, tmp_path / "mesh.ply", origin=ORIGIN_WORLD)  # local + comment
    cam, poses, gcps = mapping_camera(), grid_poses(), grid_gcps()
    obs = observe_gcps(gcps, poses, cam)
    write_all(tmp_path / "render" / "ground-truth", cam, poses, gcps, obs, "EPSG:32632",
              formats=("opk", "gcp"))
    model = tmp_path / "model"
    write_colmap_text_model(model, cam, poses, offset_world=ORIGIN_WORLD)
    rng = np.random.default_rng(4)
    pts = points_on_mesh(mesh.vertices_world, mesh.faces, 500, -0.01, rng) - ORIGIN_WORLD
    lines = [f"{i + 1} {x!r} {y!r} {z!r} 128 128 128 0.5" for i, (x, y, z) in enumerate(pts)]
    (model / "points3D.txt").write_text("\n".join(lines) + "\n")
    out = tmp_path / "out"
    assert main(["compare", str(model), str(tmp_path / "mesh.ply"), "-o", str(out),
                 "--offset", *map(str, ORIGIN_WORLD), "--truth", str(tmp_path / "render"),
                 "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert abs(summary["distances"]["median"] + 0.01) < 1e-6  # text model: 15 digits
    g = summary["gcps"]["summary"]
    assert g["check"]["n"] == 3 and g["control"]["n"] == 5 and g["all"]["max_XYZ"] < 1e-5
    c = summary["cameras"]["summary"]
    assert c["n"] == len(poses) and c["rmse_XYZ"] < 1e-6 and c["rotation_max_deg"] < 1e-6
    report = (out / "report.md").read_text()
    assert "check points" in report.lower() and "Camera poses" in report


def test_user_errors_are_one_line_exit_2(tmp_path, capsys):
    mesh = small_terrain()
    write_mesh_ply(mesh, tmp_path / "mesh.ply")
    assert main(["compare", str(tmp_path / "none.ply"), str(tmp_path / "mesh.ply"),
                 "-o", str(tmp_path / "o")]) == 2
    assert "does not exist" in capsys.readouterr().err
    write_cloud(tmp_path / "local.ply", mesh.vertices_world[:100] - ORIGIN_WORLD)
    assert main(["compare", str(tmp_path / "local.ply"), str(tmp_path / "mesh.ply"),
                 "-o", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert "--offset" in err and err.count("\n") == 1
    assert main(["compare", str(tmp_path / "local.ply"), str(tmp_path / "mesh.ply"),
                 "-o", str(tmp_path / "o"), "--max-distance", "-1"]) == 2


@pytest.mark.skipif(shutil.which("CloudCompare") is None or shutil.which("xvfb-run") is None,
                    reason="CloudCompare (Debian package cloudcompare) and xvfb not installed")
def test_cloudcompare_reads_our_scalar_and_agrees_on_a_small_case(tmp_path):
    mesh = small_terrain()
    write_mesh_ply(mesh, tmp_path / "mesh.ply")
    rng = np.random.default_rng(5)
    local = points_on_mesh(mesh.vertices_world, mesh.faces, 3000, 0.0, rng) - ORIGIN_WORLD
    local[:, 2] += rng.normal(0, 0.2, 3000)
    # float32-exact after the shift, so CloudCompare sees our geometry
    xyz = local.astype(np.float32).astype(np.float64) + ORIGIN_WORLD
    write_cloud(tmp_path / "cloud.ply", xyz)
    assert main(["compare", str(tmp_path / "cloud.ply"), str(tmp_path / "mesh.ply"),
                 "-o", str(tmp_path / "out")]) == 0
    shift = [str(-v) for v in ORIGIN_WORLD]
    subprocess.run(["xvfb-run", "-a", "CloudCompare", "-SILENT", "-AUTO_SAVE", "OFF",
                    "-O", "-GLOBAL_SHIFT", *shift, str(tmp_path / "out" / "distances.ply"),
                    "-O", "-GLOBAL_SHIFT", *shift, str(tmp_path / "mesh.ply"), "-C2M_DIST",
                    "-C_EXPORT_FMT", "PLY", "-SAVE_CLOUDS", "FILE", str(tmp_path / "cc.ply")],
                   check=True, capture_output=True, timeout=300)
    cc = PlyData.read(str(tmp_path / "cc.ply"))["vertex"].data
    names = cc.dtype.names
    ours = np.asarray(cc[next(n for n in names if "signed_distance" in n and "C2M" not in n)])
    theirs = np.asarray(cc["scalar_C2M_signed_distances"], np.float64)
    d = PlyData.read(str(tmp_path / "out" / "distances.ply"))["vertex"].data
    assert np.allclose(ours, d["scalar_signed_distance"], atol=1e-6)  # CloudCompare: float
    same = np.sign(theirs) == np.sign(ours)
    assert same.mean() > 0.99
    assert np.max(np.abs(theirs[same] - ours[same])) < 1e-5


def test_the_program_exits_at_once_with_every_product_written(tmp_path):
    """``python -m designer compare`` ends without the interpreter's teardown: the exit
    code, the printed summary and every product must still be complete; a user error
    still exits 2 with its message and no distances file."""
    import sys

    mesh = small_terrain()
    write_mesh_ply(mesh, tmp_path / "mesh.ply")
    rng = np.random.default_rng(5)
    write_cloud(tmp_path / "cloud.ply",
                points_on_mesh(mesh.vertices_world, mesh.faces, 2000, 0.02, rng))
    out = tmp_path / "out"
    done = subprocess.run([sys.executable, "-m", "designer", "compare",
                           str(tmp_path / "cloud.ply"), str(tmp_path / "mesh.ply"),
                           "-o", str(out)], capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr
    assert done.stdout.rstrip().endswith("report.html")
    summary = json.loads((out / "summary.json").read_text())
    assert abs(summary["distances"]["median"] - 0.02) < 1e-9
    d = PlyData.read(str(out / "distances.ply"))["vertex"].data["scalar_signed_distance"]
    assert len(d) == 2000 and abs(np.median(d) - 0.02) < 1e-9
    for name in ("histogram.png", "error_map.png", "error_map.tif", "error_map.npy",
                 "report.md", "report.html"):
        assert (out / name).stat().st_size > 0, name
    bad = subprocess.run([sys.executable, "-m", "designer", "compare",
                          str(tmp_path / "cloud.ply"), str(tmp_path / "mesh.ply"),
                          "-o", str(tmp_path / "bad"), "--max-distance", "1e-9"],
                         capture_output=True, text=True, timeout=600)
    assert bad.returncode == 2 and bad.stderr.count("\n") == 1, bad.stderr
    assert not (tmp_path / "bad" / "distances.ply").exists()
