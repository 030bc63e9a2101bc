"""The buildings of a render job: one mesh of every building's triangles (local
coordinates, each triangle with its own corners so walls and roofs carry their own
texture coordinates), the facade and roof textures, and emission materials lit for the
job's sun (docs/world.md, Buildings and structures).

Light: each face is drawn as its texture × the relative irradiance a plane of its
orientation gets from the sun and an isotropic sky (``designer.scene.lighting.irradiance``,
1 = flat open ground), like the scene objects: no cast shadows, neither on the ground
nor from one building on another. Faces of the same kind (facade or roof) and the same
light share one material; when a mesh-file building gives more than
``LIGHT_LEVELS`` distinct lights per kind, they are quantised to that many levels.

Texture coordinates: on each face, u runs horizontally along it and v up its slope
(``u = (p − p₀)·a``, ``v = (p − p₀)·(n × a)`` with ``a = ẑ × n`` normalised, ``p₀`` the
building's first vertex), in units of the texture's ``TILE_M`` metres: bricks stay
level on every wall and tile rows run along every eave.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import cv2
import numpy as np

from designer.render.job_files import save_npz, write_png
from designer.render.job_spec import MaterialSpec, MeshSpec
from designer.scene.building_texture import TILE_M, facade_texture, roof_texture
from designer.scene.buildings import ROOF, BuildingMesh
from designer.scene.lighting import irradiance, sun_direction_world

#: the job's Blender object of all buildings (provenance hashes it with the scene)
BUILDINGS_MESH = "buildings"
FACADE_PNG, ROOF_PNG = "building_facade.png", "building_roof.png"
#: most light levels per face kind (one material each)
LIGHT_LEVELS = 64


def write_building_textures(job_dir: Path) -> None:
    """The facade and roof textures beside job.json."""
    for name, image in ((FACADE_PNG, facade_texture()), (ROOF_PNG, roof_texture())):
        write_png(Path(job_dir) / name, cv2.cvtColor(image, cv2.COLOR_RGB2BGR))


def face_frames(vertices: np.ndarray, faces: np.ndarray
                ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Per face: unit normal, unit horizontal axis a and up-slope axis n × a, (M, 3) each."""
    v = np.asarray(vertices, float)
    n = np.cross(v[faces[:, 1]] - v[faces[:, 0]], v[faces[:, 2]] - v[faces[:, 0]])
    length = np.linalg.norm(n, axis=1, keepdims=True)
    n = np.divide(n, length, out=np.tile([0.0, 0.0, 1.0], (len(n), 1)), where=length > 0)
    a = np.column_stack([-n[:, 1], n[:, 0], np.zeros(len(n))])  # z × n
    la = np.linalg.norm(a, axis=1, keepdims=True)
    a = np.where(la > 1e-9, a / np.maximum(la, 1e-300), [1.0, 0.0, 0.0])
    return n, a, np.cross(n, a)


def render_arrays(buildings: list[BuildingMesh], origin: np.ndarray) -> dict[str, np.ndarray]:
    """Every building's triangles with unshared corners: ``vertices_local`` (3M, 3),
    ``faces`` (M, 3), ``uv`` (3M, 2), and per face ``normal`` (M, 3) and ``roof`` (M,)."""
    local, uv, normals, roof = [], [], [], []
    for b in buildings:
        corners = b.vertices_world[b.faces]  # (M, 3, 3)
        n, a, up = face_frames(b.vertices_world, b.faces)
        rel = corners - b.vertices_world[0]
        uv.append(np.stack([np.einsum("mkj,mj->mk", rel, a),
                            np.einsum("mkj,mj->mk", rel, up)], axis=-1).reshape(-1, 2) / TILE_M)
        local.append((corners - origin).reshape(-1, 3))
        normals.append(n)
        roof.append(b.face_kind == ROOF)
    count = sum(len(n) for n in normals)
    return {"vertices_local": np.vstack(local), "faces": np.arange(3 * count).reshape(-1, 3),
            "uv": np.vstack(uv), "normal": np.vstack(normals), "roof": np.concatenate(roof)}


def light_groups(light: np.ndarray, roof: np.ndarray
                 ) -> tuple[np.ndarray, list[tuple[bool, float]]]:
    """(material index per face, [(roof?, light)] per material): faces of one kind and
    one light share a material; more than LIGHT_LEVELS lights of a kind are quantised."""
    index = np.zeros(len(light), np.int64)
    materials: list[tuple[bool, float]] = []
    for kind in (False, True):
        sel = np.flatnonzero(roof == kind)
        if not sel.size:
            continue
        values = np.round(light[sel], 12)
        levels, inverse = np.unique(values, return_inverse=True)
        if len(levels) > LIGHT_LEVELS:
            lo, hi = float(values.min()), float(values.max())
            q = np.rint((values - lo) / (hi - lo) * (LIGHT_LEVELS - 1))
            levels, inverse = np.unique(lo + q * (hi - lo) / (LIGHT_LEVELS - 1),
                                        return_inverse=True)
        index[sel] = len(materials) + inverse.ravel()
        materials += [(kind, float(e)) for e in levels]
    return index, materials


def buildings_object(buildings: list[BuildingMesh], origin: np.ndarray, job_dir: Path,
                     sun_azimuth_deg: float, sun_elevation_deg: float, sun_strength: float,
                     sky_strength: float, file_name: str = "buildings.npz",
                     sun_share: Callable[[np.ndarray, np.ndarray], np.ndarray] | None = None
                     ) -> MeshSpec:
    """The buildings as one mesh lit for this sun, written beside job.json; with
    ``sun_share`` (the direct sun's factor at world x, y: cloud shadows) each face's
    direct sun is scaled by it at the face's centre."""
    arrays = render_arrays(buildings, origin)
    sun = sun_direction_world(sun_azimuth_deg, sun_elevation_deg)
    lit = np.ones(len(arrays["normal"]))
    if sun_share is not None:
        centre = arrays["vertices_local"][arrays["faces"]].mean(axis=1) + origin
        lit = sun_share(centre[:, 0], centre[:, 1])
    light = irradiance(arrays["normal"], lit, sun, sun_strength, sky_strength)
    index, materials = light_groups(light, arrays["roof"])
    save_npz(Path(job_dir) / file_name, vertices_local=arrays["vertices_local"],
             faces=arrays["faces"], uv=arrays["uv"], material_index=index)
    return MeshSpec(BUILDINGS_MESH, file_name, tuple(
        MaterialSpec(texture=ROOF_PNG if is_roof else FACADE_PNG, interpolation="Linear",
                     strength=e) for is_roof, e in materials))
