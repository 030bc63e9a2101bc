"""DJI gimbal angles ↔ the project's camera rotation.

DJI documents the gimbal attitude of a photo (XMP ``drone-dji:GimbalYawDegree``,
``GimbalPitchDegree``, ``GimbalRollDegree``; Mavic 3E/3T user manual, "Photo File",
and Zenmuse P1 manual, "XMP Data List") as angles in the NED frame with rotation order
ZYX: yaw clockwise from TRUE north, pitch 0 = horizontal and −90 = nadir, roll about
the optical axis. WPML's ``gimbalRotate`` action and MAVLink's DO_MOUNT_CONTROL use the
same angles. The gimbal body frame is x = optical axis, y = image right, z = image
down, so with designer's photogrammetric camera frame (x right, y up, z backwards):

    R_cam_to_world = T · Rz(yaw) · Ry(pitch) · Rx(roll) · M

where the middle product is the aerospace NED rotation, M maps photo axes to gimbal
axes (x_photo → y_body, y_photo → −z_body, z_photo → −x_body) and T maps NED to ENU.
``yaw`` here is measured from the grid north of the project's frame: callers add the
grid azimuth of true north (:meth:`designer.flight.geodesy.Georef.true_north_azimuth_deg`)
to a true-north yaw first. Yaw 0, pitch −90, roll 0 is ω = φ = κ = 0 (nadir, image top
north).

Inverse: pitch ∈ [−90, 90], roll ∈ (−180, 180], yaw ∈ (−180, 180]. At pitch = ±90°
(nadir or zenith, where yaw and roll turn about the same axis) roll is reported as 0
and yaw carries the rotation, so angles → matrix → angles → matrix is exact there too.
"""

from __future__ import annotations

import numpy as np

#: gimbal body axes (x optical axis, y image right, z image down) from photo axes
_M = np.array([[0.0, 0.0, -1.0], [1.0, 0.0, 0.0], [0.0, -1.0, 0.0]])
#: ENU from NED (its own inverse)
_T = np.array([[0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, -1.0]])
_LOCK = 1e-14


def _rz(a):
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def _ry(a):
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


def _rx(a):
    c, s = np.cos(a), np.sin(a)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


def rotation_from_gimbal(yaw_grid_deg: float, pitch_deg: float, roll_deg: float) -> np.ndarray:
    """R_cam_to_world (3, 3) of a camera at DJI gimbal angles (deg, yaw from grid north)."""
    y, p, r = np.radians([yaw_grid_deg, pitch_deg, roll_deg])
    return _T @ _rz(y) @ _ry(p) @ _rx(r) @ _M


def gimbal_from_rotation(R_cam_to_world) -> tuple[float, float, float]:
    """DJI (yaw from grid north, pitch, roll) in degrees of R_cam_to_world (3, 3)."""
    B = _T @ np.asarray(R_cam_to_world, float) @ _M.T  # NED rotation Rz·Ry·Rx
    cos_p = float(np.hypot(B[2, 1], B[2, 2]))
    pitch = np.arctan2(-B[2, 0], cos_p)
    roll = 0.0 if cos_p < _LOCK else float(np.arctan2(B[2, 1], B[2, 2]))
    C = B @ _rx(roll).T  # = Rz(yaw)·Ry(pitch): second column (−sin yaw, cos yaw, 0)
    yaw = np.arctan2(-C[0, 1], C[1, 1])
    return float(np.degrees(yaw)), float(np.degrees(pitch)), float(np.degrees(roll))


def wrap_deg(angle_deg: float) -> float:
    """An angle in (−180, 180]."""
    a = (angle_deg + 180.0) % 360.0 - 180.0
    return 180.0 if a == -180.0 else a
