import numpy as np
import pytest

from designer.core.heightfield import Heightfield
from designer.errors import DesignerError
from designer.scene.gcp_target import (
    BLACK,
    WHITE,
    target_clearance_m,
    target_mesh,
    target_point_world,
    target_pose_on_terrain,
)
from designer.scene.terrain import procedural_terrain

E0, N0 = 500000.0, 5000000.0


def tilted_plane(a=312.5, bx=0.3, by=-0.45, spacing=1.0, n=41):
    """z = a + bx·(X − E0) + by·(Y − N0) on an n x n grid at UTM coordinates."""
    jj, ii = np.meshgrid(np.arange(n), np.arange(n))
    z = a + bx * jj * spacing + by * ii * spacing
    return Heightfield(E0, N0, spacing, spacing, z), (a, bx, by)


@pytest.mark.parametrize(("x", "y"), [(17.3, 22.9), (0.2, 39.9), (40.0, 0.0), (5.5, 5.5)])
def test_pose_follows_a_tilted_plane_exactly(x, y):
    hf, (a, bx, by) = tilted_plane()
    centre, R = target_pose_on_terrain(hf, E0 + x, N0 + y, size_m=1.0)
    assert centre[0] == E0 + x and centre[1] == N0 + y
    assert centre[2] == pytest.approx(a + bx * x + by * y, abs=1e-9)
    normal = np.array([-bx, -by, 1.0]) / np.sqrt(1 + bx * bx + by * by)
    np.testing.assert_allclose(R[:, 2], normal, atol=1e-12)
    np.testing.assert_allclose(R.T @ R, np.eye(3), atol=1e-12)
    assert np.linalg.det(R) == pytest.approx(1.0, abs=1e-12)
    # x axis: east, tilted into the plane (no north component).
    np.testing.assert_allclose(R[:, 0], np.array([1.0, 0.0, bx]) / np.hypot(1.0, bx), atol=1e-12)


def test_yaw_turns_the_target_counter_clockwise_about_its_normal():
    hf, _ = tilted_plane()
    _, R0 = target_pose_on_terrain(hf, E0 + 20, N0 + 20, 1.0)
    _, R = target_pose_on_terrain(hf, E0 + 20, N0 + 20, 1.0, yaw_rad=np.radians(30))
    c, s = np.cos(np.radians(30)), np.sin(np.radians(30))
    np.testing.assert_allclose(R[:, 0], c * R0[:, 0] + s * R0[:, 1], atol=1e-12)
    np.testing.assert_allclose(R[:, 2], R0[:, 2], atol=1e-15)
    flat = Heightfield(0.0, 0.0, 1.0, 1.0, np.zeros((5, 5)))
    _, Rf = target_pose_on_terrain(flat, 2.0, 2.0, 1.0, yaw_rad=np.pi / 2)
    np.testing.assert_allclose(Rf[:, 0], [0, 1, 0], atol=1e-15)  # x now points north


def test_centre_is_on_the_terrain_surface():
    hf = procedural_terrain(100.0, 100.0, 0.5, 10.0, seed=9, x0_m=E0, y0_m=N0,
                            base_height_m=250.0)
    rng = np.random.default_rng(2)
    for x, y in rng.uniform([E0 + 2, N0 + 2], [E0 + 98, N0 + 98], size=(25, 2)):
        centre, R = target_pose_on_terrain(hf, x, y, size_m=0.8)
        assert centre[2] == hf.height_at(x, y)
        assert R[2, 2] > 0.5  # normal points up, slopes of at most 60°


def test_normal_is_the_mean_slope_under_the_target():
    # A ridge along Y: left flank rises 0.2, right flank falls 0.1 per metre (X).
    x = np.arange(21.0)
    z = np.where(x <= 10, 0.2 * x, 2.0 - 0.1 * (x - 10))
    hf = Heightfield(0.0, 0.0, 1.0, 1.0, np.tile(z, (5, 1)))
    _, R = target_pose_on_terrain(hf, 10.0, 2.0, size_m=4.0)
    mean_slope = (hf.height_at(12.0, 2.0) - hf.height_at(8.0, 2.0)) / 4.0
    np.testing.assert_allclose(R[:, 2], np.array([-mean_slope, 0, 1]) / np.hypot(mean_slope, 1),
                               atol=1e-12)


def test_mesh_centre_vertex_is_the_true_gcp_point():
    hf, _ = tilted_plane()
    centre, R = target_pose_on_terrain(hf, E0 + 12.34, N0 + 23.45, 0.6)
    vertices, faces, colors = target_mesh(centre, R, 0.6, lift_m=0.005)
    truth = target_point_world(centre, R, lift_m=0.005)
    np.testing.assert_array_equal(vertices[0], truth)
    np.testing.assert_allclose(truth - centre, 0.005 * R[:, 2], atol=1e-12)
    # All vertices lie in the lifted plane; the square has the requested side.
    np.testing.assert_allclose((vertices - centre) @ R[:, 2], 0.005, atol=1e-12)
    local = (vertices - centre) @ R
    np.testing.assert_allclose(np.ptp(local[:, 0]), 0.6, atol=1e-12)
    np.testing.assert_allclose(np.ptp(local[:, 1]), 0.6, atol=1e-12)
    assert faces.shape == (4, 4) and colors.shape == (4, 3)


def test_mesh_quads_face_up_with_checker_colours():
    hf, _ = tilted_plane()
    centre, R = target_pose_on_terrain(hf, E0 + 10, N0 + 10, 1.0, yaw_rad=0.4)
    vertices, faces, colors = target_mesh(centre, R, 1.0)
    for quad, colour in zip(faces, colors, strict=True):
        p = vertices[quad]
        for k in (1, 2):  # the fan triangles (0, k, k+1)
            n = np.cross(p[k] - p[0], p[k + 1] - p[0])
            np.testing.assert_allclose(n / np.linalg.norm(n), R[:, 2], atol=1e-9)
        cx, cy = ((p.mean(axis=0) - centre) @ R)[:2]
        expected = WHITE if cx * cy > 0 else BLACK
        np.testing.assert_array_equal(colour, expected)
    assert colors.dtype == np.uint8


def test_clearance_is_the_lift_on_a_plane_and_negative_in_a_hollow():
    hf, _ = tilted_plane()
    centre, R = target_pose_on_terrain(hf, E0 + 20, N0 + 20, 1.0)
    gap = target_clearance_m(hf, centre, R, 1.0, lift_m=0.005)
    assert gap == pytest.approx(0.005 / R[2, 2], abs=1e-9)  # lift along the normal
    x = np.arange(-10.0, 10.5, 0.5)
    xx, yy = np.meshgrid(x, x)
    r2 = xx**2 + yy**2
    # Without lift a plate touching a dome stays above it, but a hollow's rim pokes through.
    dome = Heightfield(-10.0, -10.0, 0.5, 0.5, 5.0 - 0.05 * r2)
    centre, R = target_pose_on_terrain(dome, 3.0, 0.0, 2.0)
    assert target_clearance_m(dome, centre, R, 2.0, lift_m=0.0) == pytest.approx(0, abs=1e-9)
    hollow = Heightfield(-10.0, -10.0, 0.5, 0.5, 0.05 * r2)
    centre, R = target_pose_on_terrain(hollow, 3.0, 0.0, 2.0)
    assert target_clearance_m(hollow, centre, R, 2.0, lift_m=0.005) < -0.01


def test_bad_targets_are_designer_errors():
    hf, _ = tilted_plane()
    with pytest.raises(DesignerError, match="lies outside the terrain") as info:
        target_pose_on_terrain(hf, E0 - 1.0, N0 + 5.0, 1.0)
    assert "\n" not in str(info.value)
    with pytest.raises(DesignerError, match="size must be > 0"):
        target_pose_on_terrain(hf, E0 + 5, N0 + 5, 0.0)
    with pytest.raises(DesignerError, match="size must be > 0"):
        target_mesh(np.zeros(3), np.eye(3), -1.0)
