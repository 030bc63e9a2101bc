"""Seeded synthetic surveys at UTM size for the export tests."""

from __future__ import annotations

import numpy as np

from designer.core.distortion import BrownConrady, FisheyeEquidistant
from designer.core.interior import InteriorOrientation
from designer.core.rotation import rotation_from_heading_tilt_roll, rotation_from_opk
from designer.core.truth import CameraPose, GroundControlPoint, observe_gcps

#: a UTM-sized world origin: float32 here would be off by decimetres
UTM = np.array([500000.0, 5000000.0, 250.0])

LENSES = ("pinhole", "opencv", "full_opencv", "fisheye", "nonsquare")


def interior_for(lens: str) -> InteriorOrientation:
    """A 5472 x 3648 camera with an offset principal point and the named lens model."""
    common = dict(focal_length_mm=8.8, sensor_width_mm=13.2, sensor_height_mm=8.8,
                  image_width_px=5472, image_height_px=3648,
                  principal_point_x_mm=0.0513, principal_point_y_mm=-0.0371)
    if lens == "pinhole":
        return InteriorOrientation(**common)
    if lens == "opencv":
        return InteriorOrientation(
            **common, distortion=BrownConrady(k1=-0.11, k2=0.023, p1=7e-4, p2=-3e-4))
    if lens == "full_opencv":
        return InteriorOrientation(
            **common, distortion=BrownConrady(k1=-0.11, k2=0.023, k3=-0.004, p1=7e-4, p2=-3e-4))
    if lens == "fisheye":
        return InteriorOrientation(
            **{**common, "focal_length_mm": 4.5},
            distortion=FisheyeEquidistant(k1=0.02, k2=-0.004, k3=0.001, k4=-1e-4))
    if lens == "nonsquare":
        return InteriorOrientation(
            **{**common, "sensor_height_mm": 8.8 * 1.01}, pixel_aspect=1.01,
            distortion=BrownConrady(k1=-0.05, k3=0.002, p1=-4e-4, p2=9e-4))
    raise ValueError(lens)


def random_poses(rng: np.random.Generator, n: int = 6, height_m: float = 100.0):
    """Cameras over a 120 m square at UTM size, tilted up to 12 degrees, any heading."""
    poses = []
    for i in range(n):
        C = UTM + np.array([*rng.uniform(-60, 60, 2), height_m + rng.uniform(-5, 5)])
        R = rotation_from_heading_tilt_roll(
            rng.uniform(0, 2 * np.pi), *np.radians(rng.uniform(-12, 12, 2)))
        R = R @ rotation_from_opk(*np.radians(rng.uniform(-2, 2, 3)))
        poses.append(CameraPose(f"IMG_{i:04d}.png", C, R))
    return poses


def random_gcps(rng: np.random.Generator, n: int = 12, sigma_m: float = 0.02):
    gcps = []
    for i in range(n):
        true = UTM + np.array([*rng.uniform(-70, 70, 2), rng.uniform(-3, 3)])
        sigma = np.array([sigma_m, sigma_m, 1.5 * sigma_m])
        surveyed = true + rng.normal(0.0, sigma)
        role = "check" if i % 3 == 2 else "control"
        gcps.append(GroundControlPoint(f"GCP{i + 1:02d}", role, true, surveyed, sigma))
    return gcps


def survey(seed: int, lens: str = "opencv"):
    """(interior, poses, gcps, observations) of a seeded random survey."""
    rng = np.random.default_rng(seed)
    interior = interior_for(lens)
    poses = random_poses(rng)
    gcps = random_gcps(rng)
    return interior, poses, gcps, observe_gcps(gcps, poses, interior)
