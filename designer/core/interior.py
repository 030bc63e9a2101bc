"""Interior orientation: the photogrammetric description of a camera and its pixel intrinsics.

Conventions (docs/conventions.md):

* sensor sizes and the principal point offset are in millimetres, the offset in the
  photogrammetric image frame (x right, y up) measured from the sensor centre;
* pixel coordinates are continuous with the origin at the top-left corner of the
  top-left pixel, u to the right, v down (pixel (i, j) has its centre at
  (i + 0.5, j + 0.5));
* the intrinsic matrix ``K_px`` maps computer-vision camera coordinates (x right,
  y down, z forward) to those pixel coordinates.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from designer.core.distortion import BrownConrady, Distortion, FisheyeEquidistant
from designer.errors import CameraModelError

#: relative tolerance for "square pixels" (sw/W == sh/H)
SQUARE_PIXEL_RTOL = 1e-6


@dataclass(frozen=True)
class InteriorOrientation:
    """A camera's interior orientation in photogrammetric terms.

    Attributes:
        focal_length_mm: principal distance f (mm), > 0.
        sensor_width_mm, sensor_height_mm: sensor size (mm), > 0.
        image_width_px, image_height_px: image size (px), positive integers.
        principal_point_x_mm, principal_point_y_mm: principal point offset from the
            sensor centre (mm), photogrammetric axes (x right, y up).
        pixel_aspect: pixel height / pixel width. ``None`` means square pixels, which
            is then checked: sw/W must equal sh/H to 1e-6 relative.
        distortion: a lens distortion model or ``None`` for an ideal pinhole.
    """

    focal_length_mm: float
    sensor_width_mm: float
    sensor_height_mm: float
    image_width_px: int
    image_height_px: int
    principal_point_x_mm: float = 0.0
    principal_point_y_mm: float = 0.0
    pixel_aspect: float | None = None
    distortion: Distortion | None = None

    def __post_init__(self) -> None:
        for problem in self.problems():
            raise CameraModelError(problem)

    # ------------------------------------------------------------------ checks
    def problems(self) -> list[str]:
        """Every reason this camera is impossible, as sentences naming the fix."""
        out: list[str] = []
        named = {
            "focal_length_mm": self.focal_length_mm,
            "sensor_width_mm": self.sensor_width_mm,
            "sensor_height_mm": self.sensor_height_mm,
            "principal_point_x_mm": self.principal_point_x_mm,
            "principal_point_y_mm": self.principal_point_y_mm,
        }
        for name, value in named.items():
            if not isinstance(value, int | float) or not math.isfinite(value):
                out.append(f"{name} = {value!r} is not a finite number; give a finite value")
        if out:
            return out
        for name in ("focal_length_mm", "sensor_width_mm", "sensor_height_mm"):
            if named[name] <= 0:
                out.append(f"{name} = {named[name]!r} must be > 0 mm")
        for name in ("image_width_px", "image_height_px"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, int | np.integer) or value < 1:
                out.append(f"{name} = {value!r} must be a positive whole number of pixels")
        if out:
            return out
        pitch_x = self.sensor_width_mm / self.image_width_px
        pitch_y = self.sensor_height_mm / self.image_height_px
        if self.pixel_aspect is None:
            if abs(pitch_y - pitch_x) > SQUARE_PIXEL_RTOL * pitch_x:
                out.append(
                    f"pixels are not square: sensor {self.sensor_width_mm} x "
                    f"{self.sensor_height_mm} mm over {self.image_width_px} x "
                    f"{self.image_height_px} px gives {pitch_x * 1000:.6g} x "
                    f"{pitch_y * 1000:.6g} µm pixels; make sensor width / image width equal "
                    f"sensor height / image height (e.g. sensor height "
                    f"{self.sensor_width_mm * self.image_height_px / self.image_width_px:.6g} "
                    f"mm), or state a pixel aspect"
                )
        else:
            aspect = self.pixel_aspect
            if not math.isfinite(aspect) or aspect <= 0:
                out.append(f"pixel_aspect = {aspect!r} must be a finite number > 0")
            elif abs(pitch_y / pitch_x - aspect) > SQUARE_PIXEL_RTOL * aspect:
                out.append(
                    f"pixel_aspect = {aspect!r} disagrees with the sensor and image sizes, "
                    f"which give {pitch_y / pitch_x:.9g}; correct one of them"
                )
        if self.distortion is not None and not isinstance(
            self.distortion, BrownConrady | FisheyeEquidistant
        ):
            out.append(f"unknown distortion model {type(self.distortion).__name__}")
        return out

    # --------------------------------------------------------- pixel intrinsics
    @property
    def pixel_pitch_x_mm(self) -> float:
        return self.sensor_width_mm / self.image_width_px

    @property
    def pixel_pitch_y_mm(self) -> float:
        return self.sensor_height_mm / self.image_height_px

    @property
    def fx_px(self) -> float:
        """Focal length in pixel widths: f·W/sw."""
        return self.focal_length_mm * self.image_width_px / self.sensor_width_mm

    @property
    def fy_px(self) -> float:
        """Focal length in pixel heights: f·H/sh."""
        return self.focal_length_mm * self.image_height_px / self.sensor_height_mm

    @property
    def cx_px(self) -> float:
        """Principal point column: W/2 + x0·W/sw (continuous, top-left corner origin)."""
        return self.image_width_px / 2 + self.principal_point_x_mm / self.pixel_pitch_x_mm

    @property
    def cy_px(self) -> float:
        """Principal point row: H/2 − y0·H/sh (v grows downwards, y0 upwards)."""
        return self.image_height_px / 2 - self.principal_point_y_mm / self.pixel_pitch_y_mm

    @property
    def K_px(self) -> np.ndarray:
        """3×3 intrinsic matrix, CV camera frame → continuous pixel coordinates."""
        return np.array(
            [[self.fx_px, 0.0, self.cx_px], [0.0, self.fy_px, self.cy_px], [0.0, 0.0, 1.0]]
        )

    @property
    def image_size_px(self) -> tuple[int, int]:
        """(width, height) in pixels."""
        return (int(self.image_width_px), int(self.image_height_px))

    # ----------------------------------------------------------- field of view
    def field_of_view_deg(self) -> tuple[float, float, float]:
        """(horizontal, vertical, diagonal) full angles of view in degrees.

        Measured through the image edges for the pinhole model about the principal
        point (so an offset principal point widens one side and narrows the other).
        For a fisheye lens the angles come from the equidistant model's inverse.
        """
        W, H = self.image_size_px
        corners = {
            "h": ((0.0, self.cy_px), (float(W), self.cy_px)),
            "v": ((self.cx_px, 0.0), (self.cx_px, float(H))),
            "d": ((0.0, 0.0), (float(W), float(H))),
        }
        out = []
        for a, b in corners.values():
            rays = self.rays_cv(np.array([a, b], dtype=float))
            cos_angle = float(np.clip(np.dot(rays[0], rays[1]), -1.0, 1.0))
            out.append(math.degrees(math.acos(cos_angle)))
        return (out[0], out[1], out[2])

    def rays_cv(self, uv_px: np.ndarray) -> np.ndarray:
        """Unit viewing rays in the CV camera frame for pixel coordinates (N, 2) → (N, 3).

        Applies the inverse distortion; raises NotInvertibleError where it fails.
        """
        uv = np.asarray(uv_px, dtype=float).reshape(-1, 2)
        xy_dist = np.empty_like(uv)
        xy_dist[:, 0] = (uv[:, 0] - self.cx_px) / self.fx_px
        xy_dist[:, 1] = (uv[:, 1] - self.cy_px) / self.fy_px
        if self.distortion is None:
            xy = xy_dist
            return _unit(np.column_stack([xy, np.ones(len(xy))]))
        tol = UNDISTORT_TOL_PX / max(self.fx_px, self.fy_px)
        return self.distortion.rays_from_distorted(xy_dist, tol=tol)


#: the accuracy to which pixel → ray inverses are solved, in pixels
UNDISTORT_TOL_PX = 1e-6


def _unit(v: np.ndarray) -> np.ndarray:
    return v / np.linalg.norm(v, axis=-1, keepdims=True)
