"""Rotations of the photogrammetric core: ω φ κ, quaternions, rotation vectors, poses.

Frames (docs/conventions.md):

* world: X = east, Y = north, Z = up (metres);
* photogrammetric camera frame: x = image right, y = image top, z = backwards (the
  camera looks along −z); the computer-vision frame (OpenCV, COLMAP) is
  ``x_cv = R_CV_FROM_PHOTO · x_photo`` (x right, y down, z forward);
* ``R_cam_to_world`` maps camera-frame vectors to world: ``X = C + R · x_cam``.

Every function takes angles of shape ``(...)`` (radians) or matrices of shape
``(..., 3, 3)``, broadcasts over the leading axes, returns new float64 arrays and never
modifies its inputs. Quaternions are Hamilton ``(w, x, y, z)``; rotation vectors are
axis · angle in radians (the Exp/Log maps of SO(3)).
"""

from __future__ import annotations

import numpy as np

#: x_cv = R_CV_FROM_PHOTO · x_photo (and back: the matrix is its own inverse).
R_CV_FROM_PHOTO: np.ndarray = np.diag([1.0, -1.0, -1.0])
R_CV_FROM_PHOTO.flags.writeable = False

#: cos of the middle Euler angle (a hypot of two matrix elements) below which it is
#: taken as ±90° (gimbal lock) and the inner angle is reported as 0. Reporting 0
#: instead of the true inner angle costs up to 2x this in the rebuilt matrix, so it
#: sits well above rounding noise (~1e-16) and well below the 1e-12 round-trip budget.
_GIMBAL_LOCK_TOL = 1e-14
#: below this angle (rad) sin θ/θ and (1 − cos θ)/θ² use their Taylor series.
_SMALL_ANGLE_RAD = 1e-4


# --------------------------------------------------------------------------- helpers
def _as_matrices(R: np.ndarray, name: str = "R") -> np.ndarray:
    R = np.asarray(R, dtype=np.float64)
    if R.ndim < 2 or R.shape[-2:] != (3, 3):
        raise ValueError(f"{name} must have shape (..., 3, 3), got {R.shape}")
    return R


def _as_vectors(v: np.ndarray, size: int, name: str) -> np.ndarray:
    v = np.asarray(v, dtype=np.float64)
    if v.ndim < 1 or v.shape[-1] != size:
        raise ValueError(f"{name} must have shape (..., {size}), got {v.shape}")
    return v


def _transpose(R: np.ndarray) -> np.ndarray:
    return np.swapaxes(R, -1, -2)


def _elementary(axis: int, angle_rad: np.ndarray) -> np.ndarray:
    """Counter-clockwise rotation by ``angle_rad`` (...) about world axis 0, 1 or 2."""
    c, s = np.cos(angle_rad), np.sin(angle_rad)
    i, j = [(1, 2), (2, 0), (0, 1)][axis]
    out = np.zeros((*np.shape(angle_rad), 3, 3))
    out[..., axis, axis] = 1.0
    out[..., i, i] = c
    out[..., j, j] = c
    out[..., i, j] = -s
    out[..., j, i] = s
    return out


def _angles(*angles_rad: np.ndarray) -> list[np.ndarray]:
    return np.broadcast_arrays(*(np.asarray(a, dtype=np.float64) for a in angles_rad))


def _skew(v: np.ndarray) -> np.ndarray:
    """[v]×, shape (..., 3, 3), so that [v]× · u = v × u."""
    x, y, z = v[..., 0], v[..., 1], v[..., 2]
    o = np.zeros_like(x)
    return np.stack(
        [np.stack([o, -z, y], -1), np.stack([z, o, -x], -1), np.stack([-y, x, o], -1)], -2
    )


def _wrap_0_2pi(angle_rad: np.ndarray) -> np.ndarray:
    a = np.mod(angle_rad, 2.0 * np.pi)
    return np.where(a >= 2.0 * np.pi, 0.0, a)  # mod(−1e-17, 2π) rounds to 2π


# --------------------------------------------------------------------------- ω φ κ
def rotation_from_opk(omega_rad, phi_rad, kappa_rad) -> np.ndarray:
    """R_cam_to_world = Rx(ω) · Ry(φ) · Rz(κ), shape (..., 3, 3).

    Angles in radians, counter-clockwise positive, broadcast against each other.
    ω = φ = κ = 0 is a nadir camera with the image top pointing north. This equals
    scipy's intrinsic ``Rotation.from_euler('XYZ', [ω, φ, κ])``.
    """
    omega, phi, kappa = _angles(omega_rad, phi_rad, kappa_rad)
    return _elementary(0, omega) @ _elementary(1, phi) @ _elementary(2, kappa)


def opk_from_rotation(R) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(ω, φ, κ) in radians, each of shape (...), from R_cam_to_world (..., 3, 3).

    φ ∈ [−π/2, π/2] is atan2(R13, hypot(R11, R12)) (accurate near ±90°, unlike asin),
    κ = atan2(−R12, R11) ∈ (−π, π]. ω is taken from R · Rz(κ)ᵀ = Rx(ω) · Ry(φ), whose
    second column is (0, cos ω, sin ω): this equals atan2(−R23, R33) for an exact
    rotation, but stays consistent with the computed κ when cos φ is tiny, so
    matrix → angles → matrix is exact to rounding at φ = ±89.999° too. At φ = ±90°
    (hypot(R11, R12) < 1e-14) only ω ± κ is defined: κ = 0 and ω carries the rotation.
    """
    R = _as_matrices(R)
    cos_phi = np.hypot(R[..., 0, 0], R[..., 0, 1])
    phi = np.arctan2(R[..., 0, 2], cos_phi)
    kappa = np.where(cos_phi < _GIMBAL_LOCK_TOL, 0.0, np.arctan2(-R[..., 0, 1], R[..., 0, 0]))
    ck, sk = np.cos(kappa), np.sin(kappa)
    omega = np.arctan2(sk * R[..., 2, 0] + ck * R[..., 2, 1], sk * R[..., 1, 0] + ck * R[..., 1, 1])
    return omega[()], phi[()], kappa[()]


# --------------------------------------------------------------- heading, tilt, roll
def rotation_from_heading_tilt_roll(heading_rad, tilt_rad, roll_rad) -> np.ndarray:
    """R_cam_to_world (..., 3, 3) of a camera as a flight planner describes it.

    R = Rz(−heading) · Rx(tilt) · Ry(−roll), angles in radians (broadcast):

    * heading: azimuth, clockwise from grid north, of the image-top axis R·(0,1,0).
      (0, 0, 0) is the identity: nadir, image top north, image right east. Heading
      π/2 turns the image top to east, so image right points south.
    * tilt: elevation of the image-top axis above the horizon. With roll = 0 it is the
      angle of the viewing axis (−z) from nadir towards the image top (forward
      oblique): 0 = nadir, π/2 = horizontal, looking towards the heading. For any
      roll, tilt is the angle from nadir of the viewing axis projected onto the
      vertical plane through the heading direction.
    * roll: rotation about the camera's image-top (along-track) axis, applied first.
      Positive roll swings the viewing axis to the right of the along-track plane
      by ``roll``: d · (cos h, −sin h, 0) = sin(roll) for view direction d. The image
      right axis (camera +x) then rises above the horizon.

    Inverse: :func:`heading_tilt_roll_from_rotation`.
    """
    heading, tilt, roll = _angles(heading_rad, tilt_rad, roll_rad)
    return _elementary(2, -heading) @ _elementary(0, tilt) @ _elementary(1, -roll)


def heading_tilt_roll_from_rotation(R) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(heading, tilt, roll) in radians, shapes (...), from R_cam_to_world (..., 3, 3).

    heading ∈ [0, 2π), tilt ∈ [−π/2, π/2], roll ∈ (−π, π]; see
    :func:`rotation_from_heading_tilt_roll`. Nadir (tilt = 0) is regular: heading and
    roll are both defined by the image-top axis. At |tilt| = π/2 the image top points
    straight up or down and has no azimuth: roll = 0 and heading is the azimuth of
    the horizontal viewing axis (of its opposite at tilt = −π/2), so
    matrix → angles → matrix stays exact.
    """
    R = _as_matrices(R)
    # R = Rz(a)·Rx(t)·Ry(b) with a = −heading, b = −roll; its third row is
    # (−cos t·sin b, sin t, cos t·cos b) and R·Ry(b)ᵀ has first column (cos a, sin a, 0).
    cos_tilt = np.hypot(R[..., 2, 0], R[..., 2, 2])
    tilt = np.arctan2(R[..., 2, 1], cos_tilt)
    roll = np.where(cos_tilt < _GIMBAL_LOCK_TOL, 0.0, np.arctan2(R[..., 2, 0], R[..., 2, 2]))
    cb, sb = np.cos(roll), -np.sin(roll)
    a = np.arctan2(cb * R[..., 1, 0] + sb * R[..., 1, 2], cb * R[..., 0, 0] + sb * R[..., 0, 2])
    return _wrap_0_2pi(-a)[()], tilt[()], roll[()]


# --------------------------------------------------------------------- quaternions
def quaternion_from_rotation(R) -> np.ndarray:
    """Unit Hamilton quaternion (w, x, y, z), shape (..., 4), w ≥ 0, of R (..., 3, 3).

    Shepperd's method: of the four equivalent formulas the one whose pivot (4·w², 4·x²,
    4·y² or 4·z²) is largest is used, so no component is found by dividing by a
    small number; accurate to rounding for every rotation angle, including π.
    """
    R = _as_matrices(R)
    r = [[R[..., i, j] for j in range(3)] for i in range(3)]
    trace = r[0][0] + r[1][1] + r[2][2]
    # Row k of this symmetric matrix equals 4·q_k·q for an exact rotation.
    rows = [
        [1 + trace, r[2][1] - r[1][2], r[0][2] - r[2][0], r[1][0] - r[0][1]],
        [r[2][1] - r[1][2], 1 + 2 * r[0][0] - trace, r[0][1] + r[1][0], r[0][2] + r[2][0]],
        [r[0][2] - r[2][0], r[0][1] + r[1][0], 1 + 2 * r[1][1] - trace, r[1][2] + r[2][1]],
        [r[1][0] - r[0][1], r[0][2] + r[2][0], r[1][2] + r[2][1], 1 + 2 * r[2][2] - trace],
    ]
    K = np.stack([np.stack(row, -1) for row in rows], -2)  # (..., 4, 4)
    pivot = np.argmax(np.diagonal(K, axis1=-2, axis2=-1), axis=-1)
    q = np.take_along_axis(K, pivot[..., None, None], axis=-2)[..., 0, :]
    q = q / np.linalg.norm(q, axis=-1, keepdims=True)
    return np.where(q[..., :1] < 0.0, -q, q)


def rotation_from_quaternion(q_wxyz) -> np.ndarray:
    """Rotation matrix (..., 3, 3) of a Hamilton quaternion (w, x, y, z), shape (..., 4).

    q is normalised first (q and −q give the same matrix); a zero or non-finite
    quaternion raises ValueError.
    """
    q = _as_vectors(q_wxyz, 4, "q_wxyz")
    norm = np.linalg.norm(q, axis=-1, keepdims=True)
    if not np.all(np.isfinite(norm) & (norm > 0.0)):
        raise ValueError("quaternion must be finite and non-zero to describe a rotation")
    w, x, y, z = np.moveaxis(q / norm, -1, 0)
    return np.stack(
        [
            np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], -1),
            np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], -1),
            np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], -1),
        ],
        -2,
    )


# ------------------------------------------------------------- rotation vectors
def rotation_from_rotvec(rotvec) -> np.ndarray:
    """Exp map: rotation matrix (..., 3, 3) of rotation vectors (..., 3) = axis·angle (rad).

    Rodrigues: R = I + A·[v]× + B·[v]×² with A = sin θ/θ, B = (1 − cos θ)/θ²,
    θ = |v|. B is evaluated as ½·(sin(θ/2)/(θ/2))² (no cancellation) and both use
    their Taylor series below 1e-4 rad, so tiny angles and θ = 0 are exact; nothing
    divides by sin θ, so angles near and at π are exact too.
    """
    v = _as_vectors(rotvec, 3, "rotvec")
    theta = np.linalg.norm(v, axis=-1)
    small = theta < _SMALL_ANGLE_RAD
    t = np.where(small, 1.0, theta)  # keeps the unused branch free of 0/0
    t2 = theta * theta
    A = np.where(small, 1.0 - t2 / 6.0 + t2 * t2 / 120.0, np.sin(t) / t)
    half_sinc = np.sin(t / 2.0) / (t / 2.0)
    B = np.where(small, 0.5 - t2 / 24.0 + t2 * t2 / 720.0, 0.5 * half_sinc * half_sinc)
    K = _skew(v)
    return np.eye(3) + A[..., None, None] * K + B[..., None, None] * (K @ K)


def rotvec_from_rotation(R) -> np.ndarray:
    """Log map: rotation vector (..., 3) = axis·angle, angle ∈ [0, π], of R (..., 3, 3).

    Goes through the Shepperd quaternion: θ = 2·atan2(|q_xyz|, w) and
    v = θ · q_xyz/|q_xyz|, which is accurate near 0 (series for θ/|q_xyz|) and near π
    (no division by sin θ). At exactly π the sign of the axis is arbitrary.
    """
    q = quaternion_from_rotation(R)
    w = q[..., 0]
    n = np.linalg.norm(q[..., 1:], axis=-1)
    small = n < 1e-8  # then w ≈ 1 and θ/n = 2/w·(1 − n²/(3w²) + …)
    n_safe = np.where(small, 1.0, n)
    w_safe = np.where(small, w, 1.0)
    ratio = n / w_safe
    factor = np.where(
        small,
        2.0 / w_safe * (1.0 - ratio * ratio / 3.0),
        2.0 * np.arctan2(n, w) / n_safe,
    )
    return factor[..., None] * q[..., 1:]


# --------------------------------------------------------------------- pose noise
def perturb_rotation(R_cam_to_world, sigma_rad, rng: np.random.Generator) -> np.ndarray:
    """R' = R · Exp(δ), δ ~ N(0, σ²) independently per camera axis (x, y, z), radians.

    R_cam_to_world: (..., 3, 3); sigma_rad: scalar or (3,) (anything broadcasting to
    (..., 3)), ≥ 0; rng: a ``numpy.random.Generator`` (the only source of randomness,
    so a seed reproduces the draw). The noise is a small rotation in the camera frame:
    isotropic, and no Euler angles are involved, so R at φ = ±90° is fine.
    Returns (..., 3, 3).
    """
    R = _as_matrices(R_cam_to_world, "R_cam_to_world")
    if not isinstance(rng, np.random.Generator):
        raise TypeError("rng must be a numpy.random.Generator, e.g. np.random.default_rng(seed)")
    sigma = np.asarray(sigma_rad, dtype=np.float64)
    if not np.all(np.isfinite(sigma) & (sigma >= 0.0)):
        raise ValueError(f"sigma_rad must be finite and >= 0, got {sigma_rad!r}")
    delta = rng.standard_normal((*R.shape[:-2], 3)) * sigma
    return R @ rotation_from_rotvec(delta)


# ----------------------------------------------------------- COLMAP and OpenCV poses
def colmap_pose_from_photo(R_cam_to_world, C_world) -> tuple[np.ndarray, np.ndarray]:
    """COLMAP ``images.txt`` pose (q_wxyz (..., 4), t (..., 3)) of a photogrammetric pose.

    R_cam_to_world (..., 3, 3), perspective centre C_world (..., 3) in metres.
    COLMAP maps world to the CV camera frame: R_colmap = diag(1, −1, −1) · Rᵀ,
    t = −R_colmap · C; q_wxyz is the Hamilton quaternion of R_colmap with w ≥ 0.
    """
    R_colmap, t = _colmap_matrix_and_t(R_cam_to_world, C_world)
    return quaternion_from_rotation(R_colmap), t


def photo_pose_from_colmap(q_wxyz, t) -> tuple[np.ndarray, np.ndarray]:
    """(R_cam_to_world (..., 3, 3), C_world (..., 3)) from a COLMAP (q_wxyz, t).

    Inverse of :func:`colmap_pose_from_photo`: R = (diag(1, −1, −1) · R_colmap)ᵀ,
    C = −R_colmapᵀ · t.
    """
    R_colmap = rotation_from_quaternion(q_wxyz)
    t = _as_vectors(t, 3, "t")
    C = -(_transpose(R_colmap) @ t[..., None])[..., 0]
    return _transpose(R_CV_FROM_PHOTO @ R_colmap), C


def opencv_rvec_tvec_from_photo(R_cam_to_world, C_world) -> tuple[np.ndarray, np.ndarray]:
    """OpenCV (rvec (..., 3), tvec (..., 3)) for ``cv2.projectPoints`` of a photo pose.

    rvec = Log(R_colmap) (Rodrigues vector, rad) and tvec = t, with R_colmap and t as in
    :func:`colmap_pose_from_photo`: x_cv = R_colmap · X + t.
    """
    R_colmap, t = _colmap_matrix_and_t(R_cam_to_world, C_world)
    return rotvec_from_rotation(R_colmap), t


def _colmap_matrix_and_t(R_cam_to_world, C_world) -> tuple[np.ndarray, np.ndarray]:
    R = _as_matrices(R_cam_to_world, "R_cam_to_world")
    C = _as_vectors(C_world, 3, "C_world")
    R_colmap = R_CV_FROM_PHOTO @ _transpose(R)
    return R_colmap, -(R_colmap @ C[..., None])[..., 0]


# ----------------------------------------------------------------------- checks
def is_rotation_matrix(R, atol: float = 1e-9) -> np.ndarray:
    """Bool array (...): R (..., 3, 3) is finite, RᵀR = I and det R = +1 within atol.

    A reflection (det −1) is not a rotation. An array whose trailing shape is not
    (3, 3) raises ValueError.
    """
    R = _as_matrices(R)
    finite = np.all(np.isfinite(R), axis=(-2, -1))
    R = np.where(finite[..., None, None], R, 0.0)  # keeps inf/nan out of the maths
    orthonormal = np.all(np.abs(_transpose(R) @ R - np.eye(3)) <= atol, axis=(-2, -1))
    proper = np.abs(np.linalg.det(R) - 1.0) <= atol
    return finite & orthonormal & proper
