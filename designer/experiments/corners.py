"""The corner detector: Harris corners, OpenCV sub-pixel refinement, nearest-neighbour match.

The same detector measures the rendered cube images and the synthetic baseline
(:mod:`designer.experiments.synthetic`), so the two error distributions are comparable.

1. ``cv2.goodFeaturesToTrack`` with the Harris response (k = 0.04, 5 px block) finds
   candidates to the nearest pixel;
2. ``cv2.cornerSubPix`` (an 11 × 11 px window) refines each to the point where the image
   gradients around it are orthogonal to the lines joining it to them — the saddle point
   of a checkerboard corner;
3. each expected corner is matched to the nearest refined detection; a pair counts only
   if each is the other's nearest and they are at most ``max_match_px`` apart.

Pixel coordinates are designer's (docs/conventions.md): origin at the top-left corner of
the top-left pixel. OpenCV's origin is that pixel's centre, so detections get + 0.5 px.
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np
from scipy.spatial import cKDTree

#: cornerSubPix half window (px): an 11 × 11 window
HALF_WINDOW_PX = 5
HARRIS_K = 0.04
HARRIS_BLOCK_PX = 5
HARRIS_QUALITY = 0.02
#: farthest a refined detection may be from its expected corner to count as a match (px)
MAX_MATCH_PX = 2.0
_CRITERIA = (cv2.TERM_CRITERIA_EPS + cv2.TERM_CRITERIA_COUNT, 100, 1e-4)


@dataclass(frozen=True)
class Detector:
    """Harris + cornerSubPix settings (defaults as documented above)."""

    half_window_px: int = HALF_WINDOW_PX
    quality: float = HARRIS_QUALITY
    max_match_px: float = MAX_MATCH_PX

    def detect(self, gray: np.ndarray) -> np.ndarray:
        """Refined corners (K, 2) in designer pixel coordinates of an (H, W) grey image."""
        image = np.asarray(gray, dtype=np.float32)
        found = cv2.goodFeaturesToTrack(
            image, maxCorners=0, qualityLevel=self.quality,
            minDistance=float(self.half_window_px + 1), blockSize=HARRIS_BLOCK_PX,
            useHarrisDetector=True, k=HARRIS_K)
        if found is None:
            return np.empty((0, 2))
        refined = cv2.cornerSubPix(image, found.astype(np.float32),
                                   (self.half_window_px, self.half_window_px), (-1, -1),
                                   _CRITERIA)
        return refined.reshape(-1, 2).astype(float) + 0.5

    def measure(self, gray: np.ndarray, uv_expected: np.ndarray
                ) -> tuple[np.ndarray, np.ndarray]:
        """Detect and match: (found (N,) bool, uv_detected (N, 2), NaN where not found)."""
        return match(self.detect(gray), uv_expected, self.max_match_px)


def match(detected: np.ndarray, expected: np.ndarray, max_px: float
          ) -> tuple[np.ndarray, np.ndarray]:
    """Mutual nearest neighbours within ``max_px``: (found (N,), detected uv per expected)."""
    expected = np.asarray(expected, float).reshape(-1, 2)
    out = np.full_like(expected, np.nan)
    found = np.zeros(len(expected), bool)
    if len(detected) == 0 or len(expected) == 0:
        return found, out
    d_e, i_e = cKDTree(detected).query(expected)
    _, i_d = cKDTree(expected).query(detected)
    found = (d_e <= max_px) & (i_d[i_e] == np.arange(len(expected)))
    out[found] = detected[i_e[found]]
    return found, out
