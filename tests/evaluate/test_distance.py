import numpy as np
import pytest

from designer.core.heightfield import Heightfield
from designer.errors import DesignerError
from designer.evaluate import build_mesh_index, signed_distances
from designer.scene.mesh import heightfield_to_mesh
from tests.evaluate.reference import brute_distances, exact_point_triangle_distance
from tests.synthetic import ORIGIN_WORLD


def random_mesh(rng, n_vertices=30, n_faces=40):
    vertices = rng.normal(size=(n_vertices, 3))
    faces = rng.integers(0, n_vertices, size=(n_faces, 3))
    return vertices, faces


def special_points(rng, vertices, faces):
    """Points on vertices, on edges, beyond edges and off faces, plus random ones."""
    a, b, c = (vertices[faces[:, k]] for k in range(3))
    t = rng.uniform(size=(len(faces), 1))
    n = np.cross(b - a, c - a)
    n /= np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-300)
    return np.vstack([
        vertices,                                  # on vertices
        a + t * (b - a),                           # on edges
        a + (1 + t) * (b - a),                     # beyond edges, on their line
        b + 0.3 * (b - a) + 0.2 * n,               # beyond vertices, off the plane
        (a + b + c) / 3 + 0.1 * n,                 # above faces
        (a + b + c) / 3 - 0.1 * n,                 # below faces
        rng.normal(size=(60, 3)) * 2,              # anywhere
    ])


@pytest.mark.parametrize("seed", range(6))
def test_distances_equal_brute_force_on_random_meshes(seed):
    rng = np.random.default_rng(seed)
    vertices, faces = random_mesh(rng)
    points = special_points(rng, vertices, faces)
    d = signed_distances(points, (vertices, faces))
    assert np.max(np.abs(np.abs(d) - brute_distances(points, vertices, faces))) < 1e-12


def test_degenerate_and_near_degenerate_triangles():
    rng = np.random.default_rng(7)
    a = rng.normal(size=(30, 3))
    b = rng.normal(size=(30, 3))
    kinds = [
        np.stack([a, a, b], 1),                              # two equal corners
        np.stack([a, a, a], 1),                              # a single point
        np.stack([a, b, (a + b) / 2], 1),                    # collinear
        np.stack([a, b, (a + b) / 2 + 1e-9 * rng.normal(size=(30, 3))], 1),  # sliver
        np.stack([a, b, a + 1e-7 * rng.normal(size=(30, 3))], 1),          # tiny angle
    ]
    tri = np.concatenate(kinds)
    vertices = tri.reshape(-1, 3)
    faces = np.arange(len(vertices)).reshape(-1, 3)
    points = np.vstack([rng.normal(size=(40, 3)) * 1.5, a[:5], (a[:5] + b[:5]) / 2])
    d = signed_distances(points, (vertices, faces))
    assert np.all(np.isfinite(d))
    exact = [min(exact_point_triangle_distance(p, *t) for t in tri) for p in points]
    assert np.max(np.abs(np.abs(d) - exact)) < 1e-9


def terrain(rng, n=30, spacing=1.0, x0=0.0, y0=0.0, h0=0.0):
    z = np.cumsum(np.cumsum(rng.normal(0, 0.05, (n, n)), 0), 1) + h0
    return Heightfield(x0, y0, spacing, spacing, z)


def surface_height(hf, x, y):
    fx, fy = (x - hf.x0_m) / hf.dx_m, (y - hf.y0_m) / hf.dy_m
    j = np.clip(fx.astype(int), 0, hf.heights_m.shape[1] - 2)
    i = np.clip(fy.astype(int), 0, hf.heights_m.shape[0] - 2)
    u, w = fx - j, fy - i
    z = hf.heights_m
    sw, se, ne, nw = z[i, j], z[i, j + 1], z[i + 1, j + 1], z[i + 1, j]
    return np.where(u >= w, sw + u * (se - sw) + w * (ne - se), sw + w * (nw - sw) + u * (ne - nw))


def test_signs_on_an_open_terrain_follow_above_and_below():
    """Every point's sign says whether it is above the surface — also where the nearest
    feature is an edge or a vertex of a rough, open terrain."""
    rng = np.random.default_rng(3)
    hf = terrain(rng, n=25, spacing=0.5)
    mesh = heightfield_to_mesh(hf)
    n = 20000
    x = rng.uniform(0, 12, n)
    y = rng.uniform(0, 12, n)
    z = surface_height(hf, x, y) + rng.normal(0, 0.3, n)
    # points right above/below vertices and edge midpoints, where pseudo-normals matter
    vx, vy = np.meshgrid(np.arange(1, 24) * 0.5, np.arange(1, 24) * 0.5)
    extra_x = np.concatenate([vx.ravel(), vx.ravel() + 0.25])
    extra_y = np.concatenate([vy.ravel(), vy.ravel()])
    extra_z = surface_height(hf, extra_x, extra_y) + rng.choice([-1, 1], len(extra_x)) * 0.05
    pts = np.column_stack([np.concatenate([x, extra_x]), np.concatenate([y, extra_y]),
                           np.concatenate([z, extra_z])])
    d = signed_distances(pts, mesh)
    truth = np.sign(pts[:, 2] - surface_height(hf, pts[:, 0], pts[:, 1]))
    assert np.array_equal(np.sign(d), truth)


def test_points_beyond_the_boundary_take_the_boundary_faces_side():
    flat = Heightfield(0.0, 0.0, 1.0, 1.0, np.zeros((5, 5)))
    mesh = heightfield_to_mesh(flat)
    pts = np.array([[-1.0, 2.0, 0.5], [-1.0, 2.0, -0.5], [6.0, 6.0, 1.0], [2.0, -3.0, -2.0]])
    d = signed_distances(pts, mesh)
    expected = np.array([np.hypot(1, 0.5), -np.hypot(1, 0.5), np.sqrt(4 + 4 + 1),
                         -np.sqrt(9 + 4)])
    assert np.allclose(d, expected, atol=1e-14)


def test_split_vertices_are_welded_for_the_sign():
    """A mesh whose faces do not share vertices (as from STL or per-corner UVs) gives
    the same signed distances as the shared-vertex mesh."""
    rng = np.random.default_rng(5)
    mesh = heightfield_to_mesh(terrain(rng, n=15, spacing=0.5))
    corners = mesh.vertices_world[mesh.faces].reshape(-1, 3)
    split_faces = np.arange(len(corners)).reshape(-1, 3)
    pts = np.column_stack([rng.uniform(0, 7, 5000), rng.uniform(0, 7, 5000),
                           rng.normal(0, 0.5, 5000)])
    shared = signed_distances(pts, mesh)
    split = signed_distances(pts, (corners, split_faces))
    assert np.array_equal(shared, split)


def test_utm_offsets_lose_nothing():
    """The same geometry at ORIGIN_WORLD size gives the same distances as near the origin."""
    rng = np.random.default_rng(6)
    hf = terrain(rng, n=20, spacing=0.25)
    local = heightfield_to_mesh(hf)
    pts = np.column_stack([rng.uniform(0, 4.75, 3000), rng.uniform(0, 4.75, 3000),
                           rng.normal(0, 0.01, 3000) + 0.0])
    pts[:, 2] += surface_height(hf, pts[:, 0], pts[:, 1])
    d_local = signed_distances(pts, local)
    d_utm = signed_distances(pts + ORIGIN_WORLD, (local.vertices_world + ORIGIN_WORLD, local.faces))
    assert np.max(np.abs(d_local - d_utm)) < 1e-9
    # float32 at these coordinates would be off by decimetres; float64 by nanometres
    assert np.max(np.abs(d_local)) > 1e-3


def test_max_distance_chunks_and_faces():
    rng = np.random.default_rng(8)
    vertices, faces = random_mesh(rng, 30, 50)
    pts = rng.normal(size=(2000, 3)) * 3
    index = build_mesh_index((vertices, faces))
    full, nearest = signed_distances(pts, index, return_faces=True)
    assert np.array_equal(signed_distances(pts, index, chunk=77), full)
    limited = signed_distances(pts, index, max_distance=0.5)
    far = np.abs(full) > 0.5
    assert np.isnan(limited[far]).all() and np.array_equal(limited[~far], full[~far])
    # the reported face is at the reported distance
    ref = brute_distances(pts[:50], vertices, faces[nearest[:50]][:, None].reshape(-1, 3)[:1])
    assert ref.shape == (50,)
    for p, f, dist in zip(pts[:50], nearest[:50], full[:50], strict=True):
        assert abs(brute_distances(p[None], vertices, faces[f][None])[0] - abs(dist)) < 1e-12


def test_bad_input_is_a_one_line_error():
    with pytest.raises(DesignerError, match="shape"):
        signed_distances(np.zeros((3, 2)), (np.eye(3), np.array([[0, 1, 2]])))
    with pytest.raises(DesignerError, match="NaN"):
        signed_distances(np.array([[0.0, np.nan, 0.0]]), (np.eye(3), np.array([[0, 1, 2]])))
    with pytest.raises(DesignerError, match="index vertices"):
        signed_distances(np.zeros((1, 3)), (np.eye(3), np.array([[0, 1, 3]])))
    with pytest.raises(DesignerError, match="max distance"):
        signed_distances(np.zeros((1, 3)), (np.eye(3), np.array([[0, 1, 2]])), max_distance=-1)


def _reference_neighbours(faces, normal):
    """The face across each edge, -1 on a boundary, -2 - e for edge e of 3+ faces
    (numbered here by first appearance), and the normal sums of those edges."""
    by_edge: dict[tuple[int, int], list[int]] = {}
    for f, face in enumerate(faces):
        for k in range(3):
            a, b = int(face[k]), int(face[(k + 1) % 3])
            by_edge.setdefault((min(a, b), max(a, b)), []).append(3 * f + k)
    neighbour = np.full((len(faces), 3), -1)
    crowded = {}
    for key, slots in by_edge.items():
        if len(slots) == 2:
            neighbour.flat[slots[0]], neighbour.flat[slots[1]] = slots[1] // 3, slots[0] // 3
        elif len(slots) >= 3:
            crowded[key] = slots
    return neighbour, crowded


@pytest.mark.parametrize("seed", range(4))
def test_edge_neighbours_match_a_dictionary_of_edges(seed):
    from designer.evaluate import _topology

    rng = np.random.default_rng(seed)
    # a small vertex pool: many edges shared by two, three or more faces, some faces
    # with a repeated corner
    vertices = rng.normal(size=(12, 3))
    faces = rng.integers(0, 12, size=(60, 3))
    _tri, normal, _angle = _topology.face_geometry(vertices, faces)
    neighbour, sums = _topology.edge_neighbours(faces, normal, len(vertices))
    expected, crowded = _reference_neighbours(faces, normal)
    assert crowded, "the random mesh should have edges of three or more faces"
    plain = neighbour >= -1
    assert np.array_equal(neighbour[plain], expected[plain])
    # every edge of 3+ faces: the same number on all its faces, whose normals it sums
    assert len(sums) == len(crowded)
    seen = set()
    for slots in crowded.values():
        numbers = {int(neighbour.flat[s]) for s in slots}
        assert len(numbers) == 1 and numbers.pop() <= -2
        e = -2 - int(neighbour.flat[slots[0]])
        seen.add(e)
        assert np.allclose(sums[e], normal[[s // 3 for s in slots]].sum(axis=0), atol=1e-15)
    assert seen == set(range(len(crowded)))
    assert (neighbour < -1).sum() == sum(len(s) for s in crowded.values())


def test_a_fin_on_a_sheet_takes_the_sign_of_the_summed_normals():
    # two triangles of a flat sheet and a vertical fin share the edge (0, 1)
    vertices = np.array([[0.0, 0, 0], [1, 0, 0], [0.5, 1, 0], [0.5, -1, 0], [0.5, 0, 1]])
    faces = np.array([[0, 1, 2], [1, 0, 3], [0, 1, 4]])
    points = np.array([[0.5, 0.0, 0.2], [0.5, -0.3, -0.1], [1.3, 0.0, 0.1], [0.5, 0.4, 0.3]])
    d = signed_distances(points, (vertices, faces))
    assert np.allclose(np.abs(d), brute_distances(points, vertices, faces), atol=1e-12)
    index = build_mesh_index((vertices, faces))
    assert len(index.crowded_edge_normals) == 1
    # the pseudo-normal of the edge is the sum of the three face normals
    n = np.array([[0, 0, 1.0], [0, 0, 1.0], [0, -1.0, 0]])
    assert np.allclose(index.crowded_edge_normals[0], n.sum(axis=0))
