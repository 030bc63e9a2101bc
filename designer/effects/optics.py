"""Lens effects in linear light: vignetting, Gaussian blur, thin-lens defocus.

All images are linear light (float32, see ``designer.effects.base``), (H, W) or
(H, W, C), on the output pixel grid of the camera ``interior``; positions are continuous
pixel coordinates (pixel centres at i + 0.5). Nothing here modifies its input.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass
from typing import ClassVar

import cv2
import numpy as np

from designer.core.interior import InteriorOrientation
from designer.effects._pixel_kernels import times_gain
from designer.effects.base import CameraContext, Effect, FrameContext, channels_last
from designer.effects.registry import implements
from designer.errors import DesignerError, ParameterValueError
from designer.project import model as m

#: how images are extended beyond their edges by the blurs (mirror about the edge)
BORDER = cv2.BORDER_REFLECT


# ------------------------------------------------------------------------- vignetting
def pixel_centres(interior: InteriorOrientation) -> tuple[np.ndarray, np.ndarray]:
    """(u, v) continuous coordinates of every pixel centre, each (H, W) float64."""
    W, H = interior.image_size_px
    return np.meshgrid(np.arange(W) + 0.5, np.arange(H) + 0.5)


def radial_vignetting_gain(interior: InteriorOrientation, coefficients: tuple[float, ...],
                           u_px: np.ndarray, v_px: np.ndarray) -> np.ndarray:
    """Gain 1 + a1 ρ² + a2 ρ⁴ + a3 ρ⁶ … at continuous positions (u, v) (any shape).

    ρ is the distance on the sensor (mm, so non-square pixels are handled) from the
    principal point, divided by the distance to the farthest image corner: ρ = 1 there.
    """
    x = (np.asarray(u_px, float) - interior.cx_px) * interior.pixel_pitch_x_mm
    y = (np.asarray(v_px, float) - interior.cy_px) * interior.pixel_pitch_y_mm
    W, H = interior.image_size_px
    r_max = max(math.hypot((cu - interior.cx_px) * interior.pixel_pitch_x_mm,
                           (cv - interior.cy_px) * interior.pixel_pitch_y_mm)
                for cu in (0.0, W) for cv in (0.0, H))
    rho2 = (x * x + y * y) / (r_max * r_max)
    gain = np.zeros_like(rho2)
    for a in reversed(coefficients):  # Horner in ρ²
        gain = (gain + a) * rho2
    return gain + 1.0


def natural_vignetting_gain(interior: InteriorOrientation, u_px: np.ndarray,
                            v_px: np.ndarray) -> np.ndarray:
    """cos⁴ θ of the ray through (u, v): the natural fall-off of an ideal thin lens
    (irradiance of a uniform scene). θ comes from the camera's distortion inverse, so
    the positions must be invertible (NotInvertibleError otherwise)."""
    uv = np.column_stack([np.ravel(u_px), np.ravel(v_px)])
    cos_theta = interior.rays_cv(uv)[:, 2]
    return (cos_theta**4).reshape(np.shape(u_px))


@implements(m.Vignetting)
@dataclass(frozen=True)
class RadialVignetting(Effect):
    """Multiply by the radial polynomial gain of ``radial_vignetting_gain``, and with
    ``natural_cos4`` also by cos⁴ θ (``natural_vignetting_gain``).

    ``from_corner_falloff(interior, c)`` gives gain = 1 − c ρ², the leading term of a
    cos⁴-like fall-off: 1 at the principal point, 1 − c at the farthest image corner.
    """

    interior: InteriorOrientation
    coefficients: tuple[float, ...]
    natural_cos4: bool = False
    kind: ClassVar[str] = "vignetting"

    @classmethod
    def from_model(cls, element: m.Vignetting, camera: CameraContext) -> RadialVignetting:
        """``<vignetting>``: the corner fall-off c is the ρ² term −c."""
        return cls(camera.interior, (-element.corner_falloff, element.rho4, element.rho6),
                   natural_cos4=element.natural_cos4)

    @classmethod
    def from_corner_falloff(cls, interior: InteriorOrientation, corner_falloff: float
                            ) -> RadialVignetting:
        if not 0.0 <= corner_falloff <= 1.0:
            raise ParameterValueError(
                f"corner_falloff = {corner_falloff!r} must be from 0 to 1",
                name="corner_falloff", value=corner_falloff, must="from 0 to 1")
        return cls(interior, (-float(corner_falloff),))

    @property
    def is_identity(self) -> bool:
        return not any(self.coefficients) and not self.natural_cos4

    @functools.cached_property
    def gain(self) -> np.ndarray:
        """(H, W) float32 gain at the pixel centres."""
        u, v = pixel_centres(self.interior)
        gain = radial_vignetting_gain(self.interior, self.coefficients, u, v)
        if self.natural_cos4:
            gain *= natural_vignetting_gain(self.interior, u, v)
        return gain.astype(np.float32)

    def apply(self, image: np.ndarray, frame_index: int, context: FrameContext) -> np.ndarray:
        return _times_gain(image, self.gain)


@dataclass(frozen=True)
class NaturalVignetting(RadialVignetting):
    """Multiply by cos⁴ θ (``natural_vignetting_gain``) at every pixel centre: a
    ``RadialVignetting`` without polynomial terms."""

    coefficients: tuple[float, ...] = ()
    natural_cos4: bool = True


def _times_gain(image: np.ndarray, gain: np.ndarray) -> np.ndarray:
    if image.shape[:2] != gain.shape:
        raise ValueError(f"vignetting for {gain.shape[1]} x {gain.shape[0]} px images got "
                         f"{image.shape[1]} x {image.shape[0]} px")
    out = times_gain(np.ascontiguousarray(channels_last(image), dtype=np.float32), gain)
    return out.reshape(image.shape)


# ----------------------------------------------------------------------- Gaussian blur
def gaussian_blur(image: np.ndarray, sigma_px: float) -> np.ndarray:
    """Convolve with a Gaussian PSF of standard deviation ``sigma_px`` (px), ±4σ kernel,
    edges mirrored. σ = 0 returns a copy."""
    if not sigma_px >= 0:
        raise ParameterValueError(f"sigma_px = {sigma_px!r} must be >= 0", name="sigma_px",
                                  value=sigma_px, unit="px", must="at least 0 px")
    if sigma_px == 0:
        return image.copy()
    return cv2.GaussianBlur(image, (0, 0), sigmaX=sigma_px, sigmaY=sigma_px, borderType=BORDER)


@implements(m.Blur)
@dataclass(frozen=True)
class GaussianBlur(Effect):
    """Gaussian optical blur, σ in output pixels."""

    sigma_px: float
    kind: ClassVar[str] = "blur"

    @classmethod
    def from_model(cls, element: m.Blur, camera: CameraContext) -> GaussianBlur:
        return cls(element.sigma_px)

    @property
    def is_identity(self) -> bool:
        return self.sigma_px == 0

    def apply(self, image: np.ndarray, frame_index: int, context: FrameContext) -> np.ndarray:
        return gaussian_blur(image, self.sigma_px)


# ---------------------------------------------------------------------------- defocus
def defocus_diameter_mm(focal_length_mm: float, f_number: float, focus_distance_m: float,
                        object_distance_m: float) -> float:
    """Thin-lens blur circle diameter on the sensor (mm) of a point at
    ``object_distance_m`` when the lens is focused at ``focus_distance_m``:
    c = f² |d − s| / (N d (s − f)), aperture diameter f / N."""
    f = focal_length_mm
    s, d = focus_distance_m * 1000.0, object_distance_m * 1000.0
    if not (f > 0 and f_number > 0 and s > f and d > f):
        raise ValueError("need f > 0, N > 0 and focus and object distances beyond the focal "
                         "length")
    return f * f * abs(d - s) / (f_number * d * (s - f))


def disc_kernel(diameter_x_px: float, diameter_y_px: float | None = None,
                supersample: int = 16) -> np.ndarray:
    """Uniform (elliptical) disc PSF, area-sampled ``supersample``² per pixel, centred
    on the middle element of an odd-sized float32 kernel that sums to 1."""
    dy = diameter_x_px if diameter_y_px is None else diameter_y_px
    ax, ay = 0.5 * diameter_x_px, 0.5 * dy
    if not (ax >= 0 and ay >= 0):
        raise ValueError("disc diameters must be >= 0")
    hx, hy = math.ceil(ax + 0.5), math.ceil(ay + 0.5)
    off = (np.arange(supersample) + 0.5) / supersample - 0.5
    xs = (np.arange(-hx, hx + 1)[:, None] + off[None, :]).ravel()
    ys = (np.arange(-hy, hy + 1)[:, None] + off[None, :]).ravel()
    with np.errstate(divide="ignore", invalid="ignore"):
        inside = (xs[None, :] / max(ax, 1e-12)) ** 2 + (ys[:, None] / max(ay, 1e-12)) ** 2 <= 1
    cover = inside.reshape(2 * hy + 1, supersample, 2 * hx + 1, supersample).sum(axis=(1, 3))
    if cover.sum() == 0:  # smaller than a sub-sample: a point
        cover[hy, hx] = 1
    return (cover / cover.sum()).astype(np.float32)


def defocus_blur(image: np.ndarray, diameter_x_px: float, diameter_y_px: float | None = None
                 ) -> np.ndarray:
    """Convolve with ``disc_kernel`` (the kernel is symmetric, so correlation = convolution)."""
    kernel = disc_kernel(diameter_x_px, diameter_y_px)
    return cv2.filter2D(image, -1, kernel, borderType=BORDER)


@dataclass(frozen=True)
class Defocus(Effect):
    """Thin-lens defocus for a scene at one distance: a uniform disc PSF.

    A single object distance suits nadir surveys of moderate relief (every point near the
    flying height); it ignores depth variations inside the image.
    """

    diameter_x_px: float
    diameter_y_px: float
    kind: ClassVar[str] = "defocus"

    @classmethod
    def from_thin_lens(cls, interior: InteriorOrientation, f_number: float,
                       focus_distance_m: float, object_distance_m: float) -> Defocus:
        c = defocus_diameter_mm(interior.focal_length_mm, f_number, focus_distance_m,
                                object_distance_m)
        return cls(c / interior.pixel_pitch_x_mm, c / interior.pixel_pitch_y_mm)

    @property
    def is_identity(self) -> bool:
        return self.diameter_x_px == 0 and self.diameter_y_px == 0

    def apply(self, image: np.ndarray, frame_index: int, context: FrameContext) -> np.ndarray:
        return defocus_blur(image, self.diameter_x_px, self.diameter_y_px)


@implements(m.Defocus)
@dataclass(frozen=True)
class ThinLensDefocus(Effect):
    """Thin-lens defocus of a camera focused at ``focus_distance_m``: a uniform disc PSF
    whose diameter follows each frame's object distance (``context.distance_m``, the
    distance along the optical axis to the ground at the principal point) unless
    ``object_distance_m`` fixes it for every frame."""

    interior: InteriorOrientation
    f_number: float
    focus_distance_m: float
    object_distance_m: float | None = None
    kind: ClassVar[str] = "defocus"

    def __post_init__(self) -> None:
        if not self.focus_distance_m * 1000.0 > self.interior.focal_length_mm:
            raise DesignerError(
                f"the focus distance {self.focus_distance_m:g} m must exceed the focal length "
                f"{self.interior.focal_length_mm:g} mm")

    @classmethod
    def from_model(cls, element: m.Defocus, camera: CameraContext) -> ThinLensDefocus:
        return cls(camera.interior, element.f_number, element.focus_distance_m,
                   element.object_distance_m)

    def at_distance(self, context: FrameContext) -> Defocus:
        """The fixed-diameter defocus of this frame (``Defocus.from_thin_lens``)."""
        d = self.object_distance_m if self.object_distance_m is not None else \
            context.distance_m
        if d is None:
            raise DesignerError("defocus needs the frame's object distance "
                                "(FrameContext.distance_m) or a fixed object-distance-m")
        return Defocus.from_thin_lens(self.interior, self.f_number, self.focus_distance_m, d)

    def diameter_px(self, context: FrameContext) -> tuple[float, float]:
        """Blur-circle diameter in pixels (x, y) for this frame."""
        fixed = self.at_distance(context)
        return fixed.diameter_x_px, fixed.diameter_y_px

    def apply(self, image: np.ndarray, frame_index: int, context: FrameContext) -> np.ndarray:
        return self.at_distance(context).apply(image, frame_index, context)
