import importlib.util
import struct
import subprocess
import sys

import numpy as np
import pytest

from designer.core.heightfield import Heightfield
from designer.errors import DesignerError
from designer.scene.mesh import TerrainMesh, heightfield_to_mesh, load_mesh, write_mesh_ply
from designer.scene.terrain import procedural_terrain
from tests.synthetic import ORIGIN_WORLD

UTM = ORIGIN_WORLD


def utm_terrain(seed=1, relief=15.0):
    return procedural_terrain(40.0, 30.0, 0.5, relief, seed=seed, x0_m=UTM[0] + 0.123456789,
                              y0_m=UTM[1] + 0.987654321, base_height_m=UTM[2])


# --------------------------------------------------------------------------- from a grid
def test_mesh_vertices_are_the_grid_nodes():
    hf = utm_terrain()
    mesh = heightfield_to_mesh(hf)
    ny, nx = hf.heights_m.shape
    assert mesh.vertices_world.shape == (nx * ny, 3)
    assert mesh.faces.shape == (2 * (nx - 1) * (ny - 1), 3)
    assert mesh.vertices_world.dtype == np.float64
    rng = np.random.default_rng(0)
    for i, j in zip(rng.integers(0, ny, 20), rng.integers(0, nx, 20), strict=True):
        x, y, z = mesh.vertices_world[i * nx + j]
        assert x == hf.x0_m + j * hf.dx_m and y == hf.y0_m + i * hf.dy_m
        assert z == hf.heights_m[i, j]


def test_winding_gives_upward_normals_even_on_steep_terrain():
    hf = procedural_terrain(20.0, 20.0, 0.25, 30.0, seed=5, roughness=1.0)  # very steep
    mesh = heightfield_to_mesh(hf)
    n = mesh.face_normals()
    assert np.all(n[:, 2] > 0)
    assert np.allclose(np.linalg.norm(n, axis=1), 1.0)


def test_flat_grid_normals_are_exactly_up():
    hf = Heightfield(UTM[0], UTM[1], 1.0, 2.0, np.full((3, 4), 7.0))
    n = heightfield_to_mesh(hf).face_normals()
    np.testing.assert_allclose(n, np.tile([0.0, 0.0, 1.0], (len(n), 1)), atol=1e-15)


def test_mesh_matches_bilinear_surface_on_a_tilted_plane():
    # On a plane the triangulation and the bilinear surface coincide everywhere.
    ny, nx = 5, 6
    jj, ii = np.meshgrid(np.arange(nx), np.arange(ny))
    hf = Heightfield(10.0, 20.0, 2.0, 3.0, 1.0 + 0.3 * jj * 2.0 - 0.1 * ii * 3.0)
    mesh = heightfield_to_mesh(hf)
    p = mesh.vertices_world[mesh.faces]
    centroids = p.mean(axis=1)
    np.testing.assert_allclose(centroids[:, 2], hf.height_at(centroids[:, 0], centroids[:, 1]),
                               atol=1e-12)


def test_uv_spans_unit_square_east_and_north():
    hf = utm_terrain()
    mesh = heightfield_to_mesh(hf)
    x0, x1, y0, y1 = hf.extent_m
    v = mesh.vertices_world
    np.testing.assert_allclose(mesh.uv[:, 0], (v[:, 0] - x0) / (x1 - x0), atol=1e-12)
    np.testing.assert_allclose(mesh.uv[:, 1], (v[:, 1] - y0) / (y1 - y0), atol=1e-12)
    assert mesh.uv.min() == 0.0 and mesh.uv.max() == 1.0
    tiled = heightfield_to_mesh(hf, uv_tiles=(4, 3))
    np.testing.assert_allclose(tiled.uv, mesh.uv * [4, 3])


def test_terrain_mesh_validates_its_arrays():
    v = np.zeros((3, 3))
    with pytest.raises(DesignerError, match=r"outside 0\.\.2"):
        TerrainMesh(v, np.array([[0, 1, 3]]), np.zeros((3, 2)))
    with pytest.raises(DesignerError, match="uv must have shape"):
        TerrainMesh(v, np.array([[0, 1, 2]]), np.zeros((2, 2)))
    with pytest.raises(DesignerError, match="faces must be integers"):
        TerrainMesh(v, np.array([[0.0, 1.0, 2.0]]), np.zeros((3, 2)))


# --------------------------------------------------------------------------- PLY
def read_header(path):
    data = path.read_bytes()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    return data[:end].decode("ascii").splitlines(), end


def test_ply_round_trip_keeps_utm_float64_and_uv(tmp_path):
    mesh = heightfield_to_mesh(utm_terrain())
    path = tmp_path / "terrain.ply"
    write_mesh_ply(mesh, path)
    back = load_mesh(path)
    assert back.vertices_world.dtype == np.float64
    assert np.abs(back.vertices_world - mesh.vertices_world).max() < 1e-6
    np.testing.assert_array_equal(back.vertices_world, mesh.vertices_world)  # doubles: exact
    np.testing.assert_array_equal(back.faces, mesh.faces)
    np.testing.assert_array_equal(back.uv, mesh.uv)
    assert list(tmp_path.iterdir()) == [path]  # atomic: no temporary left behind


def test_ply_layout_is_binary_double_with_s_t(tmp_path):
    mesh = heightfield_to_mesh(utm_terrain())
    path = tmp_path / "t.ply"
    write_mesh_ply(mesh, path)
    header, start = read_header(path)
    assert header[:2] == ["ply", "format binary_little_endian 1.0"]
    assert [h for h in header if h.startswith("property")] == [
        "property double x", "property double y", "property double z",
        "property double s", "property double t",
        "property list uchar int vertex_indices"]
    # Decode the body independently of any PLY library.
    n = len(mesh.vertices_world)
    body = np.frombuffer(path.read_bytes(), dtype="<f8", count=5 * n, offset=start)
    np.testing.assert_array_equal(body.reshape(n, 5)[:, :3], mesh.vertices_world)
    first_face = path.read_bytes()[start + 40 * n: start + 40 * n + 13]
    assert struct.unpack("<B3i", first_face) == (3, *mesh.faces[0])


def test_ply_with_origin_stores_local_coordinates_and_loads_world(tmp_path):
    mesh = heightfield_to_mesh(utm_terrain())
    path = tmp_path / "local.ply"
    origin = np.array([500000.0, 5000000.0, 250.0])
    write_mesh_ply(mesh, path, origin=origin)
    header, start = read_header(path)
    assert "comment designer_origin_m 500000.0 5000000.0 250.0" in header
    stored = np.frombuffer(path.read_bytes(), dtype="<f8", count=5, offset=start)
    np.testing.assert_allclose(stored[:3], mesh.vertices_world[0] - origin, atol=1e-9)
    assert np.abs(stored[:3]).max() < 100  # small numbers: safe for float32 readers
    back = load_mesh(path)
    assert np.abs(back.vertices_world - mesh.vertices_world).max() < 1e-6


def test_ply_texture_file_adds_face_texcoords(tmp_path):
    mesh = heightfield_to_mesh(utm_terrain(), uv_tiles=(2, 2))
    path = tmp_path / "tex.ply"
    write_mesh_ply(mesh, path, texture_file="grass.png")
    header, _ = read_header(path)
    assert "comment TextureFile grass.png" in header
    assert header[-2] == "property list uchar double texcoord"
    from plyfile import PlyData
    face = PlyData.read(str(path))["face"].data
    np.testing.assert_array_equal(np.stack(face["texcoord"]).reshape(-1, 3, 2),
                                  mesh.uv[mesh.faces])
    back = load_mesh(path)
    np.testing.assert_array_equal(back.uv, mesh.uv)


def test_ply_with_only_face_texcoords_splits_vertices(tmp_path):
    # Two triangles sharing an edge whose shared corners have different UVs per face.
    path = tmp_path / "seam.ply"
    header = ("ply\nformat ascii 1.0\nelement vertex 4\nproperty double x\n"
              "property double y\nproperty double z\nelement face 2\n"
              "property list uchar int vertex_indices\nproperty list uchar float texcoord\n"
              "end_header\n")
    body = ("0 0 0\n1 0 0\n1 1 0\n0 1 0\n"
            "3 0 1 2 6 0 0 1 0 1 1\n"
            "3 0 2 3 6 0.5 0 0.6 0.6 0 0.5\n")
    path.write_text(header + body)
    mesh = load_mesh(path)
    assert len(mesh.vertices_world) == 6
    corners = mesh.vertices_world[mesh.faces]
    np.testing.assert_array_equal(corners[:, :, :2],
                                  [[[0, 0], [1, 0], [1, 1]], [[0, 0], [1, 1], [0, 1]]])
    np.testing.assert_allclose(mesh.uv[mesh.faces][1], [[0.5, 0], [0.6, 0.6], [0, 0.5]],
                               atol=1e-7)


def test_ascii_ply_with_quads_and_no_uv_gets_planar_uv(tmp_path):
    path = tmp_path / "quad.ply"
    path.write_text("ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\n"
                    "property float y\nproperty float z\nelement face 1\n"
                    "property list uchar int vertex_index\nend_header\n"
                    "0 0 1\n2 0 1\n2 4 1\n0 4 1\n4 0 1 2 3\n")
    mesh = load_mesh(path)
    np.testing.assert_array_equal(mesh.faces, [[0, 1, 2], [0, 2, 3]])
    np.testing.assert_array_equal(mesh.uv, [[0, 0], [1, 0], [1, 1], [0, 1]])
    assert np.all(mesh.face_normals()[:, 2] > 0)


# --------------------------------------------------------------------------- OBJ, STL
def test_obj_with_texture_coordinates_keeps_float64(tmp_path):
    path = tmp_path / "t.obj"
    path.write_text(
        "# exported\nmtllib t.mtl\no terrain\n"
        "v 500000.123456 5000000.654321 310.000001\n"
        "v 500001.123456 5000000.654321 310.5\n"
        "v 500001.123456 5000001.654321 311.0\n"
        "v 500000.123456 5000001.654321 310.2\n"
        "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\nusemtl ground\n"
        "f 1/1/1 2/2/1 3/3/1 4/4/1\n")
    mesh = load_mesh(path)
    assert abs(mesh.vertices_world[0, 0] - 500000.123456) < 1e-9
    assert abs(mesh.vertices_world[0, 1] - 5000000.654321) < 1e-9
    np.testing.assert_array_equal(mesh.faces, [[0, 1, 2], [0, 2, 3]])
    np.testing.assert_array_equal(mesh.uv, [[0, 0], [1, 0], [1, 1], [0, 1]])


def test_obj_negative_indices_and_no_uv(tmp_path):
    path = tmp_path / "n.obj"
    path.write_text("v 0 0 0\nv 4 0 0\nv 4 2 1\nf -3 -2 -1\n")
    mesh = load_mesh(path)
    np.testing.assert_array_equal(mesh.faces, [[0, 1, 2]])
    np.testing.assert_array_equal(mesh.uv, [[0, 0], [1, 0], [1, 1]])


def test_obj_bad_index_names_the_file(tmp_path):
    path = tmp_path / "bad.obj"
    path.write_text("v 0 0 0\nv 1 0 0\nf 1 2 9\n")
    with pytest.raises(DesignerError, match=r"bad\.obj: face refers to vertex 9"):
        load_mesh(path)


def stl_binary(triangles):
    data = bytearray(b"\0" * 80) + struct.pack("<I", len(triangles))
    for tri in triangles:
        data += struct.pack("<12fH", 0, 0, 1, *np.ravel(tri), 0)
    return bytes(data)


def test_binary_stl_merges_shared_corners(tmp_path):
    square = [[[0, 0, 1], [1, 0, 1], [1, 1, 2]], [[0, 0, 1], [1, 1, 2], [0, 1, 1]]]
    path = tmp_path / "sq.stl"
    path.write_bytes(stl_binary(square))
    mesh = load_mesh(path)
    assert len(mesh.vertices_world) == 4
    np.testing.assert_array_equal(mesh.vertices_world[mesh.faces], square)
    assert np.all(mesh.face_normals()[:, 2] > 0)


def test_ascii_stl(tmp_path):
    path = tmp_path / "a.stl"
    path.write_text("solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0.5\n"
                    "vertex 2 0 0.5\nvertex 2 2 0.5\nendloop\nendfacet\nendsolid t\n")
    mesh = load_mesh(path)
    np.testing.assert_array_equal(mesh.vertices_world[mesh.faces[0]],
                                  [[0, 0, 0.5], [2, 0, 0.5], [2, 2, 0.5]])


@pytest.mark.parametrize(
    ("name", "content", "message"),
    [
        ("missing.ply", None, "does not exist"),
        ("empty.ply", b"", "is empty"),
        ("model.fbx", b"x", "unsupported format '.fbx'"),
        ("garbage.ply", b"not a ply file\n", "is not a valid PLY"),
        ("points.ply", b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n"
                       b"property float y\nproperty float z\nend_header\n0 0 0\n",
         "has no faces"),
        ("garbage.stl", b"GIF89a" + b"\0" * 10, "neither binary nor ASCII STL"),
        ("text.obj", b"v 0 0 zero\n", "line 1: cannot parse"),
    ],
)
def test_bad_mesh_files_are_one_line_designer_errors(tmp_path, name, content, message):
    path = tmp_path / name
    if content is not None:
        path.write_bytes(content)
    with pytest.raises(DesignerError) as info:
        load_mesh(path)
    assert name in str(info.value)
    assert message in str(info.value)
    assert "\n" not in str(info.value)


# --------------------------------------------------------------------------- Blender
BLENDER_IMPORT = """
import sys, bpy
bpy.ops.wm.read_factory_settings(use_empty=True)
bpy.ops.wm.ply_import(filepath=sys.argv[1])
me = bpy.context.selected_objects[0].data
uv = me.uv_layers[0].data
loop_vertex = [l.vertex_index for l in me.loops]
print(len(me.vertices), len(me.polygons), len(me.uv_layers))
for k in (0, 1, 2, 5):
    print(loop_vertex[k], *uv[k].uv, *me.vertices[loop_vertex[k]].co)
"""


@pytest.mark.blender
@pytest.mark.skipif(importlib.util.find_spec("bpy") is None, reason="bpy not installed")
def test_blender_reads_local_ply_with_s_t_as_uv(tmp_path):
    hf = procedural_terrain(8.0, 6.0, 1.0, 2.0, seed=2, x0_m=UTM[0], y0_m=UTM[1],
                            base_height_m=UTM[2])
    mesh = heightfield_to_mesh(hf)
    path = tmp_path / "local.ply"
    write_mesh_ply(mesh, path, origin=UTM)
    out = subprocess.run([sys.executable, "-c", BLENDER_IMPORT, str(path)],
                         capture_output=True, text=True, check=True, timeout=300)
    lines = [line.split() for line in out.stdout.splitlines() if line[:1].isdigit()]
    assert [int(t) for t in lines[0]] == [len(mesh.vertices_world), len(mesh.faces), 1]
    for row in lines[1:]:
        k = int(row[0])
        u, v, x, y, z = (float(t) for t in row[1:])
        np.testing.assert_allclose([u, v], mesh.uv[k], atol=1e-6)
        np.testing.assert_allclose([x, y, z], mesh.vertices_world[k] - UTM, atol=1e-4)
