"""Scene objects: mesh files placed in the world and lit like the ground.

Placement (the project file's ``<placement>``): world = position + scale · R · v, with
R = Rx(ω) · Ry(φ) · Rz(κ) from the core's ω φ κ rotation, v the mesh vertex in the
file's own frame (m). Each face's light is what the sun and an isotropic sky give a
plane of its orientation (``designer.scene.lighting.irradiance``, no cast shadows): the
renderer draws the objects as emission with that light, like the baked terrain.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from designer.core.rotation import rotation_from_opk
from designer.project import model as m
from designer.scene.lighting import irradiance, sun_direction_world
from designer.scene.mesh import load_mesh

#: the objects' diffuse colour (linear RGB): a light grey, as untextured survey objects
OBJECT_ALBEDO_RGB = (0.85, 0.82, 0.78)


@dataclass(frozen=True, eq=False)
class PlacedObjects:
    """The scene's mesh objects in the world as one merged triangle mesh
    (``vertices_world`` (N, 3) m, ``faces`` (M, 3)), the relative light on each face
    (M,) (1 = flat open ground in the same light) and the object each face belongs to
    (M,), an index into ``names``."""

    names: list[str]
    vertices_world: np.ndarray
    faces: np.ndarray
    face_irradiance: np.ndarray
    face_object: np.ndarray

    @property
    def is_empty(self) -> bool:
        return not self.names


def place_object(vertices: np.ndarray, placement: m.Placement) -> np.ndarray:
    """Mesh vertices (N, 3) in the object's frame → world (m): ``position + scale · R · v``
    with ``R = Rx(ω) · Ry(φ) · Rz(κ)`` (the project file's placement)."""
    R = rotation_from_opk(*np.radians([placement.omega_deg, placement.phi_deg,
                                       placement.kappa_deg]))
    p = placement.position
    return np.array([p.X, p.Y, p.Z]) + placement.scale * np.asarray(vertices, float) @ R.T


def place_objects(project: m.Project, base_dir: Path
                  ) -> tuple[list[str], np.ndarray, np.ndarray, np.ndarray]:
    """(names, vertices_world (N, 3), faces (M, 3), face_object (M,)) of every scene
    object of ``project`` read from its file (relative to ``base_dir``; an unreadable file
    raises an error naming it) and placed in the world."""
    from designer.project.files import resolve

    names, vertices, faces, owner = [], [np.zeros((0, 3))], [np.zeros((0, 3), np.int64)], [
        np.zeros(0, int)]
    start = 0
    for k, obj in enumerate(project.scene.objects):
        mesh = load_mesh(resolve(Path(base_dir), obj.file))
        v = place_object(mesh.vertices_world, obj.placement)
        names.append(obj.name)
        vertices.append(v)
        faces.append(np.asarray(mesh.faces, dtype=np.int64) + start)
        owner.append(np.full(len(mesh.faces), k))
        start += len(v)
    return names, np.vstack(vertices), np.vstack(faces), np.concatenate(owner)


def build_objects(project: m.Project, base_dir: Path, sun_azimuth_deg: float,
                  sun_elevation_deg: float,
                  sun_share: Callable[[np.ndarray, np.ndarray], np.ndarray] | None = None
                  ) -> PlacedObjects:
    """``place_objects``, and each face's light from the project's sun and sky; with
    ``sun_share`` (the direct sun's factor at world x, y: cloud shadows) each face's
    direct sun is scaled by it at the face's centre."""
    names, v, f, owner = place_objects(project, base_dir)
    if not names:
        return PlacedObjects([], v, f, np.zeros(0), owner)
    normals = np.cross(v[f[:, 1]] - v[f[:, 0]], v[f[:, 2]] - v[f[:, 0]])
    length = np.linalg.norm(normals, axis=1, keepdims=True)
    normals = np.divide(normals, length, out=np.zeros_like(normals), where=length > 0)
    lighting = project.scene.lighting
    sun = sun_direction_world(sun_azimuth_deg, sun_elevation_deg)
    lit = np.ones(len(f))
    if sun_share is not None:
        centre = v[f].mean(axis=1)
        lit = sun_share(centre[:, 0], centre[:, 1])
    light = irradiance(normals, lit, sun, lighting.sun_strength,
                       lighting.sky_strength)
    return PlacedObjects(names, v, f, light, owner)
