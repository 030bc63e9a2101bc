"""Lateral chromatic aberration (``<chromatic-aberration>``): the lens images red and blue
at a slightly different scale than green, radially about the principal point. A point of
a channel at radius r lands at r·(1 + s·10⁻⁶), s the channel's scale in parts per million;
green stays exact, so the exported ground truth (green's) is unchanged.

Applied in linear light on the output pixels, right after the lens distortion (it is a
wavelength-dependent part of the lens's mapping) and before vignetting, blur and the
sensor. Each scaled channel is resampled with the project's cubic B-splines (prefiltered,
so they interpolate) at float64 positions (designer.effects.resample). The map is a pure
scaling, so it is the same in pixel and in sensor units, square pixels or not.

Near the image edge an enlarged channel has no rendered light to draw from: the image is
mirrored about the edge pixels' centres there (at most |s|·10⁻⁶ × the corner radius, e.g.
0.7 px at 200 ppm on a 20 MP frame), and the prefilter's boundary disturbs the outermost
few pixels (designer.effects.resample.SUPPORT_PX).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from designer.effects._resample_kernels import bspline_coefficients, sample_cubic
from designer.effects.base import CameraContext, Effect, FrameContext
from designer.effects.registry import implements
from designer.project import model as m

#: rows resampled at a time: bounds the float64 position maps (2 × 8 bytes per pixel)
_ROWS_PER_BLOCK = 256


def scaled_channel(plane: np.ndarray, cx_px: float, cy_px: float, scale: float
                   ) -> np.ndarray:
    """A (H, W) float32 channel imaged at ``scale`` times its radius about (cx_px, cy_px)
    (continuous pixel coordinates): output pixel centre p takes the channel's value at
    pp + (p − pp) / scale → (H, W) float32."""
    h, w = plane.shape
    coeffs = bspline_coefficients(np.ascontiguousarray(plane[:, :, None], dtype=np.float32))
    u_src = cx_px + (np.arange(w) + 0.5 - cx_px) / scale
    v_src = cy_px + (np.arange(h) + 0.5 - cy_px) / scale
    out = np.empty((h, w), np.float32)
    for top in range(0, h, _ROWS_PER_BLOCK):
        rows = v_src[top:top + _ROWS_PER_BLOCK]
        u = np.ascontiguousarray(np.broadcast_to(u_src, (rows.size, w)))
        v = np.ascontiguousarray(np.broadcast_to(rows[:, None], (rows.size, w)))
        out[top:top + rows.size] = sample_cubic(coeffs, u, v, 1)[:, :, 0]
    return out


@implements(m.ChromaticAberration)
@dataclass(frozen=True)
class LateralChromaticAberration(Effect):
    """Red and blue scaled by 1 + ppm·10⁻⁶ about the principal point (cx_px, cy_px) of an
    image of ``image_size_px`` (W, H); green and single-channel images are left as they
    are."""

    cx_px: float
    cy_px: float
    image_size_px: tuple[int, int]
    red_scale_ppm: float
    blue_scale_ppm: float
    kind: ClassVar[str] = "chromatic_aberration"
    runs_after: ClassVar[str] = "distortion"
    stage_name: ClassVar[str] = "optics"

    @classmethod
    def from_model(cls, element: m.ChromaticAberration, camera: CameraContext
                   ) -> LateralChromaticAberration:
        """On the output camera's pixels (the effect runs after the distortion warp)."""
        interior = camera.interior
        return cls(interior.cx_px, interior.cy_px, tuple(interior.image_size_px),
                   element.red_scale_ppm, element.blue_scale_ppm)

    @property
    def is_identity(self) -> bool:
        return self.red_scale_ppm == 0 and self.blue_scale_ppm == 0

    def apply(self, image: np.ndarray, frame_index: int, context: FrameContext) -> np.ndarray:
        img = np.asarray(image, dtype=np.float32)
        w, h = self.image_size_px
        if img.shape[:2] != (h, w):
            raise ValueError(f"the image is {img.shape[1]} × {img.shape[0]} px; the camera's "
                             f"chromatic aberration is for {w} × {h} px")
        out = img.copy()
        if img.ndim == 2 or img.shape[2] != 3:
            return out
        for channel, ppm in (("R", self.red_scale_ppm), ("B", self.blue_scale_ppm)):
            if ppm != 0:
                k = context.channel_order.index(channel)
                out[:, :, k] = scaled_channel(img[:, :, k], self.cx_px, self.cy_px,
                                              1.0 + ppm * 1e-6)
        return out
