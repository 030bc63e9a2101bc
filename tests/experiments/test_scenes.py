"""Validation scenes without rendering: cube corners, texture plane, PSF sphere, baseline maps."""

from __future__ import annotations

import math

import numpy as np
import pytest

from designer.core.projection import project_points
from designer.core.rotation import rotation_from_opk
from designer.experiments import psf, texture
from designer.experiments.baseline import local_affine
from designer.experiments.cube import cube_corners, cube_walls, measurable, random_poses
from designer.experiments.projection import IO_SETS


def test_cube_has_486_inner_corners_on_its_walls_at_texel_borders():
    c = cube_corners()
    assert c.xyz_m.shape == (486, 3)
    on_wall = np.isclose(np.abs(c.xyz_m), 5.0)
    assert np.all(on_wall.sum(axis=1) == 1)  # on exactly one wall, never on an edge
    assert np.all(np.abs(c.xyz_m)[~on_wall] <= 4.0 + 1e-12)
    walls = cube_walls()
    for w in range(6):
        o, a, b = walls.vertices_local[4 * w], walls.vertices_local[4 * w + 1], \
            walls.vertices_local[4 * w + 3]
        p = c.xyz_m[c.wall == w]
        # UV of each corner (bilinear over the wall quad) lies on the 10 x 10 texel grid
        uv = np.column_stack([(p - o) @ (a - o), (p - o) @ (b - o)]) / 100.0
        assert np.allclose(uv * 10, np.round(uv * 10), atol=1e-12)
        assert np.all((uv > 0) & (uv < 1))


def test_measurable_corners_are_in_the_image_and_well_separated():
    interior = IO_SETS[0].interior((960, 640))
    C, R = np.zeros(3), rotation_from_opk(np.radians(90), 0.0, 0.0)  # looking north
    ok, uv = measurable(cube_corners(), C, R, interior, 12.0, 10.0)
    # the north wall 5 m away: 73° x 52° of view shows about 7.4 m x 4.8 m of it
    assert 20 <= ok.sum() <= 40
    assert np.all((uv[ok] >= 10) & (uv[ok] <= [950, 630]))
    tight, _ = measurable(cube_corners(), C, R, interior, 200.0, 10.0)
    assert tight.sum() == 0


def test_random_poses_are_inside_the_cube_and_rotations():
    poses = random_poses(50, np.random.default_rng(0))
    for C, R in poses:
        assert np.all(np.abs(C) <= 3.0)
        assert np.allclose(R @ R.T, np.eye(3), atol=1e-12)
        assert np.linalg.det(R) == pytest.approx(1.0)


def test_local_affine_is_the_derivative_of_the_projection():
    interior = IO_SETS[1].interior((960, 640))
    C = np.array([0.3, -0.5, 0.2])
    R = rotation_from_opk(np.radians(80), np.radians(10), np.radians(20))
    c = cube_corners()
    ok, _ = measurable(c, C, R, interior, 12.0, 10.0)
    i = int(np.nonzero(ok)[0][0])
    J = local_affine(c.xyz_m[i], c.axis_a[i], c.axis_b[i], 1.0, C, R, interior)
    h = 1e-6
    for k, axis in enumerate((c.axis_a[i], c.axis_b[i])):
        plus = project_points(c.xyz_m[i] + h * axis, C, R, interior).uv_px[0, 0]
        minus = project_points(c.xyz_m[i] - h * axis, C, R, interior).uv_px[0, 0]
        assert np.allclose(J[:, k], (plus - minus) / (2 * h), rtol=1e-5)


def test_texture_plane_is_100_px_per_texel_with_fractional_edges():
    eu, ev = texture.projected_edges()
    assert np.allclose(np.diff(eu), 100.0) and np.allclose(np.diff(ev), 100.0)
    frac = np.concatenate([eu % 1, ev % 1])
    assert np.all((frac > 0.2) & (frac < 0.8))  # edges cross pixels, not pixel borders
    point = texture.expected_point()
    widths = texture.texel_widths_px(point)
    assert set(widths.tolist()) == {100}


def test_texture_prediction_has_the_texture_image_s_colours():
    # the texel under the image centre, read from the texture image itself
    tex = texture.plane().textures["checker.png"]
    C, _ = texture.pose()
    col, row_from_bottom = int(C[0] / texture.TEXEL_M), int(C[1] / texture.TEXEL_M)
    white = tex[tex.shape[0] - 1 - row_from_bottom, col, 0] == 255
    W, H = texture.SIZE_PX
    # 3 px right of and below the principal point: 3 mm east and south of C, the same texel
    u, v = int(W / 2 + 3), int(H / 2 + 3)
    assert texture.expected_point()[v, u] == float(white)
    # exact areas agree with the centre samples wherever no edge crosses the pixel
    area, point = texture.expected_area(), texture.expected_point()
    pure = (area == 0) | (area == 1)
    assert np.array_equal(area[pure], point[pure])
    eu, ev = texture.projected_edges()
    cols, rows = np.floor(eu).astype(int), np.floor(ev).astype(int)
    crossed = np.zeros_like(pure)
    crossed[:, cols] = True
    crossed[rows, :] = True
    assert np.array_equal(~pure, crossed)


def test_psf_sphere_is_a_0_3_px_disc_inside_the_centre_pixel():
    interior = psf.camera()
    assert interior.fx_px == pytest.approx(psf.FOCAL_PX)
    assert interior.cx_px == pytest.approx(psf.SIZE_PX / 2)
    assert interior.sensor_width_mm >= 1.0  # Blender clamps narrower sensors
    mesh = psf.sphere()
    uv = project_points(mesh.vertices_local, np.zeros(3), np.eye(3), interior).uv_px[0]
    r = np.linalg.norm(uv - [interior.cx_px, interior.cy_px], axis=1)
    assert r.max() == pytest.approx(psf.DISC_RADIUS_PX, rel=1e-3)
    c = psf.SIZE_PX // 2
    assert np.all((uv >= c) & (uv <= c + 1))  # the whole sphere inside pixel (c, c)
    assert psf.expected_disc_area_px() == pytest.approx(math.pi * 0.09, rel=1e-3)
