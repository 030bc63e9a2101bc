"""A small synthetic survey at UTM coordinates: camera, poses, GCPs and observations."""

import numpy as np

from designer.core.distortion import BrownConrady
from designer.core.interior import InteriorOrientation
from designer.core.rotation import rotation_from_opk
from designer.core.truth import CameraPose, GroundControlPoint, observe_gcps

ORIGIN = np.array([512000.0, 5406000.0, 300.0])


def camera(distortion=True) -> InteriorOrientation:
    return InteriorOrientation(
        focal_length_mm=8.8, sensor_width_mm=13.2, sensor_height_mm=8.8,
        image_width_px=5472, image_height_px=3648,
        principal_point_x_mm=0.012, principal_point_y_mm=-0.008,
        distortion=BrownConrady(k1=-0.05, k2=0.01, k3=0.002, p1=1e-4, p2=-5e-5)
        if distortion else None)


def poses(seed=0, n=12) -> list[CameraPose]:
    rng = np.random.default_rng(seed)
    out = []
    for i in range(n):
        C = ORIGIN + [(i % 4) * 25.0 - 37.5, (i // 4) * 30.0 - 30.0, 80.0 + rng.normal(0, 2)]
        R = rotation_from_opk(*np.radians(rng.normal(0, 3, 3)))
        out.append(CameraPose(f"img_{i:03d}.jpg", C, R))
    return out


def gcps(seed=1) -> list[GroundControlPoint]:
    rng = np.random.default_rng(seed)
    out = []
    for i in range(8):
        true = ORIGIN + [rng.uniform(-40, 40), rng.uniform(-35, 35), rng.normal(0, 1)]
        out.append(GroundControlPoint(f"GCP{i}", "control" if i < 5 else "check", true,
                                      true + rng.normal(0, 0.01, 3), [0.01, 0.01, 0.02]))
    return out


def observations(cam, ps, gs):
    return observe_gcps(gs, ps, cam)
