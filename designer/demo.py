"""The example survey, end to end: every stage that exists so far, in order."""

from __future__ import annotations

import json
from collections.abc import Callable
from pathlib import Path

import numpy as np

from designer.atomic import write_text_atomic
from designer.core.distortion import BrownConrady
from designer.core.interior import InteriorOrientation
from designer.core.projection import footprint_on_plane, ground_sample_distance_m


def example_camera() -> InteriorOrientation:
    """A 1-inch 20 MP survey camera (13.2 × 8.8 mm, 8.8 mm lens), as in the example survey."""
    return InteriorOrientation(
        focal_length_mm=8.8, sensor_width_mm=13.2, sensor_height_mm=8.8,
        image_width_px=5472, image_height_px=3648,
        distortion=BrownConrady(k1=-0.02, k2=0.01),
    )


def run_demo(output: Path, log: Callable[[str], None] = print) -> Path:
    output = Path(output)
    output.mkdir(parents=True, exist_ok=True)
    camera = example_camera()
    altitude_m = 80.0
    gsd_m = float(ground_sample_distance_m(camera, altitude_m))
    corners = footprint_on_plane(np.array([0.0, 0.0, altitude_m]), np.eye(3), camera, 0.0)
    hfov, vfov, _ = camera.field_of_view_deg()
    summary = {
        "camera": {"fx_px": camera.fx_px, "fy_px": camera.fy_px,
                   "cx_px": camera.cx_px, "cy_px": camera.cy_px,
                   "fov_deg": [hfov, vfov]},
        "altitude_agl_m": altitude_m,
        "gsd_cm": gsd_m * 100,
        "footprint_m": [float(corners[1, 0] - corners[0, 0]),
                        float(corners[0, 1] - corners[3, 1])],
    }
    log(f"camera: fx {camera.fx_px:.1f} px, FOV {hfov:.1f} x {vfov:.1f} deg")
    log(f"at {altitude_m:.0f} m AGL: GSD {gsd_m * 100:.2f} cm, footprint "
        f"{summary['footprint_m'][0]:.1f} x {summary['footprint_m'][1]:.1f} m")
    report = output / "report.json"
    write_text_atomic(report, json.dumps(summary, indent=2))
    return report

