"""Signed point-to-mesh distances, exact in float64, for clouds of any size.

World frame: X east, Y north, Z up, metres. A distance is positive on the side the
mesh normals point to — above the terrain for designer's meshes, whose triangles wind
counter-clockwise seen from above — and negative below.

* **Exact**: every point gets the distance to its truly nearest triangle (a bounding
  volume hierarchy searched with exact pruning, not an approximation or an octree
  level), computed in float64 around a local origin (the centre of the mesh's bounding
  box), so UTM-sized coordinates lose nothing: the error is ~1e-15 of the mesh size.
* **Sign on open meshes**: from the pseudo-normal of the nearest feature (Bærentzen &
  Aanæs 2005): the face normal inside a triangle, the sum of the adjacent faces' normals
  on an edge, the angle-weighted normal sum at a vertex. It needs no watertight mesh;
  corners that appear more than once with bit-identical coordinates are welded first.
* **Memory-bounded**: points are processed in chunks (``chunk`` points at a time, a few
  hundred bytes each); only the (N,) result is allocated for the whole cloud.

``signed_distances`` is the public entry point; :func:`build_mesh_index` prepares a
mesh once when several clouds are compared with it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from designer.core.bounds import column_bounds
from designer.errors import DesignerError

#: points per chunk: ~100 bytes of temporary memory each
DEFAULT_CHUNK = 1 << 20


@dataclass(frozen=True, eq=False)
class MeshIndex:
    """A triangle mesh prepared for distance queries (build with :func:`build_mesh_index`).

    ``origin_world`` (3,) is subtracted from every coordinate; ``triangles`` (M, 9) holds
    the local corners (a, b, c) of each triangle in BVH order and ``face_order`` (M,) the
    index of each in the original face list.
    """

    origin_world: np.ndarray
    triangles: np.ndarray
    face_order: np.ndarray
    box: np.ndarray
    link: np.ndarray
    normals_face: np.ndarray
    neighbours: np.ndarray
    crowded_edge_normals: np.ndarray
    normals_vertex: np.ndarray
    corner_vertex: np.ndarray

    @property
    def n_faces(self) -> int:
        return len(self.face_order)

    @property
    def bounds_local(self) -> tuple[np.ndarray, np.ndarray]:
        return self.box[0, :3], self.box[0, 3:]


def _mesh_arrays(mesh) -> tuple[np.ndarray, np.ndarray]:
    for name in ("vertices_world", "vertices"):  # TerrainMesh, ReferenceMesh
        if hasattr(mesh, name) and hasattr(mesh, "faces"):
            mesh = (getattr(mesh, name), mesh.faces)
            break
    try:
        vertices, faces = mesh
    except (TypeError, ValueError):
        raise TypeError("mesh must be a TerrainMesh, a MeshIndex or (vertices, faces)") from None
    vertices = np.asarray(vertices, dtype=np.float64)
    faces = np.asarray(faces)
    if vertices.ndim != 2 or vertices.shape[1] != 3 or faces.ndim != 2 or faces.shape[1] != 3:
        raise DesignerError(f"mesh needs (N, 3) vertices and (M, 3) faces, got "
                            f"{vertices.shape} and {faces.shape}")
    if len(faces) == 0:
        raise DesignerError("mesh has no triangles")
    if not np.issubdtype(faces.dtype, np.integer) or faces.min() < 0 \
            or faces.max() >= len(vertices):
        raise DesignerError(f"mesh faces must index vertices 0..{len(vertices) - 1}")
    if not np.isfinite(vertices).all():
        raise DesignerError("mesh has NaN or infinite vertex coordinates")
    return vertices, faces


def build_mesh_index(mesh) -> MeshIndex:
    """Prepare ``mesh`` (TerrainMesh, ReferenceMesh or (vertices (N, 3), faces (M, 3)),
    world coordinates) for queries."""
    from designer.evaluate import _bvh, _topology

    vertices, faces = _mesh_arrays(mesh)
    lo, hi = column_bounds(vertices)
    origin = 0.5 * (lo + hi)
    local = np.ascontiguousarray(vertices - origin)
    codes = _bvh.centroid_codes(local, faces.astype(np.int64, copy=False), lo - origin,
                                _morton_scale(lo, hi))
    # 16 bits per axis (cells of 1/65536 of the mesh's extent) order the triangles as
    # well as 21 and sort in three passes instead of four
    codes >>= np.uint64(15)
    order = _bvh.radix_argsort(codes)
    codes = codes[order]
    faces = np.ascontiguousarray(faces[order], dtype=np.int64)
    triangles, normals_face, angle = _topology.face_geometry(local, faces)
    neighbours, crowded = _topology.edge_neighbours(faces, normals_face, len(local))
    # Meshes whose corners were split (per-corner UVs or normals, STL) look cut open
    # along the seams: weld the vertices of such boundary edges when their coordinates
    # are bit-identical, so the pseudo-normals see the true surface. Clean meshes pay
    # only for their real boundary.
    open_edges = neighbours == -1
    if open_edges.any():
        ends = np.concatenate([faces[open_edges], faces[np.roll(open_edges, 1, axis=1)]])
        canonical = _topology.weld_vertices(local, np.unique(ends))
        if (canonical != np.arange(len(local))).any():
            faces = canonical[faces]
            neighbours, crowded = _topology.edge_neighbours(faces, normals_face, len(local))
    normals_vertex = _topology.vertex_normals(faces, normals_face, angle, len(local))
    box, link = _bvh.build_bvh(codes, triangles)
    return MeshIndex(
        origin_world=origin, triangles=triangles, face_order=order,
        box=box, link=link,
        normals_face=normals_face, neighbours=neighbours, crowded_edge_normals=crowded,
        normals_vertex=normals_vertex, corner_vertex=faces)


def _morton_scale(lo, hi) -> np.ndarray:
    """Cells per metre of the Morton grid: one scale for all axes, so a flat terrain's
    hierarchy splits across the ground, never into thin height layers."""
    return np.full(3, ((1 << 21) - 1) / max(float(np.max(hi - lo)), 1e-12))


def signed_distances(
    points_world,
    mesh,
    *,
    max_distance: float | None = None,
    chunk: int = DEFAULT_CHUNK,
    return_faces: bool = False,
):
    """Signed distance (N,) in metres from each point (N, 3) world to ``mesh``.

    ``mesh`` is a TerrainMesh, a ReferenceMesh, a :class:`MeshIndex` or (vertices (V, 3),
    faces (M, 3)), all in world coordinates. Points farther than ``max_distance`` (m) get NaN — the
    search stops there, which is faster. With ``return_faces`` also returns the index
    (N,) of each point's nearest face (−1 where NaN). ``points_world`` may be a memory
    map: it is read ``chunk`` rows at a time and never copied whole.
    """
    from designer.evaluate import _bvh

    index = mesh if isinstance(mesh, MeshIndex) else build_mesh_index(mesh)
    points = np.asarray(points_world)
    if points.ndim != 2 or points.shape[1] != 3:
        raise DesignerError(f"points must have shape (N, 3), got {points.shape}")
    if max_distance is not None and not max_distance >= 0:
        raise DesignerError(f"max distance {max_distance} m: give a value >= 0")
    if chunk < 1:
        raise ValueError("chunk must be >= 1")
    limit_d2 = np.inf if max_distance is None else float(max_distance) ** 2
    lo, hi = index.bounds_local
    scale = _morton_scale(lo, hi)
    n = len(points)
    dist = np.empty(n)
    faces = np.empty(n, dtype=np.int64) if return_faces else None
    for s in range(0, n, chunk):
        block = np.ascontiguousarray(points[s:s + chunk], dtype=np.float64)
        if not np.isfinite(block).all():
            bad = s + int(np.flatnonzero(~np.isfinite(block).all(axis=1))[0])
            raise DesignerError(f"point {bad} has a NaN or infinite coordinate")
        part = slice(s, s + len(block))
        _bvh.query(block, index.origin_world, lo, scale, index.triangles, index.box,
                   index.link, limit_d2, index.normals_face, index.neighbours,
                   index.crowded_edge_normals, index.normals_vertex, index.corner_vertex,
                   dist[part], None if faces is None else faces[part])
    if faces is not None:  # BVH order -> the mesh's own face numbers
        faces[:] = np.where(faces >= 0, index.face_order[np.maximum(faces, 0)], -1)
    return (dist, faces) if return_faces else dist
