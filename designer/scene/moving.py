"""Moving objects: vehicles and people travelling along a polyline at a constant speed,
posed at each photo's time (docs/world.md, Moving objects).

An object's frame: origin at the centre of its base, +Y forward, +X to its right, +Z up
(m). Its pose at a time is a world position (X, Y on the path, Z the terrain height
there: the base sits on the ground, the object stays level) and a heading, clockwise
from grid north (deg), along the path segment it is on:
``world = position + Rz(−heading) · v``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from designer.project import model as m

#: sides of the prism drawn for a person
PERSON_SIDES = 16


@dataclass(frozen=True)
class MovingPose:
    """Where an object is at ``time_s`` (s after take-off): world position (m) of its base
    centre and heading (deg clockwise from grid north)."""

    object_id: str
    time_s: float
    position_world: tuple[float, float, float]
    heading_deg: float


def shape_mesh(obj: m.MovingObject, base_dir: Path) -> tuple[np.ndarray, np.ndarray]:
    """(vertices (N, 3), faces (M, 3)) of ``obj`` in its own frame (m)."""
    if obj.file is not None:
        from designer.project.files import resolve
        from designer.scene.mesh import load_mesh

        mesh = load_mesh(resolve(Path(base_dir), obj.file))
        return np.asarray(mesh.vertices_world, float), np.asarray(mesh.faces, np.int64)
    length, width, height = obj.size_m or m.MOVING_SHAPES[obj.shape]
    if obj.shape == "person":
        return _prism(width / 2, height, PERSON_SIDES)
    return _box(length, width, height)


def _box(length: float, width: float, height: float) -> tuple[np.ndarray, np.ndarray]:
    x, y = width / 2, length / 2
    v = np.array([[-x, -y, 0], [x, -y, 0], [x, y, 0], [-x, y, 0],
                  [-x, -y, height], [x, -y, height], [x, y, height], [-x, y, height]], float)
    quads = [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6),
             (3, 0, 4, 7)]
    f = [(a, b, c) for a, b, c, d in quads] + [(a, c, d) for a, b, c, d in quads]
    return v, np.array(f, np.int64)


def _prism(radius: float, height: float, sides: int) -> tuple[np.ndarray, np.ndarray]:
    a = 2 * np.pi * np.arange(sides) / sides
    ring = np.column_stack([radius * np.sin(a), radius * np.cos(a)])
    v = np.vstack([np.column_stack([ring, np.zeros(sides)]),
                   np.column_stack([ring, np.full(sides, height)]),
                   [[0, 0, 0], [0, 0, height]]])
    f = []
    for i in range(sides):
        j = (i + 1) % sides
        f += [(i, j, sides + j), (i, sides + j, sides + i),
              (2 * sides, j, i), (2 * sides + 1, sides + i, sides + j)]
    return v, np.array(f, np.int64)


def path_xy_heading(obj: m.MovingObject, time_s: float) -> tuple[float, float, float]:
    """(X, Y, heading_deg) of ``obj`` at ``time_s``: ``speed × (time − start)`` along the
    path; at the first point before it starts, at the last after it ends (heading of the
    last segment), or round the closed polyline again with ``loop``."""
    pts = np.array([(p.X, p.Y) for p in obj.path], float)
    if obj.loop:
        pts = np.vstack([pts, pts[:1]])
    seg = np.diff(pts, axis=0)
    lengths = np.hypot(seg[:, 0], seg[:, 1])
    keep = lengths > 0
    pts = np.vstack([pts[:1], pts[1:][keep]])
    seg, lengths = seg[keep], lengths[keep]
    total = float(lengths.sum())
    s = obj.speed_m_s * max(time_s - obj.start_s, 0.0)
    s = s % total if obj.loop else min(s, total)
    ends = np.cumsum(lengths)
    k = min(int(np.searchsorted(ends, s, side="right")), len(lengths) - 1)
    along = s - (ends[k] - lengths[k])
    x, y = pts[k] + seg[k] * (along / lengths[k])
    heading = math.degrees(math.atan2(seg[k, 0], seg[k, 1])) % 360.0
    return float(x), float(y), heading


def ground_height_m(scene, x: float, y: float) -> float:
    """Terrain height (world m) below (x, y): the heightfield there (clamped to its
    extent), or for a mesh terrain the height of its nearest vertex."""
    if scene.heightfield is not None:
        return float(np.asarray(scene.heightfield.height_at_clamped(x, y)).ravel()[0])
    v = scene.terrain.vertices_world
    k = int(np.argmin((v[:, 0] - x) ** 2 + (v[:, 1] - y) ** 2))
    return float(v[k, 2])


def pose_at(obj: m.MovingObject, time_s: float, scene) -> MovingPose:
    """The pose of ``obj`` at ``time_s`` on ``scene``'s terrain (a BuiltScene)."""
    x, y, heading = path_xy_heading(obj, time_s)
    return MovingPose(obj.id, float(time_s), (x, y, ground_height_m(scene, x, y)), heading)


def rotation_z(heading_deg: float) -> np.ndarray:
    """Object frame → world rotation for a heading clockwise from grid north."""
    a = -math.radians(heading_deg)
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def posed_vertices(vertices: np.ndarray, pose: MovingPose) -> np.ndarray:
    """Object-frame vertices (N, 3) → world (m) at ``pose``."""
    return np.asarray(pose.position_world) + np.asarray(vertices, float) @ rotation_z(
        pose.heading_deg).T
