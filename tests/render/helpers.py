"""Shared steps of the render tests: finding rendered GCP target centres."""

from __future__ import annotations

import cv2
import numpy as np


def detect_centres(image_gray: np.ndarray, uv_expected: np.ndarray, rng,
                   half_window: int = 5) -> np.ndarray:
    """Sub-pixel saddle points near the expected centres (designer pixel convention)."""
    start = uv_expected - 0.5 + rng.uniform(-1.0, 1.0, uv_expected.shape)
    pts = start.astype(np.float32).reshape(-1, 1, 2)
    criteria = (cv2.TERM_CRITERIA_EPS + cv2.TERM_CRITERIA_COUNT, 200, 1e-5)
    refined = cv2.cornerSubPix(image_gray.astype(np.float32), pts, (half_window, half_window),
                               (-1, -1), criteria)
    return refined.reshape(-1, 2) + 0.5
