"""Clouds whose stored coordinates are coarser than 1 mm (float32 PLY at UTM size, as
COLMAP writes them; a coarse LAS scale) are refused with the fix, or compared knowingly
with --allow-float32; float32 in a local frame plus --offset is accepted."""

from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import pytest
from plyfile import PlyData, PlyElement

from designer.cli.main import main
from designer.errors import DesignerError
from designer.evaluate import read_point_cloud, reference_mesh
from tests.evaluate.helpers import EXAMPLE, points_on_mesh


def write_ply(path, xyz, dtype):
    v = np.empty(len(xyz), dtype=[("x", dtype), ("y", dtype), ("z", dtype)])
    v["x"], v["y"], v["z"] = np.asarray(xyz).T
    PlyData([PlyElement.describe(v, "vertex")], byte_order="<").write(str(path))


@pytest.fixture(scope="module")
def example_points():
    """Points 2 cm above the example's terrain (UTM 32N: E 512 km, N 5406 km)."""
    terrain = reference_mesh(EXAMPLE, with_targets=False)
    return points_on_mesh(terrain.vertices, terrain.faces, 5000, 0.02,
                          np.random.default_rng(3))


def test_a_float32_ply_at_utm_size_is_refused_with_the_fix(tmp_path, example_points):
    path = tmp_path / "colmap.ply"
    write_ply(path, example_points, "f4")
    with pytest.raises(DesignerError) as info:
        read_point_cloud(path)
    message = str(info.value)
    assert "\n" not in message and str(path) in message
    # the largest coordinate is the northing, 5.406e6 m, where float32 steps are 0.5 m
    assert np.spacing(np.float32(5.406e6)) == 0.5
    assert "float32 up to |5406" in message and "spacing is 500 mm" in message
    assert "--offset" in message and "--allow-float32" in message
    suggested = [float(v) for v in message.split("--offset ")[1].split(",")[0].split()]
    centre = (example_points.min(axis=0) + example_points.max(axis=0)) / 2
    assert np.all(np.abs(np.array(suggested) - centre) <= 50)  # rounded to 100 m

    cloud = read_point_cloud(path, allow_coarse=True)
    assert cloud.coordinate_spacing_m == 0.5
    assert np.max(np.abs(cloud.xyz - example_points)) <= 0.25


def test_float32_in_a_local_frame_with_the_offset_is_accepted(tmp_path, example_points):
    origin = np.round(example_points.mean(axis=0))
    path = tmp_path / "local.ply"
    write_ply(path, example_points - origin, "f4")
    cloud = read_point_cloud(path, offset=origin)
    assert cloud.coordinate_spacing_m <= 1e-5  # local values of tens of metres
    assert np.max(np.abs(cloud.xyz - example_points)) < 1e-5


def test_doubles_at_utm_size_have_no_spacing_to_report(tmp_path, example_points):
    path = tmp_path / "double.ply"
    write_ply(path, example_points, "f8")
    cloud = read_point_cloud(path)
    assert cloud.coordinate_spacing_m is None
    assert np.array_equal(cloud.xyz, example_points)


def test_a_las_file_with_a_centimetre_scale_is_refused(tmp_path, example_points):
    laspy = pytest.importorskip("laspy")
    for scale, refused in ((0.01, True), (0.001, False)):
        header = laspy.LasHeader(point_format=0, version="1.2")
        header.scales = np.full(3, scale)
        header.offsets = np.floor(example_points.min(axis=0))
        las = laspy.LasData(header)
        las.x, las.y, las.z = example_points.T
        path = tmp_path / f"scale-{scale}.las"
        las.write(str(path))
        if refused:
            with pytest.raises(DesignerError, match=r"scale of 10 mm.*0\.001 m or finer"):
                read_point_cloud(path)
        else:
            assert read_point_cloud(path).coordinate_spacing_m == pytest.approx(0.001)


def test_compare_refuses_a_float32_utm_cloud_and_suggests_the_projects_origin(
        tmp_path, example_points):
    path = tmp_path / "colmap.ply"
    write_ply(path, example_points, "f4")
    run = subprocess.run([sys.executable, "-m", "designer", "compare", str(path), EXAMPLE,
                          "-o", str(tmp_path / "out")], capture_output=True, text=True)
    assert run.returncode == 2
    lines = run.stderr.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in run.stderr
    # the example project's origin is its local frame: E0 N0 H0
    from designer.project import load_project

    origin = load_project(EXAMPLE).origin
    assert f"--offset {origin.E0:.10g} {origin.N0:.10g} {origin.H0:.10g}" in lines[0]
    assert not (tmp_path / "out").exists()


def test_compare_with_allow_float32_warns_and_records_the_spacing(tmp_path, example_points,
                                                                  capsys):
    path = tmp_path / "colmap.ply"
    write_ply(path, example_points, "f4")
    out = tmp_path / "out"
    assert main(["compare", str(path), EXAMPLE, "-o", str(out), "--no-targets",
                 "--allow-float32"]) == 0
    assert "warning:" in capsys.readouterr().err
    summary = json.loads((out / "summary.json").read_text())
    assert summary["inputs"]["coordinate_spacing_m"] == 0.5
    assert summary["warnings"] and "500 mm" in summary["warnings"][0]
    assert "**warning**" in (out / "report.md").read_text()
    # the same points written locally and offset back: the true 2 cm, no warning
    local = tmp_path / "local.ply"
    origin = np.round(example_points.mean(axis=0))
    write_ply(local, example_points - origin, "f4")
    assert main(["compare", str(local), EXAMPLE, "-o", str(tmp_path / "ok"), "--no-targets",
                 "--offset", *map(str, origin)]) == 0
    good = json.loads((tmp_path / "ok" / "summary.json").read_text())
    assert good["warnings"] == [] and good["inputs"]["coordinate_spacing_m"] < 1e-5
    assert abs(good["distances"]["median"] - 0.02) < 1e-4
    coarse = summary["distances"]
    assert abs(coarse["median"] - 0.02) > abs(good["distances"]["median"] - 0.02)
