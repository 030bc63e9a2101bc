"""The true surface of a project includes its scene objects (the validation cube); its DTM
and DSM come from one load of the project and one build of its terrain."""

import re

import numpy as np
import pytest

from designer.evaluate.compare import reference_mesh, reference_meshes
from designer.evaluate.distance import signed_distances
from designer.project import template, write_project
from tests.synthetic import count_calls


def _cube_project(tmp_path):
    tpl = template("validation-cube")
    path = tmp_path / "cube.xml"
    write_project(tpl.project, path)
    for name, data in tpl.files.items():
        (tmp_path / name).write_bytes(data)
    return path


def test_the_cube_is_part_of_the_true_surface(tmp_path):
    mesh = reference_mesh(_cube_project(tmp_path), with_targets=False)
    assert mesh.vertices.max(axis=0)[2] == pytest.approx(4.0)  # the cube's top, 4 m up
    # points on the cube's top and on one side are on the surface (distance 0)
    points = np.array([[0.5, -0.3, 4.0], [2.0, 0.7, 1.5], [10.0, 10.0, 0.0]])
    d = signed_distances(points, mesh)
    np.testing.assert_allclose(d, 0.0, atol=1e-9)


def test_the_bare_earth_leaves_the_cube_out_and_the_surface_keeps_it(tmp_path):
    path = _cube_project(tmp_path)
    dtm = reference_mesh(path, with_targets=False, surface="dtm")
    dsm = reference_mesh(path, with_targets=False, surface="dsm")
    assert (dtm.surface, dsm.surface) == ("dtm", "dsm")
    assert dtm.vertices.max(axis=0)[2] < 1.0 < 4.0 == pytest.approx(dsm.vertices.max(axis=0)[2])
    top = np.array([[0.5, -0.3, 4.0]])  # on the cube's top: 4 m above the bare earth
    assert signed_distances(top, dsm)[0] == pytest.approx(0.0, abs=1e-9)
    assert signed_distances(top, dtm)[0] == pytest.approx(4.0, abs=1e-6)
    # the default is the surface, as before
    default = reference_mesh(path, with_targets=False)
    assert np.array_equal(default.vertices, dsm.vertices)
    assert np.array_equal(default.faces, dsm.faces)


def test_both_surfaces_from_one_load_equal_the_surfaces_loaded_alone(tmp_path):
    path = _cube_project(tmp_path)
    both = reference_meshes(path, surfaces=("dtm", "dsm"))
    assert list(both) == ["dtm", "dsm"]
    for surface, mesh in both.items():
        alone = reference_mesh(path, surface=surface)  # with the GCP targets, as by default
        assert (mesh.surface, mesh.source, mesh.crs) == (surface, alone.source, alone.crs)
        assert np.array_equal(mesh.vertices, alone.vertices)
        assert np.array_equal(mesh.faces, alone.faces)
    assert len(both["dtm"].faces) < len(both["dsm"].faces)  # the cube is in the DSM only
    # a mesh file is its own surface, whatever the name
    (tmp_path / "mesh.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    files = reference_meshes(tmp_path / "mesh.obj")
    assert list(files) == ["dtm", "dsm"] and files["dtm"] is files["dsm"]
    assert files["dtm"].surface is None and len(files["dtm"].faces) == 1


def test_both_surfaces_load_the_project_and_build_the_terrain_once(tmp_path, monkeypatch):
    import designer.project
    import designer.scene.build

    path = _cube_project(tmp_path)
    loads = count_calls(monkeypatch, designer.project, "load_project")
    terrains = count_calls(monkeypatch, designer.scene.build, "build_terrain_mesh")
    reference_meshes(path, surfaces=("dsm", "dtm"))
    assert (len(loads), len(terrains)) == (1, 1)
    reference_mesh(path, surface="dsm")  # each alone loads and builds its own
    reference_mesh(path, surface="dtm")
    assert (len(loads), len(terrains)) == (3, 3)


def test_compare_says_which_surface_it_used(tmp_path, capsys):
    import json

    from designer.cli.main import main
    from tests.evaluate.helpers import write_cloud

    path = _cube_project(tmp_path)
    rng = np.random.default_rng(3)
    xyz = np.column_stack([rng.uniform(-1.5, 1.5, 500), rng.uniform(-1.5, 1.5, 500),
                           np.full(500, 4.0)])  # the cube's top
    write_cloud(tmp_path / "top.ply", xyz)
    medians = {}
    for surface in ("dtm", "dsm"):
        out = tmp_path / surface
        assert main(["compare", str(tmp_path / "top.ply"), str(path), "-o", str(out),
                     "--no-targets", "--surface", surface]) == 0
        printed = capsys.readouterr().out
        summary = json.loads((out / "summary.json").read_text())
        assert summary["inputs"]["surface"] == surface
        assert re.search(rf"true surface\s+{surface.upper()} ", printed), printed
        assert surface.upper() in (out / "report.md").read_text()
        medians[surface] = summary["distances"]["median"]
    assert medians["dsm"] == pytest.approx(0.0, abs=1e-6)
    assert medians["dtm"] == pytest.approx(4.0, abs=1e-3)
    # a mesh file is its own surface: --surface is refused with one line
    (tmp_path / "mesh.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    assert main(["compare", str(tmp_path / "top.ply"), str(tmp_path / "mesh.obj"),
                 "-o", str(tmp_path / "x"), "--surface", "dtm"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--surface dtm" in err[0] and "mesh.obj" in err[0]
    assert not (tmp_path / "x").exists()
