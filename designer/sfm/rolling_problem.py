"""The rolling-shutter bundle adjustment as arrays: every observation at once.

The problem of designer.sfm.rolling_adjustment (its module docstring has the model) held
in numpy arrays — observations, stations, velocities, cameras, points — with residuals
and analytic Jacobians evaluated for all observations in one pass, for the Schur
Levenberg–Marquardt of designer.sfm.schur_lm. An observation of point X at (u, v) in
image i of station f is

    r = (π_c(R_m (R_f (X − d · vel_i) + t_f) + t_m) − (u, v)) / σ

with d its row's delay (s), (R_m, t_m) the image's mount on the rig (identity for the
reference camera), (R_f, t_f) the station's rig_from_world and π_c its camera's
FULL_OPENCV projection (designer.sfm.full_opencv). Tie points have σ = 1 px, control
marks the marking σ. Priors: surveyed control coordinates ((X − S) / σ per axis), one
camera-position prior per station ((−R_fᵀ t_f − C) / σ, σ horizontal, horizontal,
vertical) and each velocity's ((vel − start) / σ).

Rotations are updated as R ← Exp(δ) R (δ a rotation vector, rad): the Jacobian of
R Y is −[R Y]× δ. Image-local camera-side columns: δ (3), t (3), vel (3), then the
estimated interior parameters in FULL_OPENCV order.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from designer.core.rotation import rotation_from_rotvec
from designer.sfm.full_opencv import img_from_cam
from designer.sfm.schur_lm import Linearization

#: image-local columns before the interior parameters: rotation 3, translation 3, velocity 3
POSE_COLS, VEL_COLS = 6, 3


@dataclass(frozen=True)
class RollingState:
    """The unknowns: station rotations (F, 3, 3) and translations (F, 3) (rig_from_world),
    image velocities (I, 3) (zero for a global shutter), FULL_OPENCV parameters per camera
    (K, 12) and points (P, 3)."""

    R: np.ndarray
    t: np.ndarray
    vel: np.ndarray
    cam: np.ndarray
    X: np.ndarray


@dataclass
class RollingArrays:
    """The fixed data of the problem; observations sorted by image, then point."""

    obs_image: np.ndarray  # (n,) image index
    obs_point: np.ndarray  # (n,) point index
    uv: np.ndarray         # (n, 2) observed px
    weight: np.ndarray     # (n,) 1 / σ (px⁻¹)
    delay: np.ndarray      # (n,) s
    image_frame: np.ndarray   # (I,) station index
    image_camera: np.ndarray  # (I,) camera index
    mount_R: np.ndarray       # (I, 3, 3) cam_from_rig
    mount_t: np.ndarray       # (I, 3)
    variable: np.ndarray      # FULL_OPENCV indices of the estimated interior parameters
    #: priors: surveyed points (index, S, σ), stations (index, C, σ), velocities
    #: (image index, start, σ)
    control_index: np.ndarray
    control_xyz: np.ndarray
    control_sigma: np.ndarray
    prior_frame: np.ndarray
    prior_C: np.ndarray
    prior_sigma: np.ndarray
    vel_image: np.ndarray
    vel_start: np.ndarray
    vel_sigma: np.ndarray
    #: image-local → global camera-side columns (I, 9 + len(variable)), −1 held
    image_cols: np.ndarray
    n_cam: int

    @property
    def n_residuals(self) -> int:
        return 2 * len(self.obs_image) + 3 * (len(self.control_index) + len(self.prior_frame)
                                              + len(self.vel_image))


class RollingProblem:
    """Residuals, cost and Jacobians of :class:`RollingArrays` at a :class:`RollingState`
    (designer.sfm.schur_lm.SchurProblem)."""

    def __init__(self, a: RollingArrays):
        self.a = a
        start = np.searchsorted(a.obs_image, np.arange(len(a.image_frame) + 1))
        # per image: its observations' slice, station, and mount (None: the reference)
        self.images = [(slice(start[i], start[i + 1]), int(a.image_frame[i]),
                        None if np.array_equal(a.mount_R[i], np.eye(3))
                        and not np.any(a.mount_t[i]) else (a.mount_R[i], a.mount_t[i]))
                       for i in range(len(a.image_frame)) if start[i + 1] > start[i]]
        self.moving = bool(np.any(a.delay))
        self.obs_camera = a.image_camera[a.obs_image]

    def residuals(self, s: RollingState, jacobians: bool = False):
        """Whitened observation residuals (n, 2); with ``jacobians`` also the image-local
        camera-side (n, 2, c) and point (n, 2, 3) Jacobians."""
        a = self.a
        Y = s.X[a.obs_point]
        if self.moving:
            Y -= a.delay[:, None] * s.vel[a.obs_image]
        RY = np.empty_like(Y)  # R_f Y: rotated into the rig frame, not yet moved
        P = np.empty_like(Y)   # the camera frame
        for rows, f, mount in self.images:
            RY[rows] = Y[rows] @ s.R[f].T
            P[rows] = RY[rows] + s.t[f]
            if mount is not None:
                P[rows] = P[rows] @ mount[0].T + mount[1]
        cam = s.cam[self.obs_camera] if len(s.cam) > 1 else s.cam  # one: broadcast
        img, imaged, J_P, J_cam = img_from_cam(cam, P, jacobians, a.variable)
        w = a.weight[:, None]
        r = (img - a.uv) * w
        r[~imaged] = 0.0
        if not jacobians:
            return r
        A = J_P * w[:, :, None]  # ∂r/∂(camera-frame point), then the rig frame's
        J_X = np.empty_like(A)
        for rows, f, mount in self.images:
            if mount is not None:
                A[rows] = A[rows] @ mount[0]
            J_X[rows] = A[rows] @ s.R[f]
        J_rot = np.cross(RY[:, None, :], A)  # −A [RY]×
        parts = [J_rot, A, -a.delay[:, None, None] * J_X]  # rotation, translation, velocity
        if len(a.variable):
            parts.append(J_cam * w[:, :, None])
        return r, np.concatenate(parts, axis=2), J_X

    def _prior_residuals(self, s: RollingState):
        a = self.a
        Rf, tf = s.R[a.prior_frame], s.t[a.prior_frame]
        C = -np.einsum("nji,nj->ni", Rf, tf)
        r_pos = (C - a.prior_C) / a.prior_sigma
        r_vel = (s.vel[a.vel_image] - a.vel_start) / a.vel_sigma[:, None]
        r_ctl = (s.X[a.control_index] - a.control_xyz) / a.control_sigma
        return r_pos, r_vel, r_ctl

    def linearize(self, s: RollingState) -> Linearization:
        a = self.a
        r, J_c, J_p = self.residuals(s, jacobians=True)
        r_pos, r_vel, r_ctl = self._prior_residuals(s)
        n_points = len(s.X)
        point_H = np.zeros((n_points, 3, 3))
        point_g = np.zeros((n_points, 3))
        w2 = 1.0 / a.control_sigma ** 2
        idx = a.control_index
        point_H[idx, [[0], [1], [2]], [[0], [1], [2]]] += w2.T
        point_g[idx] += r_ctl / a.control_sigma

        cam_H = np.zeros((a.n_cam, a.n_cam))
        cam_g = np.zeros(a.n_cam)
        # station position priors: ∂C/∂δ = −Rᵀ[t]×, ∂C/∂t = −Rᵀ
        for k, f in enumerate(a.prior_frame):
            cols = a.image_cols[_first_image_of(a, f), :POSE_COLS]
            Rt = s.R[f].T
            J = np.hstack([-Rt @ _skew(s.t[f]), -Rt]) / a.prior_sigma[k][:, None]
            keep = cols >= 0
            J, cols = J[:, keep], cols[keep]
            cam_H[np.ix_(cols, cols)] += J.T @ J
            cam_g[cols] += J.T @ r_pos[k]
        for k, i in enumerate(a.vel_image):
            cols = a.image_cols[i, POSE_COLS:POSE_COLS + VEL_COLS]
            cam_H[cols, cols] += 1.0 / a.vel_sigma[k] ** 2
            cam_g[cols] += r_vel[k] / a.vel_sigma[k]
        cost = 0.5 * (float(np.sum(r * r)) + float(np.sum(r_pos ** 2))
                      + float(np.sum(r_vel ** 2)) + float(np.sum(r_ctl ** 2)))
        return Linearization(cost, r, J_c, J_p, point_H, point_g, cam_H, cam_g)

    def moved(self, s: RollingState, delta_c: np.ndarray, delta_p: np.ndarray
              ) -> RollingState:
        """The state after a step (global camera-side columns, points)."""
        a = self.a
        local = np.where(a.image_cols >= 0, delta_c[np.maximum(a.image_cols, 0)], 0.0) \
            if a.n_cam else np.zeros(a.image_cols.shape)
        # an image's local step holds its station's (the same in every image of a
        # station) and its camera's
        d_frame = np.zeros((len(s.t), POSE_COLS))
        d_frame[a.image_frame] = local[:, :POSE_COLS]
        d_cam = np.zeros_like(s.cam)
        d_cam[np.ix_(a.image_camera, a.variable)] = local[:, POSE_COLS + VEL_COLS:]
        R = np.einsum("fij,fjk->fik", rotation_from_rotvec(d_frame[:, :3]), s.R)
        return replace(s, R=R, t=s.t + d_frame[:, 3:],
                       vel=s.vel + local[:, POSE_COLS:POSE_COLS + VEL_COLS],
                       cam=s.cam + d_cam, X=s.X + delta_p)

    def parameter_norm(self, s: RollingState) -> float:
        return float(np.sqrt(np.sum(s.X ** 2) + np.sum(s.t ** 2) + len(s.t)
                             + np.sum(s.vel ** 2) + np.sum(s.cam[:, self.a.variable] ** 2)))


def _first_image_of(a: RollingArrays, frame: int) -> int:
    return int(np.flatnonzero(a.image_frame == frame)[0])


def _skew(v: np.ndarray) -> np.ndarray:
    return np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])
