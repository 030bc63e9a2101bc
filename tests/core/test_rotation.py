"""Tests of designer.core.rotation: conventions, round trips and independent references.

References: scipy.spatial.transform.Rotation (quaternions, intrinsic Euler angles) and
OpenCV (cv2.Rodrigues, cv2.projectPoints). Each test seeds its own generator.
"""

from __future__ import annotations

import math

import cv2
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from designer.core.rotation import (
    R_CV_FROM_PHOTO,
    colmap_pose_from_photo,
    heading_tilt_roll_from_rotation,
    is_rotation_matrix,
    opencv_rvec_tvec_from_photo,
    opk_from_rotation,
    perturb_rotation,
    photo_pose_from_colmap,
    quaternion_from_rotation,
    rotation_from_heading_tilt_roll,
    rotation_from_opk,
    rotation_from_quaternion,
    rotation_from_rotvec,
    rotvec_from_rotation,
)

PROPERTY = settings(max_examples=300, deadline=None, database=None)
angle = st.floats(-math.pi, math.pi, allow_nan=False)


def random_rotations(rng: np.random.Generator, n: int) -> np.ndarray:
    q = rng.standard_normal((n, 4))
    return Rotation.from_quat(q).as_matrix()  # uniform on SO(3)


def angle_diff(a, b) -> np.ndarray:
    """a − b wrapped to (−π, π]."""
    return np.angle(np.exp(1j * (np.asarray(a) - np.asarray(b))))


def hand_rx(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[1, 0, 0], [0, c, -s], [0, s, c]])


def hand_ry(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])


def hand_rz(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])


# --------------------------------------------------------------------------- ω φ κ
def test_opk_matches_hand_built_product():
    rng = np.random.default_rng(1)
    for omega, phi, kappa in rng.uniform(-math.pi, math.pi, (50, 3)):
        expected = hand_rx(omega) @ hand_ry(phi) @ hand_rz(kappa)
        np.testing.assert_allclose(rotation_from_opk(omega, phi, kappa), expected, atol=1e-15)


def test_opk_zero_is_nadir_with_image_top_north():
    R = rotation_from_opk(0.0, 0.0, 0.0)
    np.testing.assert_array_equal(R, np.eye(3))
    np.testing.assert_allclose(R @ [0, 1, 0], [0, 1, 0])  # image top → north
    np.testing.assert_allclose(R @ [0, 0, -1], [0, 0, -1])  # viewing axis → down


def test_opk_equals_scipy_intrinsic_xyz():
    rng = np.random.default_rng(2)
    angles = rng.uniform(-math.pi, math.pi, (200, 3))
    angles[:, 1] /= 2.0  # φ in [−90°, 90°], scipy's range for the middle angle
    R = rotation_from_opk(angles[:, 0], angles[:, 1], angles[:, 2])
    reference = Rotation.from_euler("XYZ", angles)  # upper case = intrinsic
    np.testing.assert_allclose(R, reference.as_matrix(), atol=1e-14)
    np.testing.assert_allclose(np.stack(opk_from_rotation(R), -1), angles, atol=1e-12)
    np.testing.assert_allclose(
        np.stack(opk_from_rotation(R), -1), reference.as_euler("XYZ"), atol=1e-12
    )


def test_opk_round_trip_random_angles():
    rng = np.random.default_rng(3)
    omega, kappa = rng.uniform(-math.pi, math.pi, (2, 1000))
    phi = rng.uniform(-math.pi / 2, math.pi / 2, 1000)
    R = rotation_from_opk(omega, phi, kappa)
    o2, p2, k2 = opk_from_rotation(R)
    assert np.abs(angle_diff(o2, omega)).max() < 1e-12
    assert np.abs(p2 - phi).max() < 1e-12
    assert np.abs(angle_diff(k2, kappa)).max() < 1e-12
    np.testing.assert_allclose(rotation_from_opk(o2, p2, k2), R, rtol=0, atol=1e-14)


@pytest.mark.parametrize(
    ("omega_deg", "phi_deg", "kappa_deg"),
    [
        (None, 89.999, None),
        (None, -89.999, None),
        (None, 90.0, None),
        (None, -90.0, None),
        (None, None, 180.0),
        (None, None, -180.0),
        (180.0, None, None),
        (-180.0, None, None),
        (180.0, 90.0, -180.0),
        (0.0, 90.0, 0.0),
    ],
)
def test_opk_round_trip_hard_cases(omega_deg, phi_deg, kappa_deg):
    rng = np.random.default_rng(4)
    for _ in range(200):
        omega = math.radians(omega_deg) if omega_deg is not None else rng.uniform(-3.2, 3.2)
        phi = math.radians(phi_deg) if phi_deg is not None else rng.uniform(-1.5, 1.5)
        kappa = math.radians(kappa_deg) if kappa_deg is not None else rng.uniform(-3.2, 3.2)
        R = rotation_from_opk(omega, phi, kappa)
        o2, p2, k2 = opk_from_rotation(R)
        assert np.all(np.isfinite([o2, p2, k2]))
        assert -math.pi / 2 <= p2 <= math.pi / 2
        R2 = rotation_from_opk(o2, p2, k2)
        assert np.abs(R2 - R).max() <= 1e-12
        if phi_deg is not None and abs(phi_deg) == 90.0:
            assert k2 == 0.0  # only ω ± κ is defined: κ is reported as 0
            assert abs(angle_diff(o2, omega + math.copysign(1.0, phi_deg) * kappa)) < 1e-12
        elif phi_deg is None:
            assert abs(angle_diff(o2, omega)) < 1e-12
            assert abs(angle_diff(k2, kappa)) < 1e-12


@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_euler_round_trips_are_exact_across_the_gimbal_lock_band(sign):
    """No tolerance band near ±90° where rebuilding the matrix loses accuracy."""
    rng = np.random.default_rng(21)
    for eps in [0.0, 1e-16, 1e-15, 5e-15, 2e-14, 1e-13, 1e-12, 1e-10, 1e-7, 1e-5, 1e-3]:
        middle = sign * (math.pi / 2 - eps)
        outer, inner = rng.uniform(-math.pi, math.pi, (2, 2000))
        R = rotation_from_opk(outer, middle, inner)
        assert np.abs(rotation_from_opk(*opk_from_rotation(R)) - R).max() < 1e-13
        R = rotation_from_heading_tilt_roll(outer, middle, inner)
        R2 = rotation_from_heading_tilt_roll(*heading_tilt_roll_from_rotation(R))
        assert np.abs(R2 - R).max() < 1e-13


@PROPERTY
@given(angle, st.floats(-math.pi / 2, math.pi / 2), angle)
def test_opk_property_matrix_round_trip(omega, phi, kappa):
    R = rotation_from_opk(omega, phi, kappa)
    np.testing.assert_allclose(rotation_from_opk(*opk_from_rotation(R)), R, rtol=0, atol=1e-12)


# --------------------------------------------------------------------- quaternions
def test_quaternion_matches_scipy_and_round_trips():
    rng = np.random.default_rng(5)
    R = random_rotations(rng, 2000)
    q = quaternion_from_rotation(R)
    q_scipy = Rotation.from_matrix(R).as_quat()[:, [3, 0, 1, 2]]  # scipy is (x, y, z, w)
    q_scipy *= np.where(q_scipy[:, :1] < 0, -1.0, 1.0)
    np.testing.assert_allclose(q, q_scipy, atol=1e-14)
    assert np.all(q[:, 0] >= 0)
    np.testing.assert_allclose(np.linalg.norm(q, axis=-1), 1.0, atol=1e-15)
    np.testing.assert_allclose(rotation_from_quaternion(q), R, atol=1e-14)
    np.testing.assert_allclose(
        rotation_from_quaternion(q), Rotation.from_quat(q[:, [1, 2, 3, 0]]).as_matrix(), atol=1e-14
    )


@pytest.mark.parametrize("angle_rad", [0.0, 1e-12, 1e-6, math.pi - 1e-9, math.pi])
def test_quaternion_hard_angles(angle_rad):
    rng = np.random.default_rng(6)
    axes = rng.standard_normal((500, 3))
    axes /= np.linalg.norm(axes, axis=-1, keepdims=True)
    R = rotation_from_rotvec(axes * angle_rad)
    q = quaternion_from_rotation(R)
    expected = np.concatenate(
        [np.full((500, 1), math.cos(angle_rad / 2)), axes * math.sin(angle_rad / 2)], -1
    )
    sign = np.where(np.sum(q * expected, -1, keepdims=True) < 0, -1.0, 1.0)  # w = 0 at π
    np.testing.assert_allclose(q, sign * expected, atol=1e-15)
    np.testing.assert_allclose(rotation_from_quaternion(q), R, atol=1e-15)


def test_rotation_from_quaternion_normalises_and_rejects_zero():
    q = np.array([0.9, 0.1, -0.3, 0.2])
    np.testing.assert_allclose(
        rotation_from_quaternion(7.5 * q), rotation_from_quaternion(q), atol=1e-15
    )
    np.testing.assert_allclose(
        rotation_from_quaternion(-q), rotation_from_quaternion(q), atol=1e-15
    )
    assert is_rotation_matrix(rotation_from_quaternion(q))
    with pytest.raises(ValueError, match="non-zero"):
        rotation_from_quaternion([0.0, 0.0, 0.0, 0.0])


@PROPERTY
@given(st.tuples(*[st.floats(-1, 1)] * 4).filter(lambda v: np.linalg.norm(v) > 1e-3))
def test_quaternion_property_round_trip(q):
    R = rotation_from_quaternion(q)
    np.testing.assert_allclose(rotation_from_quaternion(quaternion_from_rotation(R)), R, atol=1e-14)


# ------------------------------------------------------------- rotation vectors
def test_exp_and_log_match_cv2_rodrigues():
    rng = np.random.default_rng(7)
    axes = rng.standard_normal((500, 3))
    axes /= np.linalg.norm(axes, axis=-1, keepdims=True)
    rotvecs = axes * rng.uniform(0.0, math.pi - 1e-3, (500, 1))
    R = rotation_from_rotvec(rotvecs)
    for v, R_i in zip(rotvecs, R, strict=True):
        R_cv, _ = cv2.Rodrigues(v)
        np.testing.assert_allclose(R_i, R_cv, atol=1e-14)
        v_cv, _ = cv2.Rodrigues(R_i)
        np.testing.assert_allclose(rotvec_from_rotation(R_i), v_cv[:, 0], atol=1e-12)
    np.testing.assert_allclose(rotvec_from_rotation(R), rotvecs, atol=1e-13)


@pytest.mark.parametrize(
    "angle_rad", [0.0, 1e-300, 1e-12, 1e-8, 1e-4, 0.5, math.pi - 1e-9, math.pi]
)
def test_exp_log_hard_angles(angle_rad):
    rng = np.random.default_rng(8)
    axes = rng.standard_normal((500, 3))
    axes /= np.linalg.norm(axes, axis=-1, keepdims=True)
    rotvecs = axes * angle_rad
    R = rotation_from_rotvec(rotvecs)
    assert np.all(is_rotation_matrix(R, atol=1e-14))
    expected = Rotation.from_rotvec(rotvecs).as_matrix()
    np.testing.assert_allclose(R, expected, atol=1e-15)
    back = rotvec_from_rotation(R)
    if angle_rad == math.pi:  # axis sign is arbitrary at π
        back *= np.where(np.sum(back * rotvecs, -1, keepdims=True) < 0, -1.0, 1.0)
    # relative accuracy even for the tiniest angles
    np.testing.assert_allclose(back, rotvecs, rtol=1e-12, atol=1e-15 * angle_rad)
    np.testing.assert_allclose(rotation_from_rotvec(back), R, atol=1e-15)


def test_log_of_tiny_rotation_is_relatively_exact():
    v = np.array([1e-12, -2e-12, 3e-12])
    np.testing.assert_allclose(rotvec_from_rotation(rotation_from_rotvec(v)), v, rtol=1e-12)
    np.testing.assert_array_equal(rotvec_from_rotation(np.eye(3)), np.zeros(3))


@PROPERTY
@given(st.tuples(*[st.floats(-2, 2)] * 3).filter(lambda v: np.linalg.norm(v) < math.pi - 1e-6))
def test_rotvec_property_round_trip(v):
    np.testing.assert_allclose(rotvec_from_rotation(rotation_from_rotvec(v)), v, atol=1e-12)


# ---------------------------------------------------------- shapes and purity
def test_functions_vectorise_and_do_not_modify_inputs():
    rng = np.random.default_rng(9)
    R = random_rotations(rng, 20).reshape(4, 5, 3, 3)
    R_before = R.copy()
    R.flags.writeable = False  # any in-place write would raise
    omega, phi, kappa = opk_from_rotation(R)
    assert omega.shape == phi.shape == kappa.shape == (4, 5)
    assert quaternion_from_rotation(R).shape == (4, 5, 4)
    assert rotvec_from_rotation(R).shape == (4, 5, 3)
    assert heading_tilt_roll_from_rotation(R)[0].shape == (4, 5)
    assert is_rotation_matrix(R).shape == (4, 5)
    C = np.zeros((4, 5, 3))
    q, t = colmap_pose_from_photo(R, C)
    assert q.shape == (4, 5, 4) and t.shape == (4, 5, 3)
    assert perturb_rotation(R, 0.01, np.random.default_rng(0)).shape == (4, 5, 3, 3)
    np.testing.assert_array_equal(R, R_before)
    for i, j in [(0, 0), (3, 4), (2, 1)]:
        assert quaternion_from_rotation(R)[i, j] == pytest.approx(
            quaternion_from_rotation(R[i, j]), abs=1e-15
        )
        assert omega[i, j] == pytest.approx(opk_from_rotation(R[i, j])[0], abs=1e-15)
    # angles broadcast against each other; float32 in, float64 out
    Rb = rotation_from_opk(np.float32(0.1), np.zeros(3, np.float32), [[0.0], [0.2]])
    assert Rb.shape == (2, 3, 3, 3) and Rb.dtype == np.float64
    assert rotation_from_rotvec(np.zeros((2, 3), np.float32)).dtype == np.float64
    with pytest.raises(ValueError, match=r"\(\.\.\., 3, 3\)"):
        opk_from_rotation(np.eye(4))


def test_r_cv_from_photo():
    np.testing.assert_array_equal(R_CV_FROM_PHOTO, np.diag([1.0, -1.0, -1.0]))
    np.testing.assert_array_equal(R_CV_FROM_PHOTO @ [0, 0, -1], [0, 0, 1])  # view → +z_cv
    np.testing.assert_array_equal(R_CV_FROM_PHOTO @ [0, 1, 0], [0, -1, 0])  # top → −y_cv


def test_is_rotation_matrix():
    rng = np.random.default_rng(10)
    R = random_rotations(rng, 10)
    assert np.all(is_rotation_matrix(R))
    assert not is_rotation_matrix(np.diag([1.0, 1.0, -1.0]))  # reflection
    assert not is_rotation_matrix(1.001 * np.eye(3))
    assert not is_rotation_matrix(np.full((3, 3), np.nan))
    assert not is_rotation_matrix(np.where(np.eye(3) > 0, np.inf, 0.0))
    assert is_rotation_matrix(np.eye(3) + 1e-10)
    assert not is_rotation_matrix(np.eye(3) + 1e-10, atol=1e-12)


# --------------------------------------------------------------- heading, tilt, roll
def view_direction(R):
    return -R[..., :, 2]


def azimuth(v):
    """Clockwise from north of a world vector's horizontal part, in [0, 2π)."""
    return np.mod(np.arctan2(v[..., 0], v[..., 1]), 2 * math.pi)


def test_htr_zero_is_identity_and_heading_90_turns_image_top_east():
    np.testing.assert_array_equal(rotation_from_heading_tilt_roll(0, 0, 0), np.eye(3))
    R = rotation_from_heading_tilt_roll(math.radians(90), 0, 0)
    np.testing.assert_allclose(R @ [0, 1, 0], [1, 0, 0], atol=1e-15)  # image top → east
    np.testing.assert_allclose(R @ [1, 0, 0], [0, -1, 0], atol=1e-15)  # image right → south
    np.testing.assert_allclose(view_direction(R), [0, 0, -1], atol=1e-15)  # still nadir


def test_htr_heading_is_azimuth_of_image_top():
    rng = np.random.default_rng(11)
    heading = rng.uniform(0, 2 * math.pi, 500)
    tilt = rng.uniform(-1.5, 1.5, 500)
    roll = rng.uniform(-math.pi, math.pi, 500)
    R = rotation_from_heading_tilt_roll(heading, tilt, roll)
    image_top = R[..., :, 1]
    assert np.abs(angle_diff(azimuth(image_top), heading)).max() < 1e-12
    # tilt = elevation of the image-top axis
    np.testing.assert_allclose(np.arcsin(image_top[..., 2]), tilt, atol=1e-12)


def test_htr_tilt_is_forward_angle_from_nadir():
    rng = np.random.default_rng(12)
    heading = rng.uniform(0, 2 * math.pi, 500)
    tilt = rng.uniform(0.01, math.pi / 2, 500)
    d = view_direction(rotation_from_heading_tilt_roll(heading, tilt, 0.0))
    from_nadir = np.arctan2(np.hypot(d[:, 0], d[:, 1]), -d[:, 2])
    np.testing.assert_allclose(from_nadir, tilt, atol=1e-12)
    assert np.abs(angle_diff(azimuth(d), heading)).max() < 1e-12  # towards the image top
    # 30° forward oblique heading east: looks east and down, 30° from the vertical
    d30 = view_direction(rotation_from_heading_tilt_roll(math.radians(90), math.radians(30), 0))
    np.testing.assert_allclose(d30, [0.5, 0, -math.sqrt(3) / 2], atol=1e-15)
    # 90° tilt is horizontal, image top up
    R90 = rotation_from_heading_tilt_roll(0, math.pi / 2, 0)
    np.testing.assert_allclose(view_direction(R90), [0, 1, 0], atol=1e-15)
    np.testing.assert_allclose(R90[:, 1], [0, 0, 1], atol=1e-15)


def test_htr_positive_roll_swings_view_to_the_right():
    rng = np.random.default_rng(13)
    heading = rng.uniform(0, 2 * math.pi, 500)
    tilt = rng.uniform(-1.5, 1.5, 500)
    roll = rng.uniform(-1.5, 1.5, 500)
    d = view_direction(rotation_from_heading_tilt_roll(heading, tilt, roll))
    right = np.stack([np.cos(heading), -np.sin(heading), np.zeros(500)], -1)
    forward = np.stack([np.sin(heading), np.cos(heading), np.zeros(500)], -1)
    np.testing.assert_allclose(np.sum(d * right, -1), np.sin(roll), atol=1e-12)
    # the projection onto the along-track vertical plane is still tilted by `tilt`
    np.testing.assert_allclose(np.arctan2(np.sum(d * forward, -1), -d[:, 2]), tilt, atol=1e-12)
    # nadir camera heading north, roll 10°: looks east of nadir, image right rises
    R = rotation_from_heading_tilt_roll(0, 0, math.radians(10))
    assert view_direction(R)[0] > 0 and R[2, 0] > 0
    np.testing.assert_allclose(np.degrees(np.arcsin(view_direction(R)[0])), 10.0)


def test_htr_matches_scipy_intrinsic_zxy():
    rng = np.random.default_rng(14)
    h, t, r = rng.uniform(-math.pi, math.pi, (3, 100))
    expected = Rotation.from_euler("ZXY", np.stack([-h, t, -r], -1)).as_matrix()
    np.testing.assert_allclose(rotation_from_heading_tilt_roll(h, t, r), expected, atol=1e-14)


@pytest.mark.parametrize("tilt_deg", [0.0, 1e-9, 30.0, -45.0, 89.999, 90.0, -90.0])
def test_htr_round_trip(tilt_deg):
    rng = np.random.default_rng(15)
    heading = rng.uniform(0, 2 * math.pi, 300)
    roll = rng.uniform(-math.pi, math.pi, 300)
    tilt = np.full(300, math.radians(tilt_deg))
    R = rotation_from_heading_tilt_roll(heading, tilt, roll)
    h2, t2, r2 = heading_tilt_roll_from_rotation(R)
    assert np.all((h2 >= 0) & (h2 < 2 * math.pi))
    assert np.abs(rotation_from_heading_tilt_roll(h2, t2, r2) - R).max() <= 1e-12
    if abs(tilt_deg) < 90:  # exact angles, including nadir
        assert np.abs(angle_diff(h2, heading)).max() < 1e-12
        assert np.abs(angle_diff(r2, roll)).max() < 1e-12
        np.testing.assert_allclose(t2, tilt, atol=1e-12)
    else:  # image top vertical: roll reported as 0, heading = direction tilted towards
        assert np.all(r2 == 0.0)
        towards = math.copysign(1.0, tilt_deg) * view_direction(R)
        assert np.abs(angle_diff(h2, azimuth(towards))).max() < 1e-9


@PROPERTY
@given(angle, st.floats(-math.pi / 2, math.pi / 2), angle)
def test_htr_property_round_trip(heading, tilt, roll):
    R = rotation_from_heading_tilt_roll(heading, tilt, roll)
    R2 = rotation_from_heading_tilt_roll(*heading_tilt_roll_from_rotation(R))
    np.testing.assert_allclose(R2, R, rtol=0, atol=1e-12)


# --------------------------------------------------------------- COLMAP and OpenCV
C_UTM = np.array([500000.123, 5000000.456, 123.4])


def test_colmap_pose_recovers_utm_centre():
    rng = np.random.default_rng(16)
    R = random_rotations(rng, 200)
    q, t = colmap_pose_from_photo(R, C_UTM)
    assert np.all(q[:, 0] >= 0)
    R_colmap = rotation_from_quaternion(q)
    np.testing.assert_allclose(R_colmap, R_CV_FROM_PHOTO @ np.swapaxes(R, -1, -2), atol=1e-15)
    np.testing.assert_allclose(t, -(R_colmap @ C_UTM), rtol=1e-15, atol=1e-8)
    C_back = -np.einsum("...ji,...j->...i", R_colmap, t)  # −R_colmapᵀ t
    assert np.abs(C_back - C_UTM).max() < 1e-6  # well under 0.1 mm at UTM size
    R2, C2 = photo_pose_from_colmap(q, t)
    np.testing.assert_allclose(R2, R, atol=1e-14)
    assert np.abs(C2 - C_UTM).max() < 1e-6


def test_colmap_pose_of_nadir_camera():
    q, t = colmap_pose_from_photo(np.eye(3), [10.0, 20.0, 100.0])
    # world → CV camera of a nadir camera, image top north: rotation by π about x
    np.testing.assert_allclose(q, [0, 1, 0, 0], atol=1e-15)
    np.testing.assert_allclose(t, [-10.0, 20.0, 100.0])  # the ground is 100 m in front


def test_cv2_project_points_agrees_with_photo_pose():
    rng = np.random.default_rng(17)
    f_px, cx, cy = 1000.0, 960.0, 640.0
    K = np.array([[f_px, 0, cx], [0, f_px, cy], [0, 0, 1]])
    for _ in range(50):
        R = rotation_from_heading_tilt_roll(
            rng.uniform(0, 2 * math.pi), rng.uniform(0, 1.4), rng.uniform(-0.3, 0.3)
        )
        rvec, tvec = opencv_rvec_tvec_from_photo(R, C_UTM)
        d, a = 120.0, 6.0
        points = C_UTM + np.array([[0, 0, -d], [a, 0, -d], [0, a, -d]]) @ R.T
        uv, _ = cv2.projectPoints(points, rvec, tvec, K, None)
        centre, right, up = uv[:, 0, :]
        np.testing.assert_allclose(centre, [cx, cy], atol=1e-6)
        np.testing.assert_allclose(right, [cx + f_px * a / d, cy], atol=1e-6)  # right of pp
        np.testing.assert_allclose(up, [cx, cy - f_px * a / d], atol=1e-6)  # above: smaller v


# --------------------------------------------------------------------- pose noise
@pytest.mark.parametrize(
    ("R", "sigma_rad"),
    [
        (rotation_from_opk(0.3, math.pi / 2, 0.0), np.radians([0.5, 1.0, 2.0])),
        (rotation_from_opk(-0.2, 0.1, 2.5), np.radians(0.05)),
        (np.eye(3), np.radians([10.0, 0.0, 3.0])),
    ],
)
def test_perturb_rotation_statistics(R, sigma_rad):
    n = 20000
    rng = np.random.default_rng(18)
    R_many = np.broadcast_to(R, (n, 3, 3))
    perturbed = perturb_rotation(R_many, sigma_rad, rng)
    assert np.all(np.isfinite(perturbed))
    assert np.all(is_rotation_matrix(perturbed, atol=1e-12))
    delta = rotvec_from_rotation(np.swapaxes(R_many, -1, -2) @ perturbed)
    sigma = np.broadcast_to(sigma_rad, (3,))
    np.testing.assert_allclose(delta.std(axis=0), sigma, rtol=0.03)
    assert np.all(np.abs(delta.mean(axis=0)) <= 5 * sigma / math.sqrt(n))
    angles = opk_from_rotation(perturbed)
    assert np.all(np.isfinite(angles))


def test_perturb_rotation_is_reproducible_and_validates():
    R = rotation_from_opk(0.1, 0.2, 0.3)
    a = perturb_rotation(R, 0.01, np.random.default_rng(19))
    b = perturb_rotation(R, 0.01, np.random.default_rng(19))
    c = perturb_rotation(R, 0.01, np.random.default_rng(20))
    np.testing.assert_array_equal(a, b)
    assert not np.allclose(a, c)
    np.testing.assert_allclose(perturb_rotation(R, 0.0, np.random.default_rng(0)), R, atol=0)
    with pytest.raises(ValueError, match="sigma"):
        perturb_rotation(R, -0.1, np.random.default_rng(0))
    with pytest.raises(TypeError, match="Generator"):
        perturb_rotation(R, 0.1, 42)
