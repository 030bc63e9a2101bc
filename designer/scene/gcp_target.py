"""Ground control point targets: square 2 × 2 black/white checkers lying on the terrain.

World frame: X east, Y north, Z up, metres, float64. A target frame has its origin at
the checker centre (where the four quadrants meet), x and y along the target's edges
and z along its normal; ``R_target_to_world`` maps target-frame vectors to world
(``X = centre + R · x_target``), columns = the target's x, y, z axes in world.

Where the true GCP coordinate is: :func:`target_pose_on_terrain` puts ``centre`` on the
(bilinear) terrain surface; :func:`target_mesh` then draws the checker ``lift_m`` above
it along the target normal so the renderer does not z-fight it with the ground. The
point a camera sees, and so the GCP's true XYZ to export and to compare against, is the
drawn checker centre ``centre + lift_m · R[:, 2]`` — :func:`target_point_world` — which
is vertex 0 of the mesh. It is on the surface up to the lift (5 mm by default), and the
lift is included in the true coordinate, never forgotten.
"""

from __future__ import annotations

import numpy as np

from designer.core.heightfield import Heightfield
from designer.errors import DesignerError

#: default distance between the terrain and the drawn checker (metres)
DEFAULT_LIFT_M = 0.005
#: quadrant colours (sRGB uint8): (+x, +y) and (−x, −y) white, the others black
WHITE = np.array([255, 255, 255], dtype=np.uint8)
BLACK = np.array([0, 0, 0], dtype=np.uint8)


def target_pose_on_terrain(
    hf: Heightfield, x_m: float, y_m: float, size_m: float, yaw_rad: float = 0.0
) -> tuple[np.ndarray, np.ndarray]:
    """Centre (3,) on the terrain at (x, y) and ``R_target_to_world`` (3, 3) following its slope.

    The normal (target z) is that of the plane through the bilinear surface's slopes
    across the target: central differences of ``hf.height_at`` over ± size/2 in X and Y
    (one-sided where the target overhangs the grid edge). On planar terrain this is the
    exact normal; on curved terrain it is the mean slope a rigid plate settles on. Target
    x is the in-plane direction whose map projection points east, ``(1, 0, ∂z/∂x)``
    normalised, then turned by ``yaw_rad`` counter-clockwise about the normal; y = z × x.
    """
    if not (np.isfinite(size_m) and size_m > 0):
        raise DesignerError(f"GCP target size must be > 0 m, got {size_m}")
    x_m, y_m = float(x_m), float(y_m)
    if not hf.contains(x_m, y_m):
        x0, x1, y0, y1 = hf.extent_m
        raise DesignerError(
            f"GCP target at ({x_m:.3f}, {y_m:.3f}) lies outside the terrain "
            f"[{x0:.3f}, {x1:.3f}] x [{y0:.3f}, {y1:.3f}]; move it onto the terrain")
    centre = np.array([x_m, y_m, float(hf.height_at(x_m, y_m))])

    x_lo, x_hi, y_lo, y_hi = hf.extent_m
    h = 0.5 * size_m
    xa, xb = max(x_m - h, x_lo), min(x_m + h, x_hi)
    ya, yb = max(y_m - h, y_lo), min(y_m + h, y_hi)
    dzdx = _slope(hf, xa, y_m, xb, y_m, xb - xa)
    dzdy = _slope(hf, x_m, ya, x_m, yb, yb - ya)
    normal = np.array([-dzdx, -dzdy, 1.0])
    normal /= np.linalg.norm(normal)

    # The surface direction straight above east (it is orthogonal to the normal).
    x_axis = np.array([1.0, 0.0, dzdx]) / np.hypot(1.0, dzdx)
    y_axis = np.cross(normal, x_axis)
    c, s = np.cos(yaw_rad), np.sin(yaw_rad)
    x_axis, y_axis = c * x_axis + s * y_axis, -s * x_axis + c * y_axis
    return centre, np.column_stack([x_axis, y_axis, normal])


def _slope(hf: Heightfield, xa: float, ya: float, xb: float, yb: float, run: float) -> float:
    if run <= 0:  # a grid one spacing wide cannot happen (Heightfield is >= 2 x 2)
        return 0.0
    za, zb = hf.height_at(np.array([xa, xb]), np.array([ya, yb]))
    return float((zb - za) / run)


def target_point_world(
    centre_world: np.ndarray, R_target_to_world: np.ndarray, lift_m: float = DEFAULT_LIFT_M
) -> np.ndarray:
    """The GCP's true XYZ (3,): the drawn checker centre, ``centre + lift_m · R[:, 2]``."""
    centre = np.asarray(centre_world, dtype=np.float64).reshape(3)
    R = np.asarray(R_target_to_world, dtype=np.float64).reshape(3, 3)
    return centre + lift_m * R[:, 2]


def target_mesh(
    centre_world: np.ndarray,
    R_target_to_world: np.ndarray,
    size_m: float,
    lift_m: float = DEFAULT_LIFT_M,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Geometry of a 2 × 2 checker target: ``(vertices (9, 3), faces (4, 4), colors (4, 3))``.

    Vertices are world coordinates (float64) of a 3 × 3 grid over the square of side
    ``size_m`` in the target plane, lifted ``lift_m`` along the normal: vertex 0 is the
    checker centre (the GCP's true point, see the module docstring), then the edge
    midpoints and corners. Faces are four quads counter-clockwise seen from above the
    target (their normals are +z of the target); ``colors`` are per-face sRGB uint8,
    white in the (+x, +y) and (−x, −y) quadrants, black in the other two.
    """
    if not (np.isfinite(size_m) and size_m > 0):
        raise DesignerError(f"GCP target size must be > 0 m, got {size_m}")
    R = np.asarray(R_target_to_world, dtype=np.float64).reshape(3, 3)
    h = 0.5 * size_m
    # Local (x, y) of the 3 x 3 grid: centre first, then the ring counter-clockwise
    # from +x: E, NE, N, NW, W, SW, S, SE (in target axes).
    local = np.array([[0, 0], [h, 0], [h, h], [0, h], [-h, h],
                      [-h, 0], [-h, -h], [0, -h], [h, -h]], dtype=np.float64)
    local3 = np.column_stack([local, np.full(len(local), lift_m)])
    vertices = np.asarray(centre_world, dtype=np.float64).reshape(3) + local3 @ R.T
    faces = np.array([[0, 1, 2, 3],   # +x +y
                      [0, 3, 4, 5],   # −x +y
                      [0, 5, 6, 7],   # −x −y
                      [0, 7, 8, 1]],  # +x −y
                     dtype=np.int64)
    colors = np.array([WHITE, BLACK, WHITE, BLACK])
    return vertices, faces, colors


def target_clearance_m(
    hf: Heightfield,
    centre_world: np.ndarray,
    R_target_to_world: np.ndarray,
    size_m: float,
    lift_m: float = DEFAULT_LIFT_M,
    samples: int = 21,
) -> float:
    """Smallest vertical gap between the drawn target and the terrain, samples² points (m).

    On a plane it is ``lift_m / cos(tilt)`` (the lift is measured along the normal).

    Negative means the ground pokes through the plate (curved terrain under a large
    target, or a lift too small): move the target, shrink it or raise ``lift_m``.
    Points of the plate outside the grid are ignored.
    """
    R = np.asarray(R_target_to_world, dtype=np.float64).reshape(3, 3)
    t = np.linspace(-0.5 * size_m, 0.5 * size_m, samples)
    u, v = np.meshgrid(t, t)
    local = np.column_stack([u.ravel(), v.ravel(), np.full(u.size, lift_m)])
    offsets = local @ R.T
    centre = np.asarray(centre_world, dtype=np.float64).reshape(3)
    ground = hf.height_at(centre[0] + offsets[:, 0], centre[1] + offsets[:, 1])
    gap = centre[2] + offsets[:, 2] - ground
    return float(np.nanmin(gap))
