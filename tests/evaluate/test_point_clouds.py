import numpy as np
import pytest
from plyfile import PlyData, PlyElement

from designer.errors import DesignerError
from designer.evaluate import read_point_cloud
from designer.export.colmap_read import read_points3d

UTM = np.array([512000.123456, 5406000.654321, 312.5])


def sample(n=500, seed=0):
    rng = np.random.default_rng(seed)
    xyz = UTM + rng.uniform(-50, 50, (n, 3))
    rgb = rng.integers(0, 256, (n, 3)).astype(np.uint8)
    normals = rng.normal(size=(n, 3)).astype(np.float32)
    return xyz, rgb, normals


@pytest.mark.parametrize("text", [False, True])
def test_ply_with_colours_and_normals(tmp_path, text):
    xyz, rgb, normals = sample()
    v = np.empty(len(xyz), dtype=[("x", "f8"), ("y", "f8"), ("z", "f8"), ("nx", "f4"),
                                  ("ny", "f4"), ("nz", "f4"), ("red", "u1"), ("green", "u1"),
                                  ("blue", "u1")])
    for i, c in enumerate("xyz"):
        v[c] = xyz[:, i]
    for i, c in enumerate(("nx", "ny", "nz")):
        v[c] = normals[:, i]
    for i, c in enumerate(("red", "green", "blue")):
        v[c] = rgb[:, i]
    path = tmp_path / "cloud.ply"
    PlyData([PlyElement.describe(v, "vertex")], text=text).write(str(path))
    cloud = read_point_cloud(path)
    tol = 1e-9 if not text else 1e-6  # plyfile's ASCII writer keeps ~17 digits
    assert np.max(np.abs(cloud.xyz - xyz)) < tol
    assert np.array_equal(cloud.rgb, rgb)
    assert np.allclose(cloud.normals, normals, atol=1e-6)


def test_ply_written_by_pyvista(tmp_path):
    pv = pytest.importorskip("pyvista")
    xyz, rgb, _ = sample()
    local = xyz - UTM
    poly = pv.PolyData(local)
    poly["RGB"] = rgb
    path = tmp_path / "pyvista.ply"
    poly.save(str(path), texture="RGB", binary=True)
    cloud = read_point_cloud(path, offset=UTM)
    # VTK keeps float32 coordinates here: local values, so ~4 µm
    assert np.max(np.abs(cloud.xyz - xyz)) < 1e-5
    assert np.array_equal(cloud.rgb, rgb)


@pytest.mark.parametrize("suffix", [".las", ".laz"])
def test_las_and_laz_written_by_laspy(tmp_path, suffix):
    laspy = pytest.importorskip("laspy")
    if suffix == ".laz":
        pytest.importorskip("lazrs")
    xyz, rgb, _ = sample()
    header = laspy.LasHeader(point_format=3, version="1.2")
    header.scales = np.array([0.0001, 0.0001, 0.0001])
    header.offsets = np.floor(UTM)
    las = laspy.LasData(header)
    las.x, las.y, las.z = xyz[:, 0], xyz[:, 1], xyz[:, 2]
    las.red, las.green, las.blue = (rgb.astype(np.uint16) * 257).T
    path = tmp_path / f"cloud{suffix}"
    las.write(str(path))
    cloud = read_point_cloud(path)
    assert np.max(np.abs(cloud.xyz - xyz)) <= 0.5e-4 + 1e-9  # the file's 0.1 mm scale
    assert np.array_equal(cloud.rgb, rgb)


def test_text_clouds_with_and_without_headers(tmp_path):
    xyz, rgb, _ = sample(50)
    rows = [f"{x!r},{y!r},{z!r},{r},{g},{b}" for (x, y, z), (r, g, b) in zip(xyz, rgb,
                                                                             strict=True)]
    (tmp_path / "a.csv").write_text("X,Y,Z,R,G,B\n" + "\n".join(rows) + "\n")
    (tmp_path / "b.txt").write_text("//X,Y,Z,R,G,B\n" + "\n".join(rows) + "\n")  # CloudCompare
    (tmp_path / "c.xyz").write_text("# comment\n" + "\n".join(r.replace(",", " ") for r in rows))
    for name in ("a.csv", "b.txt", "c.xyz"):
        cloud = read_point_cloud(tmp_path / name)
        assert np.array_equal(cloud.xyz, xyz), name
    assert np.array_equal(read_point_cloud(tmp_path / "a.csv").rgb, rgb)
    # named columns in another order, semicolons, extra text column
    body = "\n".join(f"p{i};{z!r};{x!r};{y!r}" for i, (x, y, z) in enumerate(xyz))
    (tmp_path / "d.csv").write_text("name;height;easting;northing\n" + body)
    assert np.array_equal(read_point_cloud(tmp_path / "d.csv").xyz, xyz)
    (tmp_path / "e.csv").write_text("id;h;a;b\n" + body)
    with pytest.raises(DesignerError, match="no x column"):
        read_point_cloud(tmp_path / "e.csv")
    cloud = read_point_cloud(tmp_path / "e.csv", columns=("a", "b", "h"))
    assert np.array_equal(cloud.xyz, xyz)
    offset = np.array([1.0, 2.0, 3.0])
    assert np.array_equal(read_point_cloud(tmp_path / "c.xyz", offset=offset).xyz, xyz + offset)


def test_colmap_points_text_and_binary(tmp_path):
    pycolmap = pytest.importorskip("pycolmap")
    xyz, rgb, _ = sample(30)
    rec = pycolmap.Reconstruction()
    for p, c in zip(xyz, rgb, strict=True):
        rec.add_point3D(p, pycolmap.Track(), c)
    (tmp_path / "bin").mkdir()
    (tmp_path / "txt").mkdir()
    rec.write_binary(str(tmp_path / "bin"))
    rec.write_text(str(tmp_path / "txt"))
    for folder in ("bin", "txt"):
        pts = read_points3d(tmp_path / folder)
        order = np.argsort(pts.ids)
        assert np.max(np.abs(pts.xyz[order] - xyz)) < 1e-6  # text keeps ~15 digits
        assert np.array_equal(pts.rgb[order], rgb)
        assert len(read_point_cloud(tmp_path / folder)) == 30


@pytest.mark.parametrize(("content", "name", "message"), [
    (b"", "empty.ply", "is empty"),
    (b"ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nend_header\n1\n2\n",
     "nox.ply", "no x, y, z"),
    (b"not a ply at all", "bad.ply", "not a valid PLY"),
    (b"1 2\n3 4\n", "two.xyz", "rows have 2 columns"),
    (b"1 2 3\n4 5 x\n", "junk.xyz", "cannot read"),
    (b"\x00\x01\x02", "bin.txt", "not a text file"),
    (b"abc", "cloud.e57", "unknown format"),
    (b"not las", "bad.las", "cannot be read as LAS"),
])
def test_unreadable_files_give_one_line_errors(tmp_path, content, name, message):
    path = tmp_path / name
    path.write_bytes(content)
    if name.endswith(".las"):
        pytest.importorskip("laspy")
    with pytest.raises(DesignerError, match=message) as info:
        read_point_cloud(path)
    assert "\n" not in str(info.value) and name in str(info.value)


def test_missing_file_and_bad_offset(tmp_path):
    with pytest.raises(DesignerError, match="does not exist"):
        read_point_cloud(tmp_path / "nope.ply")
    (tmp_path / "a.xyz").write_text("1 2 3\n")
    with pytest.raises(DesignerError, match="offset"):
        read_point_cloud(tmp_path / "a.xyz", offset=(1, 2))
