"""Vegetation geometry without Blender: placement, the sway at two image times, the DTM
and DSM `designer compare` measures against, round trips and located one-line errors."""

from __future__ import annotations

import json
import re
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from designer.project import load_project
from designer.project import model as m
from designer.scene.build import build_heightfield, build_terrain_mesh
from designer.scene.surfaces import Ground, true_surface
from designer.scene.vegetation import (
    builtin_template,
    place_vegetation,
    plant_rotations,
    sway_angle_rad,
    sway_axis,
    vegetation_mesh_world,
)
from tests.synthetic import assert_located_error, write_project_file
from tests.world.helpers import ORIGIN
from tests.world.vegetation_helpers import WIND, vegetation_project


def _ground(p: m.Project, base: Path) -> Ground:
    hf = build_heightfield(p.scene.terrain, base, p.crs)
    return Ground(hf, build_terrain_mesh(p.scene.terrain, hf, base, np.array(ORIGIN)))


def _rotation(axis: np.ndarray, angle_rad: float) -> np.ndarray:
    K = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + np.sin(angle_rad) * K + (1 - np.cos(angle_rad)) * K @ K


def test_the_sway_between_two_times_is_the_predicted_turn_about_the_base(tmp_path):
    p = vegetation_project(flat=False)
    ground = _ground(p, tmp_path)
    (plants,) = place_vegetation(p, tmp_path, ground)
    t1, t2 = 0.4, 2.9
    (a_v, a_f), = vegetation_mesh_world(p, tmp_path, ground, t1)
    (b_v, b_f), = vegetation_mesh_world(p, tmp_path, ground, t2)
    assert np.array_equal(a_f, b_f)
    n_v = len(plants.template.vertices)
    axis = sway_axis(WIND)
    # the axis is horizontal and perpendicular to the wind (60° clockwise from north)
    wind_dir = np.array([np.sin(np.radians(60)), np.cos(np.radians(60)), 0])
    assert abs(axis @ wind_dir) < 1e-12 and axis[2] == 0
    amplitude = np.radians(WIND.amplitude_deg)
    moved = []
    for k in range(len(plants)):
        base = plants.base_world[k]
        a = a_v[k * n_v:(k + 1) * n_v] - base
        b = b_v[k * n_v:(k + 1) * n_v] - base
        phase = plants.phase_rad[k]
        predicted = amplitude * (np.sin(2 * np.pi * t2 / WIND.gust_period_s + phase)
                                 - np.sin(2 * np.pi * t1 / WIND.gust_period_s + phase))
        np.testing.assert_allclose(b, a @ _rotation(axis, predicted).T, atol=1e-9)
        moved.append(abs(predicted))
    assert max(moved) > np.radians(20)  # the plants really turned
    # the tops lean where the wind blows when the angle is positive
    theta = sway_angle_rad(WIND, plants.phase_rad, t2)
    k = int(np.argmax(theta))
    top = b_v[k * n_v + int(np.argmax(plants.template.vertices[:, 2]))] - plants.base_world[k]
    assert top[:2] @ wind_dir[:2] == pytest.approx(plants.height_m[k] * np.sin(theta[k]))
    assert theta[k] > np.radians(15)
    # without a time (no time line) or without wind: upright, whatever the time
    upright = plant_rotations(plants.yaw_rad, plants.phase_rad, None, t2)
    assert np.allclose(upright[:, 2], [0, 0, 1])
    assert np.allclose(plant_rotations(plants.yaw_rad, plants.phase_rad, WIND, None), upright)


def test_plants_stand_on_the_terrain_inside_the_extent(tmp_path):
    p = vegetation_project(flat=False, density_per_m2=0.5)
    ground = _ground(p, tmp_path)
    (plants,) = place_vegetation(p, tmp_path, ground)
    z = ground.heightfield.height_at_clamped(plants.base_world[:, 0], plants.base_world[:, 1])
    np.testing.assert_allclose(plants.base_world[:, 2], z, atol=1e-12)
    assert np.ptp(z) > 0.3  # a hilly terrain
    # a seeded process: the same seed places the same plants, another seed others
    again = place_vegetation(p, tmp_path, ground)[0]
    assert np.array_equal(again.base_world, plants.base_world)
    other = replace(p, scene=replace(p.scene, vegetation=replace(p.scene.vegetation, seed=9)))
    assert not np.array_equal(place_vegetation(other, tmp_path, ground)[0].base_world[:5],
                              plants.base_world[:5])
    # the Poisson count: about density × area (the targets' clear circles are small)
    assert abs(len(plants) - 0.5 * 1600) < 4 * np.sqrt(0.5 * 1600) + 60


@pytest.mark.parametrize("kind", list(m.PLANT_KINDS))
def test_built_in_kinds_have_unit_height_and_crown(kind):
    t = builtin_template(kind)
    assert t.vertices[:, 2].max() == pytest.approx(1.0)
    assert 2 * np.hypot(t.vertices[:, 0], t.vertices[:, 1]).max() == pytest.approx(1.0, abs=0.02)
    assert t.faces.max() < len(t.vertices) and len(t.material_index) == len(t.faces)


def test_compare_measures_a_canopy_against_the_surface_or_the_bare_earth(tmp_path, capsys):
    from designer.cli.main import main
    from tests.evaluate.helpers import write_cloud

    p = vegetation_project(density_per_m2=0.05)
    path = write_project_file(p, tmp_path / "p")
    ground = _ground(p, tmp_path)
    for at_time, flag in ((None, []), (1.3, ["--at-time", "1.3"])):
        (v, f), = vegetation_mesh_world(p, path.parent, ground, at_time)
        tri = v[f]
        normal = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
        up = normal[:, 2] / np.linalg.norm(normal, axis=1) > 0.5
        canopy = tri[up].mean(axis=1)  # points on the plants' upper faces
        write_cloud(tmp_path / "canopy.ply", canopy)
        expected = {"dsm": 0.0, "dtm": float(np.median(canopy[:, 2] - (ORIGIN[2] + 0.25)))}
        assert expected["dtm"] > 0.5
        for surface in ("dtm", "dsm"):
            out = tmp_path / f"{surface}{at_time}"
            assert main(["compare", str(tmp_path / "canopy.ply"), str(path), "-o", str(out),
                         "--no-targets", "--surface", surface, *flag]) == 0
            capsys.readouterr()
            summary = json.loads((out / "summary.json").read_text())
            assert summary["inputs"]["surface"] == surface
            assert summary["distances"]["median"] == pytest.approx(expected[surface], abs=1e-4)
    dtm = true_surface(p, path.parent, "dtm", with_targets=False)
    dsm = true_surface(p, path.parent, "dsm", with_targets=False)
    assert len(dsm[0]) > len(dtm[0]) and np.array_equal(dsm[0][:len(dtm[0])], dtm[0])


def test_vegetation_survives_a_round_trip_through_the_file(tmp_path):
    p = vegetation_project()
    veg = replace(p.scene.vegetation, plants=(
        *p.scene.vegetation.plants, m.PlantGroup(2.0, "grass-tuft"),
        m.PlantGroup(0.01, None, mesh="tree.ply", height_m=6.0)))
    (tmp_path / "tree.ply").write_text(
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
        "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
        "end_header\n-1 0 0\n1 0 0\n0 0 3\n3 0 1 2\n")
    p = replace(p, scene=replace(p.scene, vegetation=veg))
    back = load_project(write_project_file(p, tmp_path))
    assert back.scene.vegetation == p.scene.vegetation
    # a mesh plant is scaled to the group's height, its crown with it
    ground = _ground(p, tmp_path)
    mesh_plants = place_vegetation(back, tmp_path, ground)[2]
    assert len(mesh_plants) and mesh_plants.kind == "tree.ply"
    np.testing.assert_allclose(mesh_plants.height_m, 6.0)
    np.testing.assert_allclose(mesh_plants.crown_m, 4.0)
    # defaults: a bare <vegetation><plants kind density/></vegetation>
    text = re.sub(r"<vegetation .*</vegetation>",
                  '<vegetation><plants kind="tree" density-per-m2="0.01"/></vegetation>',
                  (tmp_path / "project.xml").read_text(), flags=re.S)
    (tmp_path / "project.xml").write_text(text)
    veg = load_project(tmp_path / "project.xml").scene.vegetation
    assert veg == m.Vegetation((m.PlantGroup(0.01, "tree"),))


@pytest.mark.parametrize(("edit", "needle", "words"), [
    (lambda t: t.replace('density-per-m2="0.25"', 'density-per-m2="0"'), "<plants",
     "density-per-m2"),
    (lambda t: t.replace('density-per-m2="0.25"', 'density-per-m2="500"'), "<plants",
     "density-per-m2"),
    (lambda t: t.replace('kind="shrub"', 'kind="cactus"'), "<plants", "unknown plant kind"),
    (lambda t: t.replace('kind="shrub"', ''), "<plants", "exactly one of kind and mesh"),
    (lambda t: t.replace('kind="shrub"', 'kind="shrub" mesh="x.ply"'), "<plants",
     "exactly one of kind and mesh"),
    (lambda t: t.replace('kind="shrub"', 'mesh="no_such_tree.ply"'), "<plants",
     "no_such_tree"),
    (lambda t: t.replace('height-m="1.0"', 'height-m="-1"'), "<plants", "height-m"),
    (lambda t: t.replace('height-sd-m="0.15"', 'height-sd-m="5"'), "<plants", "height-sd-m"),
    (lambda t: t.replace(' height-m="1.0"', '').replace('height-sd-m="0.15"',
                                                         'height-sd-m="1.5"'), "<plants",
     "to 1 m (the mean height)"),
    (lambda t: t.replace('crown-m="1.2"', 'crown-m="0"'), "<plants", "crown-m"),
    (lambda t: t.replace('albedo-rgb="0.8 0.04 0.04"', 'albedo-rgb="green"'), "<plants",
     "albedo-rgb"),
    (lambda t: t.replace('amplitude-deg="20.0"', 'amplitude-deg="90"'), "<wind",
     "amplitude-deg"),
    (lambda t: t.replace('gust-period-s="4.0"', 'gust-period-s="0"'), "<wind",
     "gust-period-s"),
    (lambda t: t.replace('direction-deg="60.0"', 'direction-deg="360"'), "<wind",
     "direction-deg"),
    (lambda t: t.replace('seed="5"', 'seed="-1"'), "<vegetation", "seed"),
    (lambda t: t.replace('clearance-m="0.3"', 'clearance-m="-1"'), "<vegetation",
     "clearance-m"),
])
def test_bad_vegetation_values_are_located_one_line_errors(tmp_path, edit, needle, words):
    assert_located_error(vegetation_project(), tmp_path, edit, needle, words,
                         any_located=True)


def test_on_a_mesh_terrain_plants_stand_on_the_nearest_vertex():
    from types import SimpleNamespace

    from designer.scene.vegetation import ground_heights_m

    rng = np.random.default_rng(2)
    v = np.column_stack([rng.uniform(0, 10, (500, 2)), rng.uniform(0, 3, 500)])
    ground = SimpleNamespace(heightfield=None, terrain=SimpleNamespace(vertices_world=v))
    x, y = rng.uniform(0, 10, 50), rng.uniform(0, 10, 50)
    d = (v[None, :, 0] - x[:, None]) ** 2 + (v[None, :, 1] - y[:, None]) ** 2
    np.testing.assert_array_equal(ground_heights_m(ground, x, y), v[np.argmin(d, axis=1), 2])


def test_plants_keep_out_of_buildings(tmp_path):
    E0, N0, _ = ORIGIN
    p = vegetation_project(density_per_m2=1.0)
    house = m.Building("house", tuple(m.PathPoint(E0 + x, N0 + y) for x, y in
                                      ((3, 3), (13, 3), (13, 11), (3, 11))), "flat", 6.0)
    ground = _ground(p, tmp_path)
    free = place_vegetation(p, tmp_path, ground)[0]
    built = replace(p, scene=replace(p.scene, buildings=(house,)))
    (plants,) = place_vegetation(built, tmp_path, ground)
    reach = plants.crown_m / 2 + np.sin(np.radians(WIND.amplitude_deg)) * plants.height_m
    x, y = plants.base_world[:, 0] - E0, plants.base_world[:, 1] - N0
    dx = np.maximum(np.maximum(3 - x, x - 13), 0)
    dy = np.maximum(np.maximum(3 - y, y - 11), 0)
    assert (np.hypot(dx, dy) >= reach - 1e-9).all()
    assert len(free) - len(plants) > 80  # about 10 m × 8 m and a margin of plants dropped


def test_designer_check_names_the_vegetation(tmp_path):
    from designer.project.summary import summary_line

    p = vegetation_project(density_per_m2=0.25)
    line = summary_line("x.xml", p)
    assert "1 plant group (about 400 plants, wind)" in line  # 0.25 per m² on 40 × 40 m
    assert "plant" not in summary_line("x.xml", replace(p, scene=replace(p.scene,
                                                                         vegetation=None)))
