"""The moving objects as the 3D view draws them (Qt-free): each car, person or box posed
where the render poses it at one moment of the flight (the moment the view draws the
cloud shadows at: the selected photo's time, else the take-off), standing on the
terrain, heading along its path; and each path as a line just above the ground.
Wraps :mod:`designer.scene.moving`, as the renderer does."""

from __future__ import annotations

import itertools
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from designer.core.heightfield import Heightfield
from designer.gui.state.view_geometry import polyline_cells
from designer.project import model as m

#: the paths are drawn this far above the ground (m), so the terrain does not hide them
PATH_LIFT_M = 0.15
#: points per metre of a path drawn over the terrain (it follows the ground between its
#: vertices)
PATH_POINTS_PER_M = 0.5


@dataclass(frozen=True, eq=False)
class MovingDisplay:
    """``vertices_world`` (N, 3) and ``faces`` (M, 3) of every object posed at ``time_s``,
    ``face_albedo`` (M, 3) linear; ``path_points`` (P, 3) and ``path_lines`` (VTK line
    cells) of their paths; world metres."""

    time_s: float
    ids: tuple[str, ...]
    vertices_world: np.ndarray
    faces: np.ndarray
    face_albedo: np.ndarray
    path_points: np.ndarray
    path_lines: np.ndarray


def moving_display(project: m.Project, heightfield: Heightfield | None, base_dir: Path,
                   time_s: float, ground_z_m: float = 0.0) -> MovingDisplay | None:
    """The project's moving objects at ``time_s`` (s after take-off), on ``heightfield``
    (None, a mesh terrain: at ``ground_z_m``); None when it has none."""
    from designer.scene.moving import MovingPose, path_xy_heading, posed_vertices, shape_mesh

    objects = project.scene.moving_objects
    if not objects:
        return None

    def ground(x, y) -> np.ndarray:
        if heightfield is None:
            return np.full(np.shape(x), float(ground_z_m))
        return np.asarray(heightfield.height_at_clamped(x, y), dtype=float)

    vertices, faces, albedo, path_points, path_cells = [], [], [], [], []
    n_vertices = n_points = 0
    for obj in objects:
        v, f = shape_mesh(obj, Path(base_dir))
        x, y, heading = path_xy_heading(obj, time_s)
        z = float(np.ravel(ground(np.array([x]), np.array([y])))[0])
        vertices.append(posed_vertices(v, MovingPose(obj.id, time_s, (x, y, z), heading)))
        faces.append(np.asarray(f, dtype=np.int64) + n_vertices)
        albedo.append(np.tile(obj.albedo_rgb, (len(f), 1)))
        n_vertices += len(v)
        xy = _path_xy(obj)
        pts = np.column_stack([xy, ground(xy[:, 0], xy[:, 1]) + PATH_LIFT_M])
        path_points.append(pts)
        path_cells.append(polyline_cells(1, len(pts)) + np.r_[0, np.full(len(pts), n_points)])
        n_points += len(pts)
    return MovingDisplay(float(time_s), tuple(o.id for o in objects), np.vstack(vertices),
                         np.vstack(faces), np.vstack(albedo), np.vstack(path_points),
                         np.concatenate(path_cells))


def _path_xy(obj: m.MovingObject) -> np.ndarray:
    """(K, 2) points along ``obj``'s path (closed when it loops), its vertices and points
    between them every 1 / PATH_POINTS_PER_M metres."""
    corners = np.array([(p.X, p.Y) for p in obj.path], dtype=float)
    if obj.loop:
        corners = np.vstack([corners, corners[:1]])
    out = [corners[:1]]
    for a, b in itertools.pairwise(corners):
        n = max(1, int(np.ceil(np.hypot(*(b - a)) * PATH_POINTS_PER_M)))
        t = np.arange(1, n + 1)[:, None] / n
        out.append(a + t * (b - a))
    return np.vstack(out)
