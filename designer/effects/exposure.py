"""Per-image auto exposure and auto white balance (``<exposure-variation>``): a drone
camera meters each photo anew, so overlapping photos of the same ground differ in
brightness and colour. Applied in linear light before the sensor."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from designer.effects.base import CameraContext, Effect, FrameContext, channels_last, frame_key
from designer.effects.registry import implements
from designer.project import model as m

#: wavelengths (m) standing for the camera's red, green and blue channels
_WAVELENGTHS_M = {"R": 600e-9, "G": 540e-9, "B": 460e-9}
#: second radiation constant h·c/k (m·K)
_C2_M_K = 1.438777e-2
_STREAM = 7


def _planck(wavelength_m: float, temperature_k: float) -> float:
    """Black-body spectral radiance up to a constant factor."""
    return 1.0 / (wavelength_m ** 5 * math.expm1(_C2_M_K / (wavelength_m * temperature_k)))


def white_balance_gains(balanced_k: float, light_k: float) -> dict[str, float]:
    """Channel multipliers (green 1) of a camera that balances for ``balanced_k`` while the
    light is ``light_k``: grey under that light comes out grey only when they agree."""
    def ratio(c: str, t: float) -> float:
        return _planck(_WAVELENGTHS_M["G"], t) / _planck(_WAVELENGTHS_M[c], t)
    return {c: ratio(c, balanced_k) / ratio(c, light_k) for c in "RGB"}


@implements(m.ExposureVariation)
@dataclass(frozen=True)
class ExposureWhiteBalance(Effect):
    """Gain 2^e (e ~ N(0, σ_ev²)) and white balance for T ~ N(reference, σ_k²), drawn per
    frame from (seed, frame index)."""

    exposure_sigma_ev: float
    white_balance_sigma_k: float
    reference_k: float = 5500.0
    seed: int = 0
    kind: ClassVar[str] = "exposure"
    runs_after: ClassVar[str] = "blur"
    stage_name: ClassVar[str] = "camera"

    @classmethod
    def from_model(cls, element: m.ExposureVariation, camera: CameraContext
                   ) -> ExposureWhiteBalance:
        return cls(element.exposure_sigma_ev, element.white_balance_sigma_k,
                   element.reference_k, element.seed)

    @property
    def is_identity(self) -> bool:
        return self.exposure_sigma_ev == 0 and self.white_balance_sigma_k == 0

    def frame_draw(self, frame_index: int) -> tuple[float, float]:
        """(exposure error in EV, white-balance temperature in K) of one frame."""
        rng = np.random.default_rng(int(frame_key(self.seed, frame_index, _STREAM)))
        ev, z = rng.standard_normal(2)
        temperature = self.reference_k + self.white_balance_sigma_k * float(z)
        return self.exposure_sigma_ev * float(ev), min(max(temperature, 1000.0), 40000.0)

    def apply(self, image: np.ndarray, frame_index: int, context: FrameContext) -> np.ndarray:
        ev, temperature = self.frame_draw(frame_index)
        gain = 2.0 ** ev
        img = channels_last(np.asarray(image, dtype=np.float32))
        if img.shape[2] == 3:
            wb = white_balance_gains(temperature, self.reference_k)
            order = context.channel_order
            gains = np.array([wb[c] for c in order], dtype=np.float32) * np.float32(gain)
        else:
            gains = np.full(img.shape[2], gain, dtype=np.float32)
        out = img * gains
        return out.reshape(np.shape(image))
