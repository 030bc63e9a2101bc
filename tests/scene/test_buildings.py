"""Building geometry without rendering: closed outward meshes with the right volumes and
roof heights, standing on the lowest terrain under them, in the DSM and not the DTM; the
file round trip; and every bad value a located one-line error."""

from __future__ import annotations

import re
from dataclasses import replace

import numpy as np
import pytest

from designer.project import load_project, read_project
from designer.project import model as m
from designer.scene.buildings import (
    FLOOR,
    ROOF,
    build_buildings,
    building_meshes_world,
    extruded_mesh,
    mesh_volume_m3,
    roof_height_m,
    triangulate_polygon,
)
from designer.scene.surfaces import true_surface
from designer.survey.mesh_occlusion import MeshOccluder
from tests.synthetic import assert_located_error, write_project_file
from tests.world.building_helpers import building_project, rectangle

E0, N0 = 500000.0, 5200000.0


def _building(roof, xy, eave=6.0, ridge=9.0, **kw) -> m.Building:
    return m.Building("b", tuple(m.PathPoint(E0 + x, N0 + y) for x, y in xy), roof, eave,
                      None if roof == "flat" else ridge, **kw)


RECT = ((0, 0), (20, 0), (20, 10), (0, 10))


def _closed_and_outward(v: np.ndarray, f: np.ndarray) -> None:
    edges = np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]])
    directed = set(map(tuple, edges))
    assert len(directed) == len(edges), "an edge is used twice in one direction"
    assert all((b, a) in directed for a, b in directed), "the mesh has a boundary"
    assert mesh_volume_m3(v, f) > 0


@pytest.mark.parametrize(("roof", "volume"), [
    ("flat", 20 * 10 * 6),
    ("gable", 20 * 10 * 6 + 20 * 10 * 3 / 2),
    ("hip", 20 * 10 * 6 + 3 * 10 / 6 * (3 * 20 - 10)),  # h·w/6·(3L − w)
])
@pytest.mark.parametrize("clockwise", [False, True])
def test_extruded_buildings_are_closed_with_their_volume(roof, volume, clockwise):
    xy = RECT[::-1] if clockwise else RECT
    mesh = extruded_mesh(_building(roof, xy), 400.0)
    _closed_and_outward(mesh.vertices_world, mesh.faces)
    assert mesh_volume_m3(mesh.vertices_world, mesh.faces) == pytest.approx(volume, rel=1e-12)
    z = mesh.vertices_world[:, 2]
    assert z.min() == 400.0 and z.max() == 400.0 + (6.0 if roof == "flat" else 9.0)
    normals = np.cross(*(mesh.vertices_world[mesh.faces[:, k]]
                         - mesh.vertices_world[mesh.faces[:, 0]] for k in (1, 2)))
    assert (normals[mesh.face_kind == ROOF, 2] > 0).all()
    assert (normals[mesh.face_kind == FLOOR, 2] < 0).all()


def test_roof_heights_at_known_points():
    base = 100.0
    gable, hip = _building("gable", RECT), _building("hip", RECT)
    x = E0 + np.array([10.0, 10.0, 1.0, 0.5, 19.0])
    y = N0 + np.array([5.0, 7.5, 5.0, 5.0, 9.0])
    np.testing.assert_allclose(roof_height_m(gable, base, x, y),
                               base + np.array([9.0, 7.5, 9.0, 9.0, 6.6]))
    # hip: every plane has the gable's pitch, 3 m over 5 m; the ridge ends 5 m in
    np.testing.assert_allclose(roof_height_m(hip, base, x, y),
                               base + np.array([9.0, 7.5, 6.6, 6.3, 6.6]))
    assert np.isnan(roof_height_m(hip, base, E0 - 1.0, N0 + 5.0))
    # the ridge follows ridge-direction-deg: across the short side, a gable over 10 m
    across = _building("gable", RECT, ridge_direction_deg=0.0)
    assert roof_height_m(across, base, E0 + 10.0, N0 + 1.0) == pytest.approx(base + 9.0)
    assert roof_height_m(across, base, E0 + 19.0, N0 + 1.0) == pytest.approx(base + 6.3)
    # the mesh's top is the same surface: a ray down at (x, y) meets it at that height
    for b in (gable, hip, across):
        mesh = extruded_mesh(b, base)
        occ = MeshOccluder(mesh.vertices_world, mesh.faces)
        for xi, yi in zip(x, y, strict=True):
            z = float(roof_height_m(b, base, xi, yi))
            above = occ.occluded([[xi, yi, z - 1e-4]], [[xi, yi, 500.0]], tol_m=0.0)
            below = occ.occluded([[xi, yi, z + 1e-4]], [[xi, yi, 500.0]], tol_m=0.0)
            assert above[0] and not below[0]


def test_a_square_hip_roof_is_a_pyramid_and_an_l_shaped_flat_roof_is_closed():
    pyramid = extruded_mesh(_building("hip", ((0, 0), (10, 0), (10, 10), (0, 10))), 0.0)
    assert len(pyramid.vertices_world) == 9
    assert mesh_volume_m3(pyramid.vertices_world, pyramid.faces) == pytest.approx(
        600 + 100 * 3 / 3)
    ell = ((0, 0), (10, 0), (10, 4), (4, 4), (4, 10), (0, 10))
    assert len(triangulate_polygon(np.array(ell, float))) == 4
    mesh = extruded_mesh(_building("flat", ell), 0.0)
    _closed_and_outward(mesh.vertices_world, mesh.faces)
    assert mesh_volume_m3(mesh.vertices_world, mesh.faces) == pytest.approx((100 - 36) * 6)


def test_buildings_stand_on_the_lowest_terrain_under_them(tmp_path):
    from designer.scene.build import build_scene

    p = building_project()
    scene = build_scene(p, tmp_path)
    for b, built in zip(p.scene.buildings, build_buildings(p, tmp_path, scene), strict=True):
        xs = np.linspace(min(q.X for q in b.footprint), max(q.X for q in b.footprint), 41)
        ys = np.linspace(min(q.Y for q in b.footprint), max(q.Y for q in b.footprint), 41)
        ground = scene.heightfield.height_at(*np.meshgrid(xs, ys))
        assert ground.min() >= built.base_z_m - 1e-9
        assert ground.min() - built.base_z_m < 0.01  # the low point is sampled
        assert built.vertices_world[:, 2].max() == pytest.approx(
            built.base_z_m + (b.ridge_height_m or b.eave_height_m))


def test_buildings_are_in_the_dsm_and_not_in_the_dtm(tmp_path):
    path = write_project_file(building_project(), tmp_path)
    p = read_project(path)
    dtm_v, _ = true_surface(p, tmp_path, "dtm", with_targets=False)
    dsm_v, _ = true_surface(p, tmp_path, "dsm", with_targets=False)
    meshes = building_meshes_world(p, tmp_path, _ground(p, tmp_path))
    assert len(meshes) == 3
    assert len(dsm_v) == len(dtm_v) + sum(len(v) for v, _ in meshes)
    tower_top = meshes[0][0][:, 2].max()
    assert dtm_v[:, 2].max() < p.origin.H0 + 1 < tower_top - 13 and dsm_v[:, 2].max() == tower_top


def _ground(p, base):
    from designer.scene.build import build_heightfield, build_terrain_mesh
    from designer.scene.surfaces import Ground

    hf = build_heightfield(p.scene.terrain, base, p.crs)
    origin = np.array([p.origin.E0, p.origin.N0, p.origin.H0])
    return Ground(hf, build_terrain_mesh(p.scene.terrain, hf, base, origin))


def test_a_mesh_file_building_is_placed_turned_and_standing(tmp_path):
    cube = tmp_path / "shed.obj"
    cube.write_text("v -1 -2 0\nv 1 -2 0\nv 1 2 0\nv -1 2 0\nv -1 -2 3\nv 1 -2 3\nv 1 2 3\n"
                    "v -1 2 3\nf 1 4 3\nf 1 3 2\nf 5 6 7\nf 5 7 8\nf 1 2 6\nf 1 6 5\n"
                    "f 2 3 7\nf 2 7 6\nf 3 4 8\nf 3 8 7\nf 4 1 5\nf 4 5 8\n")
    p = building_project()
    shed = m.Building("shed", file="shed.obj", position=m.PathPoint(E0 - 10, N0 + 10),
                      heading_deg=90.0)
    p = replace(p, scene=replace(p.scene, buildings=(shed,)))
    path = write_project_file(p, tmp_path)
    assert read_project(path).scene.buildings == (shed,)
    (built,) = build_buildings(load_project(path), tmp_path, _ground(p, tmp_path))
    v = built.vertices_world
    # +Y (4 m long) turned to the east: 4 m along X, 2 m along Y
    np.testing.assert_allclose(np.ptp(v, axis=0), [4.0, 2.0, 3.0], atol=1e-9)
    np.testing.assert_allclose(v[:, :2].mean(axis=0), [E0 - 10, N0 + 10], atol=1e-9)
    assert (built.face_kind == ROOF).sum() == 2


def test_buildings_survive_a_round_trip_through_the_file(tmp_path):
    p = building_project()
    p = replace(p, scene=replace(p.scene, buildings=p.scene.buildings + (
        replace(p.scene.buildings[1], id="across", ridge_direction_deg=0.0,
                footprint=rectangle(-14.0, -4.0, -8.0, 0.0)),)))
    assert read_project(write_project_file(p, tmp_path)) == p


def _sub(pattern, repl):
    return lambda t: re.sub(pattern, repl, t, count=1)


TOWER_FP = "500004.5 5199999.0 500005.5 5199999.0 500005.5 5200001.0 500004.5 5200001.0"


@pytest.mark.parametrize(("edit", "needle", "words"), [
    (_sub('roof="flat"', 'roof="dome"'), 'roof="dome"', "unknown roof"),
    (_sub('eave-height-m="15.0"', 'eave-height-m="0"'), 'id="tower"', "eave-height-m"),
    (_sub('eave-height-m="15.0"', 'eave-height-m="-3"'), 'id="tower"', "eave-height-m"),
    (_sub(' ridge-height-m="5.0"', ""), 'id="gable"', "needs ridge-height-m"),
    (_sub('ridge-height-m="5.0"', 'ridge-height-m="2.0"'), 'id="gable"', "above eave-height"),
    (_sub('eave-height-m="15.0"', 'eave-height-m="15.0" ridge-height-m="18"'), 'id="tower"',
     "flat roof has no ridge"),
    (_sub('ridge-height-m="5.0"', 'ridge-height-m="5.0" ridge-direction-deg="30"'),
     'id="gable"', "along no side"),
    (_sub('roof="hip" ', 'roof="hip" ridge-direction-deg="0" '), 'id="hip"', "longer side"),
    (lambda t: t.replace(TOWER_FP, "500004.5 5199999.0 500005.5 5199999.0"), TOWER_FP[:20],
     "at least three"),
    (lambda t: t.replace(TOWER_FP, TOWER_FP + " 500004.0"), "<footprint>500004.5",
     "even count"),
    (lambda t: t.replace(TOWER_FP, "500004.5 5199999.0 500005.5 5200001.0 500005.5 5199999.0 "
                         "500004.5 5200001.0"), "<footprint>500004.5", "crosses itself"),
    (lambda t: t.replace(TOWER_FP, "500004.5 5199999.0 500005.5 5199999.0 500006.5 "
                         "5199999.0"), "<footprint>500004.5", "zero area"),
    (lambda t: t.replace(TOWER_FP, "500004.5 5199999.0 500055.5 5199999.0 500005.5 "
                         "5200001.0"), "<footprint>500004.5", "outside the terrain"),
    (lambda t: t.replace(TOWER_FP, TOWER_FP.replace("500004.5 5200001.0", "500004.5 5200001.0 "
                                                    "500004.5 5200001.0")),
     "<footprint>500004.5", "repeats"),
    (lambda t: t.replace("499996.0 5199995.5 500002.0 5199995.5 500002.0 5199998.5",
                         "499996.0 5199995.5 500002.0 5199995.5 500003.0 5199998.5"),
     "<footprint>499996.0 5199995.5", "rectangular footprint"),
    (lambda t: t.replace(TOWER_FP, "500005.0 5199999.0 500007.0 5199999.0 500007.0 5200001.0 "
                         "500005.0 5200001.0"), "<footprint>500005.0", "lies under building"),
    (_sub('<building id="hip"', '<building id="tower"'), '<building id="tower" roof="hip"',
     "used twice"),
    (_sub(r'(<building id="tower"[^>]*)>', r'\1 file="x.ply">'), 'id="tower"', "exactly one"),
    (_sub(r'<building id="tower"[^>]*>\s*<footprint>[^<]*</footprint>\s*</building>',
          '<building id="tower" file="no_such_shed.ply" X="500005" Y="5200000"/>'),
     "no_such_shed", "no_such_shed"),
    (_sub(r'<building id="tower"[^>]*>\s*<footprint>[^<]*</footprint>\s*</building>',
          '<building id="tower" file="x.ply" Y="5200000"/>'), 'file="x.ply"', "needs X and Y"),
])
def test_bad_building_values_are_located_one_line_errors(tmp_path, edit, needle, words):
    assert_located_error(building_project(), tmp_path, edit, needle, words)
