"""Motion blur: the camera moves during the exposure.

Approximation: a camera translating (no rotation) over flat ground it looks at
(near-nadir): every ground point then moves across a pinhole image along the same
straight line, by v · t pixels, with v the image velocity (px/s) = ground speed / GSD in
the direction of flight. The PSF is that line segment, centred, because the pose of a
photo is its mid-exposure pose: blur spreads the image symmetrically and shifts nothing.
Relief, oblique views and rotation during the exposure make the true blur vary over the
image; this model ignores that. In the chain it runs on the pinhole render, before the
distortion warp, where the flat-ground motion is uniform.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

import cv2
import numpy as np

from designer.effects.base import CameraContext, Effect, FrameContext
from designer.effects.registry import implements
from designer.errors import DesignerError, ParameterValueError
from designer.project import model as m

BORDER = cv2.BORDER_REFLECT
#: points per pixel of blur length used to draw the line PSF
SAMPLES_PER_PX = 16


def linear_motion_kernel(displacement_px: tuple[float, float],
                         samples_per_px: int = SAMPLES_PER_PX) -> np.ndarray:
    """PSF of a uniform motion by (du, dv) px during the exposure, centred.

    The segment from −d/2 to +d/2 is sampled at n = ceil(|d| · samples_per_px) + 1
    midpoints, each spread bilinearly over its four nearest kernel elements: the kernel
    is the average of the image shifted (with bilinear interpolation) along the segment,
    exact to sub-pixel lengths. Returns an odd-sized float32 kernel summing to 1, its
    centroid at the middle element (u right = columns, v down = rows).
    """
    du, dv = (float(d) for d in displacement_px)
    length = math.hypot(du, dv)
    if not math.isfinite(length):
        raise ParameterValueError(f"displacement {displacement_px!r} must be finite",
                                  name="displacement_px", value=displacement_px,
                                  must="finite")
    n = math.ceil(length * samples_per_px) + 1
    t = (np.arange(n) + 0.5) / n - 0.5
    hx, hy = math.ceil(abs(du) / 2) + 1, math.ceil(abs(dv) / 2) + 1
    x, y = t * du + hx, t * dv + hy  # kernel index coordinates
    x0, y0 = np.floor(x).astype(np.int64), np.floor(y).astype(np.int64)
    fx, fy = x - x0, y - y0
    kernel = np.zeros((2 * hy + 1, 2 * hx + 1))
    for ox, oy, w in ((0, 0, (1 - fx) * (1 - fy)), (1, 0, fx * (1 - fy)),
                      (0, 1, (1 - fx) * fy), (1, 1, fx * fy)):
        np.add.at(kernel, (y0 + oy, x0 + ox), w)
    kernel /= kernel.sum()
    return kernel.astype(np.float32)


def motion_blur(image: np.ndarray, displacement_px: tuple[float, float]) -> np.ndarray:
    """Convolve ``image`` (linear light) with ``linear_motion_kernel``; edges mirrored."""
    kernel = linear_motion_kernel(displacement_px)
    # filter2D correlates; flipping the kernel makes it a convolution (it is symmetric
    # up to rounding anyway)
    return cv2.filter2D(image, -1, kernel[::-1, ::-1].copy(), borderType=BORDER)


def flight_direction_uv(velocity_world: np.ndarray, R_cam_to_world: np.ndarray
                        ) -> tuple[float, float]:
    """Direction (du, dv) in pixel axes (u right, v down) of the camera's motion in the
    image plane, unit length; (0, 0) if it moves along its viewing axis.

    ``velocity_world`` (3,) in the world frame; ``R_cam_to_world`` maps the
    photogrammetric camera frame (x right, y image top, z backwards) to the world.
    """
    v_cam = np.asarray(R_cam_to_world, float).T @ np.asarray(velocity_world, float)
    du, dv = float(v_cam[0]), -float(v_cam[1])  # image v points down, camera y up
    norm = math.hypot(du, dv)
    return (0.0, 0.0) if norm == 0 else (du / norm, dv / norm)


@implements(m.MotionBlur)
@dataclass(frozen=True)
class LinearMotionBlur(Effect):
    """Motion blur of length speed · exposure / GSD px along the frame's flight direction.

    ``pixels_per_output_px`` scales the length when the effect runs on an image finer
    than the output (the oversampled pinhole render). Needs ``context.gsd_m`` and
    ``context.flight_direction_uv``.
    """

    exposure_time_s: float
    speed_m_s: float
    pixels_per_output_px: float = 1.0
    kind: ClassVar[str] = "motion_blur"

    @classmethod
    def from_model(cls, element: m.MotionBlur, camera: CameraContext) -> LinearMotionBlur:
        """It runs on the pinhole render, ``camera.pixels_per_output_px`` finer."""
        return cls(element.exposure_time_s, element.speed_m_s,
                   float(camera.pixels_per_output_px))

    @property
    def is_identity(self) -> bool:
        return self.exposure_time_s * self.speed_m_s == 0

    def displacement_px(self, context: FrameContext) -> tuple[float, float]:
        if context.gsd_m is None or context.flight_direction_uv is None:
            raise DesignerError("motion blur needs the frame's ground sample distance and "
                                "flight direction (FrameContext.gsd_m, flight_direction_uv)")
        if not context.gsd_m > 0:
            raise DesignerError(f"ground sample distance {context.gsd_m!r} m must be > 0")
        du, dv = context.flight_direction_uv
        norm = math.hypot(du, dv)
        if norm == 0:
            return (0.0, 0.0)
        length = (self.speed_m_s * self.exposure_time_s / context.gsd_m
                  * self.pixels_per_output_px)
        return (length * du / norm, length * dv / norm)

    def apply(self, image: np.ndarray, frame_index: int, context: FrameContext) -> np.ndarray:
        return motion_blur(image, self.displacement_px(context))
