"""Multi-camera rigs: a mount's rotation on the platform and the names of its images.

Frames (docs/conventions.md): a station's pose is the platform's, ``R_platform`` mapping
the platform's photogrammetric axes (x = image right, y = image top, z = backwards) to
the world. A mount turns its camera by ω φ κ relative to the platform with the same
convention as a photo's angles, so

    R_cam_to_world = R_platform · R_mount,   R_mount = Rx(ω) · Ry(φ) · Rz(κ)

and ω = φ = κ = 0 is a camera looking where the platform looks, image top forward. All
mounts share the station's perspective centre (no lever arm).
"""

from __future__ import annotations

import math
import posixpath

import numpy as np

from designer.core.rotation import opk_from_rotation, rotation_from_opk, rotation_from_rotvec

#: a nadir + four 45° oblique rig: (suffix, ω, φ, κ deg) of each mount — forward,
#: backward (turned 180° so the image top points away), left and right
PENTA_MOUNTS = (("_N", 0.0, 0.0, 0.0), ("_F", 45.0, 0.0, 0.0), ("_B", -45.0, 0.0, 180.0),
                ("_L", 0.0, 45.0, 0.0), ("_R", 0.0, -45.0, 0.0))


def mount_rotation(omega_deg: float, phi_deg: float, kappa_deg: float) -> np.ndarray:
    """R_mount (3, 3): the mounted camera's axes → the platform's axes (angles in deg)."""
    return rotation_from_opk(math.radians(omega_deg), math.radians(phi_deg),
                             math.radians(kappa_deg))


def mounted_rotation(R_platform_to_world: np.ndarray, R_mount: np.ndarray) -> np.ndarray:
    """R_cam_to_world (3, 3) of a mounted camera on a platform posed ``R_platform_to_world``."""
    return np.asarray(R_platform_to_world, float) @ np.asarray(R_mount, float)


def mount_tilt_deg(omega_deg: float, phi_deg: float, kappa_deg: float = 0.0) -> float:
    """Angle (deg, 0..180) between the mounted camera's viewing axis and the platform's."""
    axis = mount_rotation(omega_deg, phi_deg, kappa_deg)[:, 2]  # camera z in platform axes
    return math.degrees(math.acos(max(-1.0, min(1.0, float(axis[2])))))


def mount_image_name(image_name: str, suffix: str) -> str:
    """The station's image name with ``suffix`` before its extension:
    IMG_00001.png, _F → IMG_00001_F.png (no extension: appended)."""
    stem, ext = posixpath.splitext(image_name)
    return f"{stem}{suffix}{ext}"


def retilted_mount_deg(omega_deg: float, phi_deg: float, kappa_deg: float,
                       tilt_deg: float) -> tuple[float, float, float]:
    """ω φ κ (deg) of the mount turned about the axis perpendicular to the platform's
    axis and its own, so that it looks ``tilt_deg`` from the platform's axis in the same
    direction (ω = 45, φ = 0 → ω = tilt_deg). A mount along the platform's axis has no
    direction to tilt in and is returned unchanged."""
    R = mount_rotation(omega_deg, phi_deg, kappa_deg)
    view = -R[:, 2]  # the viewing axis in platform axes; the platform looks along −z
    axis = np.cross([0.0, 0.0, -1.0], view)
    norm = float(np.linalg.norm(axis))
    if norm < 1e-12:
        return omega_deg, phi_deg, kappa_deg
    turn = math.radians(tilt_deg - mount_tilt_deg(omega_deg, phi_deg, kappa_deg))
    R_new = rotation_from_rotvec(axis / norm * turn) @ R
    # rounded to 1e-12 deg so that 45 → 30 reads back as 30, not 29.999999999999996
    return tuple(round(float(math.degrees(a)), 12) + 0.0 for a in opk_from_rotation(R_new))
