import cv2
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from designer.core.distortion import BrownConrady, FisheyeEquidistant
from designer.core.heightfield import Heightfield
from designer.core.interior import InteriorOrientation
from designer.core.projection import (
    footprint_on_plane,
    ground_sample_distance_m,
    intersect_plane,
    pixel_rays_world,
    project_pairwise,
    project_points,
)
from designer.core.rotation import opencv_rvec_tvec_from_photo, rotation_from_opk
from tests.synthetic import ORIGIN_WORLD


def camera(distortion=None, x0=0.0, y0=0.0, f=8.8):
    return InteriorOrientation(
        focal_length_mm=f, sensor_width_mm=13.2, sensor_height_mm=8.8,
        image_width_px=5472, image_height_px=3648,
        principal_point_x_mm=x0, principal_point_y_mm=y0, distortion=distortion)


def random_pose(rng, centre=ORIGIN_WORLD, tilt_deg=15.0):
    C = centre + rng.uniform([-30, -30, 80], [30, 30, 120])
    R = rotation_from_opk(*np.radians(rng.uniform(-tilt_deg, tilt_deg, 3)))
    return C, R


def points_in_view(rng, C, R, cam, n=2000, depth=(60.0, 140.0)):
    """World points that project inside the image of (C, R, cam)."""
    uv = rng.uniform([0, 0], cam.image_size_px, size=(n, 2))
    rays = pixel_rays_world(uv, R, cam)
    d = rng.uniform(*depth, size=n)
    return C + rays * d[:, None], uv


def cv2_project(points, C, R, cam, dist=None, fisheye=False):
    rvec, _ = opencv_rvec_tvec_from_photo(R, C)
    # OpenCV's pixel origin is the centre of the top-left pixel: cx_cv = cx - 0.5
    K = cam.K_px.copy()
    K[0, 2] -= 0.5
    K[1, 2] -= 0.5
    # cv2 wants camera-relative values; passing ORIGIN_WORLD-sized points to its float math
    # is exactly what the conventions warn about, so shift both by C.
    local = (points - C).reshape(-1, 1, 3)
    tvec_local = np.zeros(3)
    if fisheye:
        out, _ = cv2.fisheye.projectPoints(local, rvec.reshape(3, 1), tvec_local.reshape(3, 1),
                                           K, np.asarray(dist, float).reshape(4, 1))
    else:
        out, _ = cv2.projectPoints(local, rvec, tvec_local, K,
                                   np.zeros(5) if dist is None else np.asarray(dist, float))
    return out.reshape(-1, 2) + 0.5


@pytest.mark.parametrize("seed", range(5))
@pytest.mark.parametrize(
    "model",
    [None,
     BrownConrady(k1=-0.3, k2=0.12, k3=-0.02, p1=2e-3, p2=-1.5e-3),
     BrownConrady(k1=0.2, k2=-0.05, p1=-1e-3, p2=1e-3)],
)
def test_projection_matches_opencv(seed, model):
    rng = np.random.default_rng(seed)
    cam = camera(model, x0=rng.uniform(-0.1, 0.1), y0=rng.uniform(-0.1, 0.1))
    C, R = random_pose(rng)
    points = C + rng.uniform([-60, -40, -130], [60, 40, -70], size=(3000, 3))
    proj = project_points(points, C, R, cam)
    assert proj.in_front.all()
    dist = None if model is None else [model.k1, model.k2, model.p1, model.p2, model.k3]
    expected = cv2_project(points, C, R, cam, dist)
    assert np.max(np.abs(proj.uv_px[0] - expected)) <= 1e-6


@pytest.mark.parametrize("seed", range(3))
def test_fisheye_projection_matches_opencv(seed):
    rng = np.random.default_rng(seed)
    model = FisheyeEquidistant(k1=0.03, k2=-0.01, k3=0.002, k4=-0.0005)
    cam = InteriorOrientation(focal_length_mm=1.8, sensor_width_mm=6.4, sensor_height_mm=4.8,
                              image_width_px=4000, image_height_px=3000,
                              principal_point_x_mm=0.02, distortion=model)
    C, R = random_pose(rng)
    # directions up to 75 degrees off the viewing axis (a 150 degree fisheye)
    theta = rng.uniform(0, np.radians(75), 2000)
    azim = rng.uniform(0, 2 * np.pi, 2000)
    dirs_cv = np.column_stack([np.sin(theta) * np.cos(azim), np.sin(theta) * np.sin(azim),
                               np.cos(theta)])
    dirs_world = dirs_cv @ np.diag([1.0, -1.0, -1.0]) @ R.T
    points = C + dirs_world * rng.uniform(5, 50, (2000, 1))
    proj = project_points(points, C, R, cam)
    expected = cv2_project(points, C, R, cam, [model.k1, model.k2, model.k3, model.k4],
                           fisheye=True)
    assert proj.in_front.all()
    assert np.max(np.abs(proj.uv_px[0] - expected)) <= 1e-6


def test_utm_sized_coordinates_keep_sub_millipixel_precision():
    rng = np.random.default_rng(11)
    cam = camera(BrownConrady(k1=-0.1, p1=1e-3))
    C, R = random_pose(rng)
    points, _ = points_in_view(rng, C, R, cam)
    uv_world = project_points(points, C, R, cam).uv_px[0]
    # the same scene in local coordinates (what the project origin is for)
    uv_local = project_points(points - ORIGIN_WORLD, C - ORIGIN_WORLD, R, cam).uv_px[0]
    assert np.max(np.abs(uv_world - uv_local)) <= 1e-3
    # and float32 world coordinates would be off by far more: the hazard is real
    uv_f32 = project_points(points.astype(np.float32), C.astype(np.float32), R, cam).uv_px[0]
    assert np.max(np.abs(uv_f32 - uv_local)) > 0.1


def test_points_behind_the_camera_are_flagged_and_never_projected():
    cam = camera(BrownConrady(k1=-0.3))
    C = ORIGIN_WORLD.copy()
    R = np.eye(3)  # nadir: looks down
    points = np.array([
        C + [0, 0, -50],     # below: in front
        C + [0, 0, 50],      # above: behind
        C + [10, 5, 0],      # in the image plane: not in front
        C + [1e3, 0, 1e-3],  # just behind
    ])
    proj = project_points(points, C, R, cam)
    assert proj.in_front[0].tolist() == [True, False, False, False]
    assert np.isfinite(proj.uv_px[0, 0]).all()
    assert np.isnan(proj.uv_px[0, 1:]).all()
    assert proj.in_image[0].tolist() == [True, False, False, False]
    assert proj.depth_m[0, 1] == pytest.approx(-50)


def test_in_image_uses_the_half_open_image_rectangle():
    cam = camera()
    C, R = ORIGIN_WORLD.copy(), np.eye(3)
    uv = np.array([[1e-6, 1e-6], [5471.999, 3647.999], [5472.0 + 1e-6, 100.0], [-1e-6, 10.0]])
    points = C + pixel_rays_world(uv, R, cam) * 100.0
    proj = project_points(points, C, R, cam)
    assert np.allclose(proj.uv_px[0], uv, atol=1e-6)
    assert proj.in_image[0].tolist() == [True, True, False, False]


def test_many_cameras_at_once_match_one_at_a_time():
    rng = np.random.default_rng(5)
    cam = camera(BrownConrady(k1=-0.05))
    poses = [random_pose(rng) for _ in range(7)]
    C = np.array([p[0] for p in poses])
    R = np.array([p[1] for p in poses])
    points = ORIGIN_WORLD + rng.uniform([-50, -50, -5], [50, 50, 5], size=(1000, 3))
    together = project_points(points, C, R, cam)
    for m in range(7):
        alone = project_points(points, C[m], R[m], cam)
        assert np.array_equal(together.in_image[m], alone.in_image[0])
        np.testing.assert_allclose(together.uv_px[m], alone.uv_px[0], atol=1e-9)


def test_each_point_in_its_own_camera_matches_one_camera_at_a_time():
    """project_pairwise (the plan figures' many cameras with a few points each) against
    project_points camera by camera, to the bit, also behind a camera and for a fisheye."""
    rng = np.random.default_rng(8)
    fisheye = FisheyeEquidistant(k1=0.03, k2=-0.01, k3=0.002, k4=-0.0005)
    for cam in (camera(BrownConrady(k1=-0.05, p1=1e-3)), camera(fisheye)):
        poses = [random_pose(rng) for _ in range(9)]
        C = np.array([p[0] for p in poses])
        R = np.array([p[1] for p in poses])
        points = ORIGIN_WORLD + rng.uniform([-80, -80, -5], [80, 80, 120], size=(3000, 3))
        which = rng.integers(0, 9, len(points))
        pairwise = project_pairwise(points, C, R, which, cam)
        assert pairwise.in_front.any() and not pairwise.in_front.all()
        for m in range(9):
            sel = which == m
            alone = project_points(points[sel], C[m], R[m], cam)
            assert np.array_equal(pairwise.in_front[sel], alone.in_front[0])
            assert np.array_equal(pairwise.in_image[sel], alone.in_image[0])
            # the same numbers to the bit: each camera's points are turned as one product
            np.testing.assert_array_equal(pairwise.uv_px[sel], alone.uv_px[0])
            np.testing.assert_array_equal(pairwise.depth_m[sel], alone.depth_m[0])


@settings(max_examples=60, deadline=None)
@given(
    omega=st.floats(-40, 40), phi=st.floats(-40, 40), kappa=st.floats(-180, 180),
    k1=st.floats(-0.15, 0.25), p1=st.floats(-2e-3, 2e-3),
    u=st.floats(0, 5472), v=st.floats(0, 3648), depth=st.floats(10.0, 5000.0),
)
def test_project_after_back_project_returns_the_pixel(omega, phi, kappa, k1, p1, u, v, depth):
    cam = camera(BrownConrady(k1=k1, k2=0.0, p1=p1), x0=0.03, y0=-0.02)
    R = rotation_from_opk(*np.radians([omega, phi, kappa]))
    C = ORIGIN_WORLD
    ray = pixel_rays_world(np.array([[u, v]]), R, cam)
    point = C + ray * depth
    uv = project_points(point, C, R, cam).uv_px[0, 0]
    assert np.max(np.abs(uv - [u, v])) <= 1e-6


def test_gsd_matches_the_flight_planning_formula():
    cam = camera()
    height = 100.0
    gsd_cm_qgc = 100 * height * 13.2 / (5472 * 8.8)
    assert ground_sample_distance_m(cam, height) * 100 == pytest.approx(gsd_cm_qgc, rel=1e-12)


def test_nadir_footprint_is_image_size_times_gsd():
    cam = camera()
    C = ORIGIN_WORLD + [0, 0, 100.0]
    corners = footprint_on_plane(C, np.eye(3), cam, height_m=ORIGIN_WORLD[2])
    gsd = ground_sample_distance_m(cam, 100.0)
    width = corners[1, 0] - corners[0, 0]
    height = corners[0, 1] - corners[3, 1]   # image top is north
    assert width == pytest.approx(5472 * gsd, rel=1e-9)
    assert height == pytest.approx(3648 * gsd, rel=1e-9)
    assert np.allclose(corners[:, 2], ORIGIN_WORLD[2])


def test_rays_above_the_horizon_miss_the_plane():
    rays = np.array([[0, 0, -1.0], [1.0, 0, 0.1], [1.0, 0, 0]])
    hits = intersect_plane(np.array([0, 0, 10.0]), rays, 0.0)
    assert np.allclose(hits[0], [0, 0, 0])
    assert np.isnan(hits[1:]).all()


def wavy_terrain():
    x = np.linspace(0, 100, 101)
    y = np.linspace(0, 80, 81)
    X, Y = np.meshgrid(x, y)
    Z = ORIGIN_WORLD[2] + 10 * np.sin(X / 15) * np.cos(Y / 11)
    return Heightfield(x0_m=ORIGIN_WORLD[0], y0_m=ORIGIN_WORLD[1], dx_m=1.0, dy_m=1.0, heights_m=Z)


def test_rays_hit_the_heightfield_on_its_surface():
    rng = np.random.default_rng(2)
    terrain = wavy_terrain()
    cam = camera(BrownConrady(k1=-0.1))
    C = ORIGIN_WORLD + [50, 40, 45]
    R = rotation_from_opk(*np.radians([5, -4, 30]))
    uv = rng.uniform([0, 0], cam.image_size_px, size=(3000, 2))
    rays = pixel_rays_world(uv, R, cam)
    hits = terrain.intersect_rays(np.broadcast_to(C, rays.shape), rays)
    ok = np.isfinite(hits[:, 0])
    assert ok.mean() > 0.5
    gap = hits[ok, 2] - terrain.height_at(hits[ok, 0], hits[ok, 1])
    assert np.max(np.abs(gap)) < 1e-5
    # the hit is where the pixel looks
    uv_back = project_points(hits[ok], C, R, cam).uv_px[0]
    assert np.max(np.abs(uv_back - uv[ok])) < 1e-4
    # misses really miss: they leave the grid extent
    assert not ok.all()


def test_heightfield_intersection_of_a_tilted_plane_is_exact():
    x = np.arange(0, 51.0)
    X, Y = np.meshgrid(x, x)
    plane = Heightfield(x0_m=0, y0_m=0, dx_m=1, dy_m=1, heights_m=0.2 * X - 0.1 * Y + 3)
    origin = np.array([[25.0, 25.0, 100.0]])
    direction = np.array([[0.1, -0.1, -1.0]])
    hit = plane.intersect_rays(origin, direction, tol_m=1e-9)[0]
    # analytic: O + tD on z = 0.2x - 0.1y + 3
    t = (3 + 0.2 * 25 - 0.1 * 25 - 100) / (-1.0 - 0.2 * 0.1 + 0.1 * -0.1)
    expected = origin[0] + t * direction[0]
    assert np.allclose(hit, expected, atol=1e-8)
