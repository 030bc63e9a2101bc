"""Lens distortion models against OpenCV, finite differences and their own inverses."""

import math

import cv2
import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from designer.core.distortion import BrownConrady, FisheyeEquidistant
from designer.errors import CameraModelError, NotInvertibleError

CRITERIA = (cv2.TERM_CRITERIA_COUNT | cv2.TERM_CRITERIA_EPS, 100, 1e-14)

BROWN_CASES = [
    BrownConrady(k1=-0.3),
    BrownConrady(k1=0.2),
    BrownConrady(k1=-0.3, k2=0.1, p1=1e-3, p2=-5e-4),
    BrownConrady(k1=0.2, k2=-0.05, k3=0.01, p1=0.01, p2=-0.01),
    BrownConrady(k1=-0.05, k2=0.01, k3=-0.002, p1=0.01, p2=0.01),
    BrownConrady(p1=0.01, p2=-0.01),
]
FISHEYE_CASES = [
    FisheyeEquidistant(),
    FisheyeEquidistant(k1=0.03, k2=-0.01, k3=0.002, k4=-0.0005),
    FisheyeEquidistant(k1=-0.05, k2=0.004),
    FisheyeEquidistant(k1=0.1, k2=0.02, k3=-0.003, k4=0.0002),
]
#: a realistic 20 MP camera (px): fx, fy, cx, cy, W, H
CAMERA = (3648.0, 3648.0, 2736.4, 1823.9, 5472, 3648)
REALISTIC = BrownConrady(k1=-0.3, k2=0.1, p1=1e-3, p2=-5e-4)


def cv_brown(model, xy, K=None):
    """cv2.projectPoints of normalised points (x, y, 1); with K=None in normalised units."""
    K = np.eye(3) if K is None else K
    dist = np.array([model.k1, model.k2, model.p1, model.p2, model.k3])
    obj = np.column_stack([xy, np.ones(len(xy))]).reshape(-1, 1, 3)
    uv, _ = cv2.projectPoints(obj, np.zeros(3), np.zeros(3), K, dist)
    return uv.reshape(-1, 2)


def cv_fisheye(model, rays):
    D = np.array([model.k1, model.k2, model.k3, model.k4]).reshape(4, 1)
    zero = np.zeros((3, 1))
    uv, _ = cv2.fisheye.projectPoints(rays.reshape(1, -1, 3), zero, zero, np.eye(3), D)
    return uv.reshape(-1, 2)


def random_rays(rng, n, max_deg):
    """Unit CV-frame rays uniform in angle off axis up to max_deg, any azimuth."""
    theta = np.radians(rng.uniform(0.0, max_deg, n))
    phi = rng.uniform(0.0, 2 * np.pi, n)
    return np.column_stack([np.sin(theta) * np.cos(phi), np.sin(theta) * np.sin(phi),
                            np.cos(theta)])


def pixel_grid(width, height, step):
    u = np.append(np.arange(0.0, width, step), width)
    v = np.append(np.arange(0.0, height, step), height)
    return np.stack(np.meshgrid(u, v), axis=-1).reshape(-1, 2)


def to_normalised(uv, fx, fy, cx, cy):
    return (uv - [cx, cy]) / [fx, fy]


def radial_slope(model, r):
    """d/dr of r·(1 + k1 r² + k2 r⁴ + k3 r⁶)."""
    s = r * r
    return 1 + 3 * model.k1 * s + 5 * model.k2 * s**2 + 7 * model.k3 * s**3


# ------------------------------------------------------------------ forward vs OpenCV
@pytest.mark.parametrize("model", BROWN_CASES, ids=repr)
def test_brown_distort_matches_cv2_in_normalised_units(model):
    rng = np.random.default_rng(1)
    xy = rng.uniform(-0.9, 0.9, (2000, 2))
    assert np.abs(model.distort(xy) - cv_brown(model, xy)).max() <= 1e-9


def test_brown_distort_matches_cv2_through_a_real_K_for_random_models():
    rng = np.random.default_rng(2)
    fx, fy, cx, cy, _, _ = CAMERA
    K = np.array([[fx, 0, cx], [0, fy + 1.5, cy], [0, 0, 1]])
    for _ in range(20):
        model = BrownConrady(k1=rng.uniform(-0.4, 0.4), k2=rng.uniform(-0.2, 0.2),
                             k3=rng.uniform(-0.05, 0.05), p1=rng.uniform(-0.01, 0.01),
                             p2=rng.uniform(-0.01, 0.01))
        xy = rng.uniform([-0.75, -0.5], [0.75, 0.5], (1000, 2))
        uv = model.distort(xy) * [fx, fy + 1.5] + [cx, cy]
        assert np.abs(uv - cv_brown(model, xy, K)).max() <= 1e-6


def test_brown_distort_is_exact_across_block_boundaries():
    rng = np.random.default_rng(3)
    xy = rng.uniform(-1, 1, (50_001, 2))
    model = BROWN_CASES[3]
    out = model.distort(xy)
    assert out.shape == xy.shape
    assert np.abs(out - cv_brown(model, xy)).max() <= 1e-9


@pytest.mark.parametrize("model", FISHEYE_CASES, ids=repr)
def test_fisheye_distort_rays_matches_cv2_up_to_75_degrees(model):
    rng = np.random.default_rng(4)
    rays = random_rays(rng, 2000, 75.0) * rng.uniform(0.1, 100.0, (2000, 1))
    assert np.abs(model.distort_rays(rays) - cv_fisheye(model, rays)).max() <= 1e-9
    xy = rays[:, :2] / rays[:, 2:]
    assert np.abs(model.distort(xy) - cv_fisheye(model, rays)).max() <= 1e-9


# ------------------------------------------------------------------ inverse vs OpenCV
@pytest.mark.parametrize("model", BROWN_CASES, ids=repr)
def test_brown_undistort_matches_cv2_where_cv2_converges(model):
    rng = np.random.default_rng(5)
    xy_dist = model.distort(rng.uniform(-0.8, 0.8, (2000, 2)))
    dist = np.array([model.k1, model.k2, model.p1, model.p2, model.k3])
    ref = cv2.undistortPointsIter(xy_dist.reshape(-1, 1, 2), np.eye(3), dist, np.eye(3),
                                  np.eye(3), CRITERIA).reshape(-1, 2)
    converged = np.abs(cv_brown(model, ref) - xy_dist).max(axis=1) <= 1e-12
    assert converged.mean() > 0.9
    ours = model.undistort(xy_dist)
    assert np.abs(ours[converged] - ref[converged]).max() <= 1e-9


@pytest.mark.parametrize("model", FISHEYE_CASES, ids=repr)
def test_fisheye_undistort_matches_cv2(model):
    rng = np.random.default_rng(6)
    rays = random_rays(rng, 2000, 75.0)
    xy_dist = model.distort_rays(rays)
    D = np.array([model.k1, model.k2, model.k3, model.k4]).reshape(4, 1)
    ref = cv2.fisheye.undistortPoints(xy_dist.reshape(1, -1, 2), np.eye(3), D,
                                      criteria=CRITERIA).reshape(-1, 2)
    ref_rays = np.column_stack([ref, np.ones(len(ref))])
    converged = np.abs(cv_fisheye(model, ref_rays) - xy_dist).max(axis=1) <= 1e-12
    assert converged.mean() > 0.9
    ours = model.undistort(xy_dist)
    # relative: tan θ reaches 3.7 at 75°
    scale = np.abs(ref[converged]).max()
    assert np.abs(ours[converged] - ref[converged]).max() <= 1e-9 * scale
    assert np.abs(ours - rays[:, :2] / rays[:, 2:]).max() <= 1e-9 * scale


# ----------------------------------------------------------------------- round trips
def test_brown_round_trips_over_a_full_image_grid_to_1e_6_px():
    fx, fy, cx, cy, W, H = CAMERA
    assert REALISTIC.invertibility_problem(*CAMERA) is None
    uv = pixel_grid(W, H, 8.0)
    xy_dist = to_normalised(uv, fx, fy, cx, cy)
    xy = REALISTIC.undistort(xy_dist, tol=1e-6 / fx)
    # the tolerance is a guarantee on the forward residual …
    back = REALISTIC.distort(xy) * [fx, fy] + [cx, cy]
    assert np.abs(back - uv).max() <= 1e-6
    # … and undistort ∘ distort returns the undistorted points
    assert np.abs((REALISTIC.undistort(REALISTIC.distort(xy)) - xy) * fx).max() <= 1e-6


def test_fisheye_150_degree_round_trips_over_a_full_image_grid():
    model = FISHEYE_CASES[1]
    W, H = 4000, 3000
    edge = math.radians(75.0)
    corner_theta_d = model.distort_rays(np.array([[math.sin(edge), 0.0, math.cos(edge)]]))[0, 0]
    f = math.hypot(W / 2, H / 2) / corner_theta_d  # the corners are 75° off axis
    assert model.invertibility_problem(f, f, W / 2, H / 2, W, H) is None
    uv = pixel_grid(W, H, 10.0)
    rays = model.rays_from_distorted(to_normalised(uv, f, f, W / 2, H / 2), tol=1e-6 / f)
    np.testing.assert_allclose(np.linalg.norm(rays, axis=1), 1.0, atol=1e-15, rtol=0)
    theta = np.degrees(np.arctan2(np.hypot(rays[:, 0], rays[:, 1]), rays[:, 2]))
    assert 74.99 < theta.max() < 75.01
    back = model.distort_rays(rays) * f + [W / 2, H / 2]
    assert np.abs(back - uv).max() <= 1e-6
    # and normalised coordinates (z > 0 here) both ways
    xy = model.undistort(to_normalised(uv, f, f, W / 2, H / 2))
    assert np.abs(model.distort(xy) * f + [W / 2, H / 2] - uv).max() <= 1e-6


def test_fisheye_wider_than_180_degrees_returns_rays_behind_the_camera():
    model = FisheyeEquidistant(k1=-0.01, k2=0.001)
    rng = np.random.default_rng(7)
    rays = random_rays(rng, 1000, 110.0)
    assert (rays[:, 2] < 0).any()
    back = model.rays_from_distorted(model.distort_rays(rays))
    assert np.abs(back - rays).max() <= 1e-11
    xy, ok = model.undistort_with_status(model.distort_rays(rays))
    np.testing.assert_array_equal(ok, rays[:, 2] > 0)
    assert np.isnan(xy[~ok]).all()
    with pytest.raises(NotInvertibleError, match="90° or more off axis"):
        model.undistort(model.distort_rays(rays))


def test_fisheye_distort_rays_handles_the_optical_axis_and_backwards_rays():
    model = FISHEYE_CASES[1]
    rays = np.array([[0.0, 0.0, 2.0], [0.0, 0.0, -1.0], [0.0, 0.0, 0.0], [1.0, 0.0, 0.0]])
    out = model.distort_rays(rays)
    np.testing.assert_array_equal(out[0], [0.0, 0.0])
    assert np.isnan(out[1:3]).all()
    theta_d = model.distort_rays(np.array([[1.0, 1e-300, 1e-300]]))[0, 0]
    assert out[3, 0] == pytest.approx(theta_d, abs=1e-15)
    assert out[3, 0] == pytest.approx(
        math.pi / 2 * (1 + sum(k * (math.pi / 2) ** (2 * i + 2) for i, k in
                               enumerate([model.k1, model.k2, model.k3, model.k4]))), abs=1e-14)


def test_fisheye_beyond_180_degrees_has_no_ray():
    model = FisheyeEquidistant()
    with pytest.raises(NotInvertibleError, match="1 of 2 points"):
        model.rays_from_distorted(np.array([[0.1, 0.0], [0.0, math.pi + 0.01]]))
    assert model.invertibility_problem(100.0, 100.0, 200.0, 200.0, 400, 400) is None  # 2.83
    msg = model.invertibility_problem(50.0, 50.0, 200.0, 200.0, 400, 400)  # 5.66 > π
    assert msg is not None and "180°" in msg


# ------------------------------------------------------------------------ Jacobians
@pytest.mark.parametrize("model", BROWN_CASES + FISHEYE_CASES, ids=repr)
def test_jacobian_matches_central_differences(model):
    rng = np.random.default_rng(8)
    xy = np.vstack([rng.uniform(-1.2, 1.2, (500, 2)), [[0.0, 0.0], [1e-9, -2e-9]]])
    h = 1e-6
    numeric = np.empty((len(xy), 2, 2))
    for j in range(2):
        dxy = np.zeros(2)
        dxy[j] = h
        numeric[:, :, j] = (model.distort(xy + dxy) - model.distort(xy - dxy)) / (2 * h)
    analytic = model.jacobian(xy)
    assert analytic.shape == (len(xy), 2, 2)
    assert np.abs(analytic - numeric).max() <= 1e-8 * max(1.0, np.abs(numeric).max())


# ------------------------------------------------------------------------- folding
FOLDING = BrownConrady(k1=-0.5)
FOLD_CAMERA = (1000.0, 1000.0, 600.0, 450.0, 1200, 900)  # corners at r_d = 0.75


def test_max_monotone_radius_for_k1_minus_half():
    r_max = FOLDING.max_monotone_radius()
    assert r_max == pytest.approx(math.sqrt(2 / 3), rel=1e-12)
    assert FOLDING.distort(np.array([[r_max, 0.0]]))[0, 0] == pytest.approx(0.5443, abs=1e-4)


def test_folding_at_the_image_corners_is_reported():
    message = FOLDING.invertibility_problem(*FOLD_CAMERA)
    assert message is not None
    assert "k1=-0.5" in message and "corner" in message and "reduce |k1|" in message
    assert "0.75" in message and "0.5443" in message
    assert "\n" not in message


def test_undistort_raises_for_corner_points_and_inverts_interior_ones():
    fx, fy, cx, cy, W, H = FOLD_CAMERA
    corners = to_normalised(np.array([[0.0, 0.0], [W, 0.0], [0.0, H], [W, H]]), fx, fy, cx, cy)
    interior = to_normalised(pixel_grid(W, H, 20.0), fx, fy, cx, cy)
    interior = interior[np.hypot(interior[:, 0], interior[:, 1]) < 0.54]
    points = np.vstack([interior, corners])
    with pytest.raises(NotInvertibleError) as info:
        FOLDING.undistort(points)
    message = str(info.value)
    assert f"4 of {len(points)} points" in message
    assert "(0.6, -0.45)" in message.replace("-0.6", "0.6")  # first failing corner
    assert "reduce |k1| or the image size/field of view" in message and "\n" not in message
    xy, ok = FOLDING.undistort_with_status(points)
    np.testing.assert_array_equal(ok, np.arange(len(points)) < len(interior))
    assert np.isnan(xy[~ok]).all()
    assert np.abs(FOLDING.distort(xy[ok]) - interior).max() <= 1e-12
    assert np.hypot(xy[ok, 0], xy[ok, 1]).max() < FOLDING.max_monotone_radius()


def test_folding_inverse_holds_up_to_the_edge_of_the_range():
    reach = FOLDING.distort(np.array([[FOLDING.max_monotone_radius(), 0.0]]))[0, 0]
    rd = reach * np.array([0.5, 0.9, 0.999, 0.999999, 1.0 + 1e-9, 1.01, 1.5])
    xy_dist = np.column_stack([rd * 0.6, rd * 0.8])
    xy, ok = FOLDING.undistort_with_status(xy_dist)
    np.testing.assert_array_equal(ok, [True, True, True, True, False, False, False])
    assert np.abs(FOLDING.distort(xy[ok]) - xy_dist[ok]).max() <= 1e-12


def test_no_silent_wrong_answers_on_a_grid_through_the_fold():
    xy_dist = pixel_grid(2.0, 2.0, 0.01) - 1.0
    for model in (FOLDING, BrownConrady(k1=-0.4, k2=0.05, p1=0.02, p2=-0.01)):
        xy, ok = model.undistort_with_status(xy_dist)
        assert 0.05 < ok.mean() < 0.95
        assert np.abs(model.distort(xy[ok]) - xy_dist[ok]).max() <= 1e-12
        assert (np.linalg.det(model.jacobian(xy[ok])) > 0).all()
        assert np.hypot(xy[ok, 0], xy[ok, 1]).max() < model.max_monotone_radius()


def test_a_solution_beyond_a_tangential_fold_is_rejected():
    # Found by a random search: Newton converges to a true preimage, but one where the
    # Jacobian is not positive definite (past the fold the strong p2 makes).
    model = BrownConrady(k1=-0.5946180989483821, k2=0.1755956279116006,
                         p1=0.03488276994697298, p2=-0.16591626266236706)
    xy_dist = np.array([[-0.30125065850183885, -0.5275368244930324]])
    xy, ok = model.undistort_with_status(xy_dist)
    assert not ok[0] and np.isnan(xy).all()
    with pytest.raises(NotInvertibleError, match=r"folds \(Jacobian not positive definite"):
        model.undistort(xy_dist)


def test_tangential_folding_is_found_by_sampling_the_image():
    model = BrownConrady(p1=0.3)  # J11 = 1 + 1.8 y on the axis: folds at y = -0.556
    assert math.isinf(model.max_monotone_radius())
    # y_d = y + 0.3 (x² + 3y²) >= -1/3.6 for all x, y: the top of a tall image has no preimage
    message = model.invertibility_problem(500.0, 500.0, 1000.0, 1000.0, 2000, 2000)
    assert message is not None and "p1=0.3" in message and "reduce |p1|" in message
    assert "pixel (0.0, 0.0)" in message
    # every pixel inverts, but the disc holding the preimages reaches over the fold
    message = model.invertibility_problem(1000.0, 1000.0, 500.0, 0.0, 1000, 600)
    assert message is not None and "not positive definite" in message
    assert "reduce |p1| or the image size/field of view" in message
    assert model.invertibility_problem(1000.0, 1000.0, 500.0, 0.0, 1000, 400) is None
    assert model.invertibility_problem(10000.0, 10000.0, 1000.0, 1000.0, 2000, 2000) is None


def test_fisheye_inverse_converges_where_theta_d_is_nearly_flat():
    # Found by a random search: plain bracketed Newton creeps (linear convergence) here
    # and ran out of iterations; bisection must take over when a step does not halve.
    model = FisheyeEquidistant(k1=0.014473328961955037, k2=0.020080845066786323,
                               k3=-0.003600335340583757, k4=2.93978846051137e-05)
    theta_max = model.max_monotone_theta()
    reach = model.distort_rays(np.array([[math.sin(theta_max), 0.0, math.cos(theta_max)]]))
    theta_d = np.linspace(2.3, reach[0, 0] * (1 - 1e-9), 20001)
    xy_dist = np.column_stack([theta_d * 0.6, theta_d * -0.8])
    rays = model.rays_from_distorted(xy_dist)
    assert np.abs(model.distort_rays(rays) - xy_dist).max() <= 2e-12


def test_fisheye_folding():
    model = FisheyeEquidistant(k1=-0.1)
    theta_max = model.max_monotone_theta()
    assert theta_max == pytest.approx(math.sqrt(1 / 0.3), rel=1e-12)
    message = model.invertibility_problem(500.0, 500.0, 1000.0, 1000.0, 2000, 2000)
    assert message is not None and "k1=-0.1" in message and "fold" in message
    assert model.invertibility_problem(1500.0, 1500.0, 1000.0, 1000.0, 2000, 2000) is None
    reach = theta_max * (1 - 0.1 * theta_max**2)
    ray = model.rays_from_distorted(np.array([[0.0, 0.999 * reach]]))
    assert ray[0, 1] == pytest.approx(math.sin(theta_max), abs=0.05) and ray[0, 2] < 0
    with pytest.raises(NotInvertibleError, match=r"beyond 1\.21"):
        model.rays_from_distorted(np.array([[0.0, 1.001 * reach]]))


@pytest.mark.parametrize(
    ("coefficients", "expected"),
    [((0.0, 0.0, 0.0), math.inf), ((0.2, 0.1, 0.01), math.inf), ((-0.3, 0.1, 0.0), math.inf),
     ((-0.5, 0.0, 0.0), math.sqrt(2 / 3)), ((0.0, -0.2, 0.0), 1.0)],
)
def test_max_monotone_radius_known_values(coefficients, expected):
    model = BrownConrady(*coefficients)
    assert model.max_monotone_radius() == pytest.approx(expected, rel=1e-12)


def test_max_monotone_radius_is_where_the_radial_slope_turns_negative():
    rng = np.random.default_rng(9)
    for _ in range(200):
        model = BrownConrady(k1=rng.uniform(-1, 1), k2=rng.uniform(-1, 1),
                             k3=rng.uniform(-1, 1))
        r_max = model.max_monotone_radius()
        below = np.linspace(0, r_max if math.isfinite(r_max) else 10.0, 2001)[:-1]
        assert (radial_slope(model, below) > 0).all()
        if math.isfinite(r_max):
            assert abs(radial_slope(model, r_max)) < 1e-9
            assert radial_slope(model, r_max * (1 + 1e-6)) < 0


# ------------------------------------------------------------------ property tests
coefficient = st.floats(-0.6, 0.6)


@settings(max_examples=300, deadline=None)
@given(k1=coefficient, k2=st.floats(-0.3, 0.3), k3=st.floats(-0.1, 0.1),
       p1=st.floats(-0.01, 0.01), p2=st.floats(-0.01, 0.01),
       fraction=st.floats(0.0, 0.9), angle=st.floats(0.0, 2 * math.pi))
def test_brown_round_trip_within_the_monotone_region(k1, k2, k3, p1, p2, fraction, angle):
    model = BrownConrady(k1=k1, k2=k2, k3=k3, p1=p1, p2=p2)
    r = fraction * min(model.max_monotone_radius(), 1.5)
    xy = np.array([[r * math.cos(angle), r * math.sin(angle)]])
    assume(np.linalg.det(model.jacobian(xy))[0] > 0.05)
    xy_dist = model.distort(xy)
    back, ok = model.undistort_with_status(xy_dist)
    assert ok[0]
    assert np.abs(back - xy).max() <= 1e-9


@settings(max_examples=200, deadline=None)
@given(k1=st.floats(-0.1, 0.1), k2=st.floats(-0.02, 0.02), k3=st.floats(-0.005, 0.005),
       k4=st.floats(-0.001, 0.001), fraction=st.floats(0.0, 0.95),
       angle=st.floats(0.0, 2 * math.pi))
def test_fisheye_round_trip_within_the_monotone_region(k1, k2, k3, k4, fraction, angle):
    model = FisheyeEquidistant(k1=k1, k2=k2, k3=k3, k4=k4)
    theta = fraction * min(model.max_monotone_theta(), math.pi)
    ray = np.array([[math.sin(theta) * math.cos(angle), math.sin(theta) * math.sin(angle),
                     math.cos(theta)]])
    back = model.rays_from_distorted(model.distort_rays(ray))
    assert np.abs(back - ray).max() <= 1e-9


@settings(max_examples=200, deadline=None)
@given(k1=coefficient, k2=st.floats(-0.3, 0.3), p1=st.floats(-0.05, 0.05),
       x=st.floats(-2, 2), y=st.floats(-2, 2))
def test_brown_undistort_never_returns_a_wrong_answer(k1, k2, p1, x, y):
    model = BrownConrady(k1=k1, k2=k2, p1=p1)
    xy_dist = np.array([[x, y]])
    xy, ok = model.undistort_with_status(xy_dist)
    if ok[0]:
        assert np.abs(model.distort(xy) - xy_dist).max() <= 1e-12
        assert np.linalg.det(model.jacobian(xy))[0] > 0
        assert math.hypot(*xy[0]) < model.max_monotone_radius()
    else:
        assert np.isnan(xy).all()
        with pytest.raises(NotInvertibleError, match="1 of 1 points"):
            model.undistort(xy_dist)


# -------------------------------------------------------------- identity and contract
def test_identity_model_returns_its_input_unchanged():
    model = BrownConrady()
    assert model.is_identity
    assert not BrownConrady(p2=1e-9).is_identity
    assert not FisheyeEquidistant().is_identity  # the equidistant map is no pinhole
    xy = np.random.default_rng(10).uniform(-2, 2, (100, 2))
    for out in (model.distort(xy), model.undistort(xy)):
        assert out is not xy
        np.testing.assert_array_equal(out, xy)
    np.testing.assert_array_equal(model.jacobian(xy), np.broadcast_to(np.eye(2), (100, 2, 2)))


@pytest.mark.parametrize("model", [BROWN_CASES[3], FISHEYE_CASES[1]], ids=repr)
def test_inputs_are_never_modified(model):
    rng = np.random.default_rng(11)
    xy = rng.uniform(-0.5, 0.5, (50, 2))
    rays = random_rays(rng, 50, 60.0)
    for a in (xy, rays):
        a.flags.writeable = False
    kept_xy, kept_rays = xy.copy(), rays.copy()
    model.distort(xy)
    model.jacobian(xy)
    model.undistort(xy)
    model.undistort_with_status(xy)
    model.rays_from_distorted(xy)
    model.distort_rays(rays)
    np.testing.assert_array_equal(xy, kept_xy)
    np.testing.assert_array_equal(rays, kept_rays)


def test_brown_distort_rays_matches_distort_and_rejects_rays_behind():
    model = BROWN_CASES[2]
    rng = np.random.default_rng(12)
    rays = random_rays(rng, 100, 60.0) * rng.uniform(0.5, 5.0, (100, 1))
    np.testing.assert_allclose(model.distort_rays(rays),
                               model.distort(rays[:, :2] / rays[:, 2:]), rtol=0, atol=1e-15)
    rays[::3, 2] *= -1
    rays[1, 2] = 0.0
    out = model.distort_rays(rays)
    behind = rays[:, 2] <= 0
    assert np.isnan(out[behind]).all() and np.isfinite(out[~behind]).all()
    back = model.rays_from_distorted(out[~behind])
    unit = rays[~behind] / np.linalg.norm(rays[~behind], axis=1, keepdims=True)
    assert np.abs(back - unit).max() <= 1e-12


def test_non_finite_and_misshaped_input():
    model = BROWN_CASES[2]
    _, ok = model.undistort_with_status(np.array([[np.nan, 0.0], [0.1, 0.1], [np.inf, 1.0]]))
    np.testing.assert_array_equal(ok, [False, True, False])
    with pytest.raises(NotInvertibleError, match=r"2 of 3 points.*not finite"):
        model.undistort(np.array([[np.nan, 0.0], [0.1, 0.1], [np.inf, 1.0]]))
    with pytest.raises(ValueError, match=r"\(N, 2\)"):
        model.distort(np.zeros(2))
    with pytest.raises(ValueError, match=r"\(N, 3\)"):
        FISHEYE_CASES[0].distort_rays(np.zeros((4, 2)))


def test_a_tight_iteration_limit_fails_instead_of_answering_wrongly():
    model = BrownConrady(k1=-0.45, k2=0.1)
    xy_dist = model.distort(np.array([[0.7, 0.3]]))
    _, ok = model.undistort_with_status(xy_dist, max_iter=1)
    assert not ok[0]
    with pytest.raises(NotInvertibleError, match="did not reach the tolerance"):
        model.undistort(xy_dist, max_iter=1)


@pytest.mark.parametrize("bad", [math.nan, math.inf, "0.1", True, None])
def test_coefficients_must_be_finite_numbers(bad):
    with pytest.raises(CameraModelError, match="k2"):
        BrownConrady(k1=0.1, k2=bad)
    with pytest.raises(CameraModelError, match="k4"):
        FisheyeEquidistant(k4=bad)


def test_to_dict():
    assert BrownConrady(k1=-1, p2=0.5).to_dict() == {
        "model": "brown_conrady", "k1": -1.0, "k2": 0.0, "k3": 0.0, "p1": 0.0, "p2": 0.5}
    assert isinstance(BrownConrady(k1=-1).k1, float)
    assert FisheyeEquidistant(k3=0.25).to_dict() == {
        "model": "fisheye_equidistant", "k1": 0.0, "k2": 0.0, "k3": 0.25, "k4": 0.0}
    model = BROWN_CASES[3]
    assert BrownConrady(**{k: v for k, v in model.to_dict().items() if k != "model"}) == model


def test_a_vanishing_coefficient_puts_the_limit_past_every_image_without_overflow():
    """k2 = -8e-255 (a value the project's random round trip drew): the monotone region
    ends near t = 1e125, where g overflows; the image is invertible, with no warning."""
    import warnings

    from designer.core.distortion import BrownConrady

    d = BrownConrady(k1=0.0078125, k2=-8.411652069934376e-255)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert d.invertibility_problem(64.0, 64.0, 32.0, 32.0, 64.0, 64.0) is None
