"""Triangle meshes of the terrain: from a height field, from PLY/OBJ/STL files, to PLY.

World frame: X east, Y north, Z up, metres, float64. Triangles wind counter-clockwise
seen from above, so their normals ``(v1 − v0) × (v2 − v0)`` point up.

Texture coordinates (u, v) follow OpenGL/Blender: u grows east, v grows north, and
(0, 0) is the **bottom-left** of the texture image. An image's top row therefore lies
along the north edge: a texture viewed as a picture is a north-up map.

PLY files written here are binary little-endian with ``double`` x, y, z (so UTM-sized
coordinates survive to well below 1e-6 m) and per-vertex ``double s, t`` texture
coordinates: the names Blender's PLY importer reads as UVs (checked with Blender 5.0,
which ignores ``u, v`` and ``texture_u, texture_v``), as do trimesh and three.js.
CloudCompare's PLY filter reads UVs only from a per-face ``texcoord`` list, and only
when the header names a ``comment TextureFile NAME`` (the layout Metashape writes too);
:func:`write_mesh_ply` adds both when given ``texture_file``. CloudCompare loads the
double coordinates and offers its global shift for UTM-sized values.
"""

from __future__ import annotations

import os
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from designer.atomic import atomic_path
from designer.core.heightfield import Heightfield
from designer.errors import DesignerError

MESH_SUFFIXES = (".ply", ".obj", ".stl")
#: header comment recording the origin subtracted from the stored coordinates
ORIGIN_COMMENT = "designer_origin_m"


@dataclass(frozen=True, eq=False)
class TerrainMesh:
    """A triangle mesh in world coordinates with one (u, v) per vertex.

    ``vertices_world`` (N, 3) float64 metres; ``faces`` (M, 3) int64 vertex indices,
    counter-clockwise seen from outside (from above, for terrain); ``uv`` (N, 2) float64
    texture coordinates (see the module docstring for their orientation).
    """

    vertices_world: np.ndarray
    faces: np.ndarray
    uv: np.ndarray

    def __post_init__(self) -> None:
        v = np.asarray(self.vertices_world, dtype=np.float64)
        f = np.asarray(self.faces)
        uv = np.asarray(self.uv, dtype=np.float64)
        if v.ndim != 2 or v.shape[1] != 3 or len(v) < 3:
            raise DesignerError(f"mesh vertices must have shape (N >= 3, 3), got {v.shape}")
        if f.ndim != 2 or f.shape[1] != 3 or len(f) < 1 or not np.issubdtype(f.dtype, np.integer):
            raise DesignerError(f"mesh faces must be integers of shape (M >= 1, 3), got "
                                f"{f.shape} {f.dtype}")
        if uv.shape != (len(v), 2):
            raise DesignerError(f"mesh uv must have shape ({len(v)}, 2), got {uv.shape}")
        if f.min() < 0 or f.max() >= len(v):
            raise DesignerError(f"mesh faces index vertices outside 0..{len(v) - 1}")
        if not (np.all(np.isfinite(v)) and np.all(np.isfinite(uv))):
            raise DesignerError("mesh has NaN or infinite vertex coordinates or uv")
        object.__setattr__(self, "vertices_world", v)
        object.__setattr__(self, "faces", f.astype(np.int64, copy=False))
        object.__setattr__(self, "uv", uv)

    def face_normals(self) -> np.ndarray:
        """(M, 3) unit normals ``(v1 − v0) × (v2 − v0)``, world frame (up for terrain)."""
        p = self.vertices_world[self.faces]
        # Differences first: subtracting UTM-sized coordinates keeps full precision.
        n = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
        return n / np.linalg.norm(n, axis=1, keepdims=True)


# --------------------------------------------------------------------------- from a grid
def heightfield_to_mesh(hf: Heightfield, uv_tiles: tuple[float, float] = (1, 1)) -> TerrainMesh:
    """Mesh a height field: its nodes as vertices, two triangles per grid cell.

    Vertex ``k = i·nx + j`` is node (row i, column j). Cell (i, j) with corners
    SW = (i, j), SE = (i, j+1), NE = (i+1, j+1), NW = (i+1, j) becomes the triangles
    (SW, SE, NE) and (SW, NE, NW), both counter-clockwise from above (normals up). The
    mesh equals the bilinear surface at the nodes; inside a cell it differs by at most
    ``|z_SW − z_SE + z_NE − z_NW| / 4``.

    ``u`` runs 0 → ``uv_tiles[0]`` west → east and ``v`` 0 → ``uv_tiles[1]`` south →
    north. The project keeps the default (1, 1) — UV spanning [0, 1] over the extent —
    and applies texture tiling in the renderer's material (a mapping scale), so the mesh
    does not depend on the texture chosen; other values bake the tiling into the UVs for
    viewers without material tiling.
    """
    z = hf.heights_m
    ny, nx = z.shape
    x = hf.x0_m + hf.dx_m * np.arange(nx)
    y = hf.y0_m + hf.dy_m * np.arange(ny)
    xx, yy = np.meshgrid(x, y)
    vertices = np.column_stack([xx.ravel(), yy.ravel(), z.ravel()])
    uu, vv = np.meshgrid(np.arange(nx) / (nx - 1), np.arange(ny) / (ny - 1))
    uv = np.column_stack([uu.ravel() * uv_tiles[0], vv.ravel() * uv_tiles[1]])

    sw = (np.arange(ny - 1)[:, None] * nx + np.arange(nx - 1)[None, :]).ravel()
    se, nw = sw + 1, sw + nx
    ne = nw + 1
    faces = np.empty((2 * len(sw), 3), dtype=np.int64)
    faces[0::2] = np.column_stack([sw, se, ne])
    faces[1::2] = np.column_stack([sw, ne, nw])
    return TerrainMesh(vertices, faces, uv)


def planar_uv(vertices_world: np.ndarray) -> np.ndarray:
    """(N, 2) UVs mapping the XY bounding box of the vertices onto [0, 1]² (u east, v north)."""
    xy = np.asarray(vertices_world, dtype=np.float64)[:, :2]
    lo, hi = xy.min(axis=0), xy.max(axis=0)
    span = np.where(hi > lo, hi - lo, 1.0)
    return (xy - lo) / span


# --------------------------------------------------------------------------- PLY writing
def write_mesh_ply(
    mesh: TerrainMesh,
    path: str | os.PathLike,
    origin: np.ndarray | None = None,
    *,
    texture_file: str | None = None,
) -> None:
    """Write ``mesh`` as a binary little-endian PLY, atomically.

    Vertices are ``double x, y, z`` in world coordinates, or, when ``origin`` (3,) is
    given, in local coordinates ``world − origin`` with the origin recorded in a
    ``comment designer_origin_m E N H`` header line (17 significant digits) that
    :func:`load_mesh` adds back. Per-vertex UVs are ``double s, t``; faces are
    ``list uchar int vertex_indices``. With ``texture_file`` (a file name relative to the
    PLY) the header also gets ``comment TextureFile NAME`` and each face a
    ``list uchar double texcoord`` of its three corners' (s, t), for CloudCompare,
    MeshLab and Metashape.
    """
    v = mesh.vertices_world
    comments = ["designer terrain mesh: X east, Y north, Z up, metres"]
    if origin is not None:
        origin = np.asarray(origin, dtype=np.float64).reshape(3)
        v = v - origin
        comments.append(f"{ORIGIN_COMMENT} " + " ".join(repr(float(c)) for c in origin))
    else:
        comments.append("coordinates: world")
    if texture_file is not None:
        if any(c in texture_file for c in "\r\n"):
            raise DesignerError("PLY texture file name must be a single line")
        comments.append(f"TextureFile {texture_file}")
    if len(v) >= 2**31:
        raise DesignerError(f"mesh has {len(v)} vertices; PLY int indices hold < 2**31")

    vertex = np.empty(len(v), dtype=[("x", "<f8"), ("y", "<f8"), ("z", "<f8"),
                                     ("s", "<f8"), ("t", "<f8")])
    vertex["x"], vertex["y"], vertex["z"] = v[:, 0], v[:, 1], v[:, 2]
    vertex["s"], vertex["t"] = mesh.uv[:, 0], mesh.uv[:, 1]
    face_fields = [("n", "u1"), ("vertex_indices", "<i4", (3,))]
    if texture_file is not None:
        face_fields += [("m", "u1"), ("texcoord", "<f8", (6,))]
    face = np.empty(len(mesh.faces), dtype=face_fields)
    face["n"] = 3
    face["vertex_indices"] = mesh.faces
    if texture_file is not None:
        face["m"] = 6
        face["texcoord"] = mesh.uv[mesh.faces].reshape(-1, 6)

    header = ["ply", "format binary_little_endian 1.0"]
    header += [f"comment {c}" for c in comments]
    header += [f"element vertex {len(vertex)}"]
    header += [f"property double {name}" for name in ("x", "y", "z", "s", "t")]
    header += [f"element face {len(face)}", "property list uchar int vertex_indices"]
    if texture_file is not None:
        header.append("property list uchar double texcoord")
    header.append("end_header")
    with atomic_path(path) as tmp, open(tmp, "wb") as fh:
        fh.write(("\n".join(header) + "\n").encode("ascii"))
        fh.write(vertex.tobytes())
        fh.write(face.tobytes())


# --------------------------------------------------------------------------- loading
def load_mesh(path: str | os.PathLike) -> TerrainMesh:
    """Read a triangle mesh from PLY, OBJ or STL into world coordinates (float64).

    * PLY (any PLY flavour, via plyfile): per-vertex UVs from ``s, t``, ``u, v`` or
      ``texture_u, texture_v``, else from a per-face ``texcoord`` list; a
      ``designer_origin_m`` header comment is added back to the coordinates.
    * OBJ: ``v``/``vt``/``f`` records; vertices used with several ``vt`` are split.
    * STL (binary or ASCII): identical corners are merged into shared vertices. Binary
      STL stores float32, which resolves only ~0.5 m at UTM northings: keep STL terrain
      in local coordinates.

    Polygons are split into triangle fans. Meshes without texture coordinates get
    :func:`planar_uv`. Errors raise :class:`DesignerError` naming the file.
    """
    path = Path(path)
    if not path.is_file():
        raise DesignerError(f"mesh file {path} does not exist; check the terrain path")
    suffix = path.suffix.lower()
    if suffix not in MESH_SUFFIXES:
        raise DesignerError(f"mesh file {path}: unsupported format '{path.suffix}'; "
                            "use PLY (.ply), OBJ (.obj) or STL (.stl)")
    if path.stat().st_size == 0:
        raise DesignerError(f"mesh file {path} is empty; export the mesh again")
    reader = {".ply": _read_ply, ".obj": _read_obj, ".stl": _read_stl}[suffix]
    try:
        vertices, faces, uv = reader(path)
    except DesignerError:
        raise
    except (ValueError, IndexError, KeyError, OSError, UnicodeDecodeError) as exc:
        detail = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        raise DesignerError(f"mesh file {path} cannot be read as {suffix[1:].upper()} "
                            f"({detail}); export it again") from None
    if len(faces) == 0:
        raise DesignerError(f"mesh file {path} has no faces; a terrain needs a triangle mesh")
    if uv is None:
        uv = planar_uv(vertices)
    try:
        return TerrainMesh(vertices, faces, uv)
    except DesignerError as exc:
        raise DesignerError(f"mesh file {path}: {exc}") from None


def _fan(polygons: list[list[int]]) -> list[list[int]]:
    return [[p[0], p[k], p[k + 1]] for p in polygons for k in range(1, len(p) - 1)]


def _split_by_uv(positions: np.ndarray, corner_v: np.ndarray, corner_uv: np.ndarray):
    """Vertices, (M, 3) faces and per-vertex UVs from per-corner position indices and UVs.

    A position used with several UVs becomes several vertices.
    """
    key = np.column_stack([corner_v.astype(np.float64), corner_uv])
    unique, inverse = np.unique(key, axis=0, return_inverse=True)
    return positions[unique[:, 0].astype(np.int64)], inverse.reshape(-1, 3), unique[:, 1:]


def _read_ply(path: Path):
    from plyfile import PlyData, PlyElementParseError, PlyHeaderParseError

    try:
        try:
            # Fast, memory-mapped path for all-triangle files; plyfile checks the lengths.
            ply = PlyData.read(str(path), known_list_len={"face": {
                "vertex_indices": 3, "vertex_index": 3, "texcoord": 6}})
        except PlyElementParseError:
            ply = PlyData.read(str(path), mmap=False)
    except (PlyHeaderParseError, PlyElementParseError) as exc:
        raise DesignerError(f"mesh file {path} is not a valid PLY ({exc}); "
                            "export it again") from None
    names = [e.name for e in ply.elements]
    if "vertex" not in names:
        raise DesignerError(f"mesh file {path} has no 'vertex' element; is it a PLY mesh?")
    vert = ply["vertex"].data
    fields = vert.dtype.names
    positions = np.column_stack([np.asarray(vert[c], dtype=np.float64) for c in "xyz"])
    origin = origin_from_ply_comments(path, ply.comments)
    if origin is not None:
        positions = positions + origin
    if "face" not in names:
        return positions, np.empty((0, 3), np.int64), None
    face = ply["face"].data
    index_name = next((n for n in ("vertex_indices", "vertex_index") if n in face.dtype.names),
                      None)
    if index_name is None:
        raise DesignerError(f"mesh file {path}: faces have no vertex_indices list")
    faces = _face_array(face[index_name])

    uv = None
    for su, sv in (("s", "t"), ("u", "v"), ("texture_u", "texture_v")):
        if su in fields and sv in fields:
            uv = np.column_stack([np.asarray(vert[su], np.float64),
                                  np.asarray(vert[sv], np.float64)])
            break
    if uv is None and "texcoord" in face.dtype.names and faces.shape[0] == len(face):
        tc = _face_array(face["texcoord"], width=6).astype(np.float64)
        return _split_by_uv(positions, faces.ravel(), tc.reshape(-1, 2))
    return positions, faces, uv


def _face_array(column, width: int = 3) -> np.ndarray:
    arr = np.asarray(column)
    if arr.dtype != object and arr.ndim == 2 and arr.shape[1] == width:
        return np.array(arr)  # copy: detach from plyfile's memory map
    rows = [np.asarray(r).tolist() for r in column]
    if width == 3:
        return np.asarray(_fan(rows), dtype=np.int64).reshape(-1, 3)
    if any(len(r) != width for r in rows):
        raise ValueError(f"face lists must hold {width} values per triangle")
    return np.asarray(rows, dtype=np.float64).reshape(-1, width)


def origin_from_ply_comments(path: Path, comments: list[str]) -> np.ndarray | None:
    """The world origin (E, N, H) m a PLY's ``ORIGIN_COMMENT`` comment states, or None."""
    for c in comments:
        tokens = c.split()
        if tokens and tokens[0] == ORIGIN_COMMENT:
            try:
                origin = np.array([float(t) for t in tokens[1:]])
            except ValueError:
                origin = np.empty(0)
            if origin.shape != (3,) or not np.all(np.isfinite(origin)):
                raise DesignerError(f"mesh file {path}: bad header comment '{c}'; "
                                    f"expected '{ORIGIN_COMMENT} E N H'")
            return origin
    return None


def _read_obj(path: Path):
    positions, texcoords, polygons = [], [], []
    with open(path, encoding="utf-8", errors="replace") as fh:
        for line_no, line in enumerate(fh, start=1):
            tokens = line.split()
            if not tokens:
                continue
            tag = tokens[0]
            try:
                if tag == "v":
                    positions.append([float(t) for t in tokens[1:4]])
                elif tag == "vt":
                    texcoords.append([float(t) for t in tokens[1:3]])
                elif tag == "f":
                    corners = [t.split("/") for t in tokens[1:]]
                    polygons.append([(int(c[0]), int(c[1]) if len(c) > 1 and c[1] else None)
                                     for c in corners])
            except (ValueError, IndexError):
                raise DesignerError(f"mesh file {path}, line {line_no}: cannot parse "
                                    f"'{line.strip()[:60]}'; fix the OBJ record") from None
            if tag in ("v", "vt") and len((positions if tag == "v" else texcoords)[-1]) != (
                    3 if tag == "v" else 2):
                raise DesignerError(f"mesh file {path}, line {line_no}: '{tag}' needs "
                                    f"{3 if tag == 'v' else 2} numbers; fix the OBJ record")
    positions_arr = np.asarray(positions, dtype=np.float64).reshape(-1, 3)
    texcoords_arr = np.asarray(texcoords, dtype=np.float64).reshape(-1, 2)

    def resolve(index: int, count: int, what: str) -> int:
        k = index - 1 if index > 0 else count + index  # OBJ: 1-based, negative = relative
        if not 0 <= k < count:
            raise DesignerError(f"mesh file {path}: face refers to {what} {index}, "
                                f"the file has {count}; fix the OBJ faces")
        return k

    tris = _fan([p for p in polygons if len(p) >= 3])
    if not tris:
        return positions_arr, np.empty((0, 3), np.int64), None
    has_vt = {c[1] is not None for tri in tris for c in tri}
    if has_vt == {True} and len(texcoords_arr):
        corner_v = np.array([resolve(c[0], len(positions_arr), "vertex")
                             for tri in tris for c in tri])
        corner_t = np.array([resolve(c[1], len(texcoords_arr), "texture coordinate")
                             for tri in tris for c in tri])
        return _split_by_uv(positions_arr, corner_v, texcoords_arr[corner_t])
    faces = np.array([[resolve(c[0], len(positions_arr), "vertex") for c in tri]
                      for tri in tris], dtype=np.int64)
    return positions_arr, faces, None


_STL_VERTEX = re.compile(rb"vertex\s+(\S+)\s+(\S+)\s+(\S+)")


def _read_stl(path: Path):
    data = path.read_bytes()
    if len(data) >= 84:
        n = int(np.frombuffer(data, dtype="<u4", count=1, offset=80)[0])
        if len(data) == 84 + 50 * n:
            tri = np.frombuffer(data, dtype=[("normal", "<f4", (3,)), ("v", "<f4", (3, 3)),
                                             ("attr", "<u2")], count=n, offset=84)
            corners = tri["v"].reshape(-1, 3).astype(np.float64)
            return _merge_corners(corners)
    if not data.lstrip().lower().startswith(b"solid"):
        raise DesignerError(f"mesh file {path} is neither binary nor ASCII STL; "
                            "export it again")
    corners = np.array(_STL_VERTEX.findall(data), dtype=np.float64).reshape(-1, 3)
    if len(corners) % 3:
        raise DesignerError(f"mesh file {path}: ASCII STL has {len(corners)} vertices, "
                            "not a multiple of 3; export it again")
    return _merge_corners(corners)


def _merge_corners(corners: np.ndarray):
    if len(corners) == 0:
        return corners, np.empty((0, 3), np.int64), None
    unique, inverse = np.unique(corners, axis=0, return_inverse=True)
    return unique, inverse.reshape(-1, 3), None
