"""The projection-validation scene: a 10 m cube with a checkerboard on each inside wall.

The cube (1000 m³) is centred on the origin. Each of its six walls carries a 10 × 10
black/white checkerboard of 1 m squares (a 10 × 10 texel texture, 'Closest'
interpolation, so every square edge is exactly where the geometry says). The 9 × 9
inner corners of each wall — 486 in all — are the points measured; corners on the
cube's edges are folds between two walls, not checkerboard corners, and are not used.

Cameras are placed at random inside the central 6 m of the cube and turned uniformly at
random (a uniform random unit quaternion): every direction sees a wall, the inside of a
convex box hides nothing from itself.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from designer.core.interior import InteriorOrientation
from designer.core.projection import project_points
from designer.core.rotation import rotation_from_quaternion
from designer.experiments.jobs import MeshObject
from designer.render.job_spec import MaterialSpec
from designer.scene.texture import checkerboard_texture

CUBE_SIZE_M = 10.0
SQUARES = 10
#: wall origin (a cube corner) and its two in-plane axes (unit vectors)
_WALLS = [
    ((-1, -1, -1), (0, 1, 0), (0, 0, 1)),  # x = −5
    ((1, -1, -1), (0, 0, 1), (0, 1, 0)),  # x = +5
    ((-1, -1, -1), (0, 0, 1), (1, 0, 0)),  # y = −5
    ((-1, 1, -1), (1, 0, 0), (0, 0, 1)),  # y = +5
    ((-1, -1, -1), (1, 0, 0), (0, 1, 0)),  # z = −5 (floor)
    ((-1, -1, 1), (0, 1, 0), (1, 0, 0)),  # z = +5 (ceiling)
]
#: the 8 neighbours of a corner on its wall (steps of one square along the wall axes)
_NEIGHBOURS = [(-1, -1), (-1, 0), (-1, 1), (0, -1), (0, 1), (1, -1), (1, 0), (1, 1)]


@dataclass(frozen=True)
class Corners:
    """Checkerboard corners: positions (N, 3) m and each corner's wall axes (N, 3) × 2."""

    xyz_m: np.ndarray
    axis_a: np.ndarray
    axis_b: np.ndarray
    wall: np.ndarray  # (N,) wall index 0..5


def cube_corners() -> Corners:
    """The 486 inner checkerboard corners (9 × 9 on each of the 6 walls)."""
    half = CUBE_SIZE_M / 2
    step = CUBE_SIZE_M / SQUARES
    xyz, aa, bb, wall = [], [], [], []
    ij = np.arange(1, SQUARES)
    i, j = (g.ravel() for g in np.meshgrid(ij, ij, indexing="ij"))
    for w, (o, a, b) in enumerate(_WALLS):
        o, a, b = half * np.array(o, float), np.array(a, float), np.array(b, float)
        xyz.append(o + step * (i[:, None] * a + j[:, None] * b))
        aa.append(np.tile(a, (len(i), 1)))
        bb.append(np.tile(b, (len(i), 1)))
        wall.append(np.full(len(i), w))
    return Corners(np.concatenate(xyz), np.concatenate(aa), np.concatenate(bb),
                   np.concatenate(wall))


def cube_walls(texels_per_square: int = 1) -> MeshObject:
    """The six inside walls as one mesh: a quad per wall, UV 0…1 over the wall.

    ``texels_per_square`` > 1 only matters with 'Linear' texture interpolation, which
    blends over one texel: it then blurs each edge over 1/texels_per_square of a square.
    """
    half = CUBE_SIZE_M / 2
    vertices, faces, uv = [], [], []
    for w, (o, a, b) in enumerate(_WALLS):
        o, a, b = half * np.array(o, float), np.array(a, float), np.array(b, float)
        s = CUBE_SIZE_M
        vertices += [o, o + s * a, o + s * (a + b), o + s * b]
        uv += [(0, 0), (1, 0), (1, 1), (0, 1)]
        faces.append([4 * w, 4 * w + 1, 4 * w + 2, 4 * w + 3])
    texture = checkerboard_texture(SQUARES, texels_per_square)
    return MeshObject(name="walls", vertices_local=np.array(vertices), faces=np.array(faces),
                      uv=np.array(uv, float), textures={"checker.png": texture},
                      materials=(MaterialSpec(texture="checker.png"),))


def random_poses(n: int, rng: np.random.Generator, reach_m: float = 3.0
                 ) -> list[tuple[np.ndarray, np.ndarray]]:
    """``n`` poses (C (3,), R_cam_to_world (3, 3)): C uniform in ±reach_m, R uniform."""
    C = rng.uniform(-reach_m, reach_m, (n, 3))
    R = rotation_from_quaternion(rng.standard_normal((n, 4)))
    return [(C[k], R[k]) for k in range(n)]


def measurable(corners: Corners, C: np.ndarray, R: np.ndarray, interior: InteriorOrientation,
               min_square_px: float, margin_px: float) -> tuple[np.ndarray, np.ndarray]:
    """Which corners a detector window can measure in this view, and where they project.

    A corner counts if it and its 8 neighbours on the wall are in front of the camera,
    it lies at least ``margin_px`` inside the image, and every neighbour projects at
    least ``min_square_px`` away (so a detector window sees this corner's two edges only,
    however foreshortened the wall). Returns (mask (N,), uv_px (N, 2)).
    """
    uv = project_points(corners.xyz_m, C, R, interior).uv_px[0]
    ok = np.all(np.isfinite(uv), axis=1)
    step = CUBE_SIZE_M / SQUARES
    for da, db in _NEIGHBOURS:
        xyz = corners.xyz_m + step * (da * corners.axis_a + db * corners.axis_b)
        p = project_points(xyz, C, R, interior)
        with np.errstate(invalid="ignore"):
            ok &= p.in_front[0] & (np.linalg.norm(p.uv_px[0] - uv, axis=1) >= min_square_px)
    W, H = interior.image_size_px
    with np.errstate(invalid="ignore"):
        ok &= ((uv[:, 0] >= margin_px) & (uv[:, 0] <= W - margin_px)
               & (uv[:, 1] >= margin_px) & (uv[:, 1] <= H - margin_px))
    return ok, uv
