"""The true surfaces of a project: bare earth (DTM) and the surface with what stands on it
(DSM), as world-coordinate triangles.

* ``dtm`` — the terrain and, when asked, the GCP target plates lying on it;
* ``dsm`` — the DTM plus everything standing on the ground at the reference time: scene
  objects (mesh files), and every layer in :data:`DSM_LAYERS` (buildings, vegetation…);
  moving objects only when a moment ``at_time_s`` (seconds after take-off) is given.

A project with none of these elements has DTM = DSM = the terrain (and targets), the
surface ``designer compare`` has always used.

:data:`DSM_LAYERS` is the one place where a scene element that stands on the ground says
what it adds to the surface: a function ``(project, base_dir, ground, at_time_s) ->
list[(vertices_world (N, 3) float64, faces (M, 3) int64)]``, returning ``[]`` when the
project does not use that element.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from designer.project import model as m

SURFACES = ("dtm", "dsm")

Triangles = tuple[np.ndarray, np.ndarray]


@dataclass(frozen=True)
class Ground:
    """What a layer may need to stand on the ground: the terrain's heightfield (or
    ``None`` for a mesh terrain) and its triangle mesh (``vertices_world``, ``faces``)."""

    heightfield: object
    terrain: object


def _scene_objects(project: m.Project, base_dir: Path, ground: Ground,
                   at_time_s: float | None) -> list[Triangles]:
    from designer.scene.objects import place_objects

    _, vertices, faces, _ = place_objects(project, base_dir)
    return [(vertices, faces)] if len(faces) else []


def _moving_objects(project: m.Project, base_dir: Path, ground: Ground,
                    at_time_s: float | None) -> list[Triangles]:
    if at_time_s is None or not project.scene.moving_objects:
        return []
    from designer.scene.moving import pose_at, posed_vertices, shape_mesh

    layers = []
    for obj in project.scene.moving_objects:
        v, f = shape_mesh(obj, base_dir)
        layers.append((posed_vertices(v, pose_at(obj, at_time_s, ground)), f))
    return layers


def _buildings(project: m.Project, base_dir: Path, ground: Ground,
               at_time_s: float | None) -> list[Triangles]:
    if not project.scene.buildings:
        return []
    from designer.scene.buildings import building_meshes_world

    return building_meshes_world(project, base_dir, ground)


def _vegetation(project: m.Project, base_dir: Path, ground: Ground,
                at_time_s: float | None) -> list[Triangles]:
    if project.scene.vegetation is None:
        return []
    from designer.scene.vegetation import vegetation_mesh_world

    # the plants as they sway at the reference time; upright without one
    return vegetation_mesh_world(project, base_dir, ground, at_time_s)


#: what stands on the ground, in the order it is added to the DSM
DSM_LAYERS: list[Callable[[m.Project, Path, Ground, float | None], list[Triangles]]] = [
    _scene_objects,
    _moving_objects,
    _buildings,
    _vegetation,
]


def merge_triangles(parts: list[Triangles]) -> Triangles:
    """One vertex and face array from several (face indices shifted)."""
    vertices, faces, n = [], [], 0
    for v, f in parts:
        vertices.append(np.asarray(v, np.float64).reshape(-1, 3))
        faces.append(np.asarray(f, np.int64).reshape(-1, 3) + n)
        n += len(vertices[-1])
    if not vertices:
        return np.zeros((0, 3)), np.zeros((0, 3), np.int64)
    return np.vstack(vertices), np.vstack(faces)


def true_surfaces(project: m.Project, base_dir: Path, surfaces=SURFACES, *,
                  with_targets: bool = True,
                  at_time_s: float | None = None, growth=None) -> dict[str, Triangles]:
    """Each of ``surfaces`` ("dtm", "dsm") of ``project`` as world triangles (float64),
    keyed by name in the order given, from one build of the terrain (and targets): each
    is equal, array for array, to :func:`true_surface` of that name. ``growth`` (a
    :class:`~designer.scene.surroundings.Growth`) grows the terrain as the renderer did,
    so the truth covers everything the images see; None: the declared terrain."""
    surfaces = (surfaces,) if isinstance(surfaces, str) else tuple(surfaces)
    for surface in surfaces:
        if surface not in SURFACES:
            raise ValueError(f"surface {surface!r}: give one of {', '.join(SURFACES)}")
    from designer.scene.build import build_heightfield, build_targets, build_terrain_mesh

    base_dir = Path(base_dir)
    terrain = project.scene.terrain
    origin = np.array([project.origin.E0, project.origin.N0, project.origin.H0])
    # Only the geometry is needed: build the terrain and targets, not the texture.
    hf = build_heightfield(terrain, base_dir, project.crs)
    if hf is not None and growth is not None and any(growth.steps):
        from designer.scene.surroundings import grow_terrain

        hf = grow_terrain(project, hf, growth).heightfield
    mesh = build_terrain_mesh(terrain, hf, base_dir, origin)
    bare: list[Triangles] = [(mesh.vertices_world, mesh.faces)]
    if with_targets:
        for t in build_targets(project, hf):
            quads = np.asarray(t.faces, np.int64)  # counter-clockwise quads
            bare.append((t.vertices_world,
                         np.vstack([quads[:, [0, 1, 2]], quads[:, [0, 2, 3]]])))
    parts = {"dtm": bare}
    if "dsm" in surfaces:
        ground = Ground(heightfield=hf, terrain=mesh)
        parts["dsm"] = bare + [triangles for layer in DSM_LAYERS
                               for triangles in layer(project, base_dir, ground, at_time_s)]
    return {surface: merge_triangles(parts[surface]) for surface in surfaces}


def true_surface(project: m.Project, base_dir: Path, surface: str = "dsm", *,
                 with_targets: bool = True, at_time_s: float | None = None) -> Triangles:
    """The ``surface`` ("dtm" or "dsm") of ``project`` as world triangles (float64)."""
    return true_surfaces(project, base_dir, (surface,), with_targets=with_targets,
                         at_time_s=at_time_s)[surface]
