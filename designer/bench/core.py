"""Projection throughput of the photogrammetric core (``designer bench core``)."""

from __future__ import annotations

import numpy as np

from designer.bench.table import Column, text_table
from designer.bench.timing import best_of
from designer.core.distortion import BrownConrady
from designer.core.interior import InteriorOrientation
from designer.core.projection import project_points
from designer.core.rotation import rotation_from_opk


def _survey_camera() -> InteriorOrientation:
    return InteriorOrientation(
        focal_length_mm=8.8, sensor_width_mm=13.2, sensor_height_mm=8.8,
        image_width_px=5472, image_height_px=3648,
        principal_point_x_mm=0.012, principal_point_y_mm=-0.008,
        distortion=BrownConrady(k1=-0.12, k2=0.05, k3=-0.01, p1=4e-4, p2=-2e-4),
    )


def run(repeats: int = 3, scale: float = 1.0) -> list[dict]:
    """Measure points/s for the two standard cases; ``scale`` shrinks them for tests."""
    rng = np.random.default_rng(1)
    camera = _survey_camera()
    origin = np.array([500000.0, 5000000.0, 300.0])
    rows = []
    cases = [("10 M points x 1 camera", int(10_000_000 * scale), 1),
             ("1 M points x 100 cameras", int(1_000_000 * scale), 100)]
    for label, n_points, n_cameras in cases:
        points = origin + rng.uniform([-50, -50, -10], [50, 50, 10], size=(n_points, 3))
        C = origin + np.column_stack([
            rng.uniform(-20, 20, n_cameras), rng.uniform(-20, 20, n_cameras),
            np.full(n_cameras, 100.0)])
        R = rotation_from_opk(*np.radians(rng.normal(0, 3, size=(3, n_cameras))))
        for model, cam in (("pinhole", _pinhole(camera)), ("pinhole + Brown", camera)):
            seconds, _ = best_of(
                repeats, lambda p=points, c=C, r=R, cam=cam: project_points(p, c, r, cam))
            total = n_points * n_cameras
            rows.append({"case": label, "model": model, "seconds": seconds,
                         "points_per_s": total / seconds})
    return rows


def _pinhole(camera: InteriorOrientation) -> InteriorOrientation:
    from dataclasses import replace
    return replace(camera, distortion=None)


def format_table(rows: list[dict]) -> str:
    return text_table(
        [Column("case", "<26", "case"), Column("model", "<16", "model"),
         Column("seconds", ">9.3f", "seconds"),
         Column("M points/s", ">11.1f", lambda r: r["points_per_s"] / 1e6)], rows,
        "(one process, one thread: numpy is single-threaded for these operations; best of "
        "the repeats)")
