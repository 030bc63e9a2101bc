"""What every image effect shares: its place in the chain, its domain, per-frame seeding.

Domains (how an effect wants its pixels):

* ``"linear"``: float32 linear light, 0 = black, 1 = the largest code value (white);
  the sRGB transfer function already undone. Physics (warps, blur, vignetting,
  photon and read noise) happens here.
* ``"encoded"``: float32 sRGB-encoded values on 0 … 1 (code value / largest code),
  not yet rounded: noise specified in digital numbers of the stored image lives here.
* ``"integer"``: the stored uint8 / uint16 image itself (JPEG works on bytes).

Images are (H, W) or (H, W, C) arrays, rows first, pixel (i, j) covering
[i, i+1) × [j, j+1) in the continuous pixel coordinates of docs/conventions.md.
Channels are in OpenCV order (B, G, R) unless ``FrameContext.channel_order`` says
otherwise; only the JPEG encoder cares (its YCbCr conversion weighs R, G, B
differently), every other effect treats the channels alike.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, ClassVar, Literal

import numpy as np

from designer.errors import ParameterValueError

if TYPE_CHECKING:
    from designer.core.interior import InteriorOrientation

Domain = Literal["linear", "encoded", "integer"]
ChannelOrder = Literal["BGR", "RGB"]

#: the order effects run in (lowest first): optics → sensor → camera. Motion blur runs on
#: the pinhole render before the distortion warp: for a camera translating over flat
#: ground the image motion is uniform in the pinhole image, not in the distorted one.
#: Vignetting and the lens blurs run on the output (distorted) pixel grid.
EFFECT_ORDER: tuple[str, ...] = (
    "motion_blur",   # optics: scene moves during the exposure (pinhole render pixels)
    "distortion",    # optics: the lens maps the pinhole render onto the sensor
    "vignetting",    # optics: light fall-off towards the corners, fixed to the sensor
    "defocus",       # optics: thin-lens disc PSF
    "blur",          # optics: Gaussian PSF
    "sensor",        # sensor: shot noise, dark current, read noise, ADC quantisation
    "noise_dn",      # sensor: Gaussian noise in digital numbers of the stored image
    "jpeg",          # camera: JPEG compression
)
STAGE_OF: dict[str, str] = {
    "motion_blur": "optics", "distortion": "optics", "vignetting": "optics",
    "defocus": "optics", "blur": "optics", "sensor": "sensor", "noise_dn": "sensor",
    "jpeg": "camera",
}


@dataclass(frozen=True)
class FrameContext:
    """What an effect may need to know about the frame beyond its pixels.

    Attributes:
        gsd_m: ground sample distance of the frame (m per output pixel), for motion blur.
        flight_direction_uv: direction of the camera's motion in the image, a vector
            (du, dv) in pixel axes (u right, v down); normalised by the effect.
        channel_order: "BGR" (OpenCV, the default) or "RGB" for 3-channel images.
        distance_m: distance (m) along the optical axis from the camera to the ground at
            the principal point, for defocus.
    """

    gsd_m: float | None = None
    flight_direction_uv: tuple[float, float] | None = None
    channel_order: ChannelOrder = "BGR"
    distance_m: float | None = None


@dataclass(frozen=True)
class CameraContext:
    """What an effect built from a project element needs to know about the camera.

    Attributes:
        interior: the output camera (with its distortion), whose pixels the effects
            after the distortion warp see.
        pixels_per_output_px: how much finer than the output the pinhole render is
            (the distortion warp's oversample; 1 without distortion), for the effects
            that run before the warp.
    """

    interior: InteriorOrientation
    pixels_per_output_px: float = 1.0


class Effect:
    """Base of every effect: a frozen dataclass with a ``kind`` from EFFECT_ORDER.

    ``apply(image, frame_index, context)`` returns a new image in the effect's domain
    and never modifies its input. An effect a project can ask for names its model
    element in ``model`` and builds itself from that element whole in ``from_model``
    (both set up by ``designer.effects.registry.implements``).
    """

    #: the project model class (``designer.project.model``) this effect implements;
    #: None for effects only code builds (the distortion warp comes from the camera)
    model: ClassVar[type | None] = None
    kind: ClassVar[str] = ""
    domain: ClassVar[Domain] = "linear"
    #: an effect whose kind is not in EFFECT_ORDER runs right after this kind, in this
    #: stage (so a new effect is declared in its own module alone)
    runs_after: ClassVar[str] = ""
    stage_name: ClassVar[str] = ""

    @classmethod
    def from_model(cls, element: Any, camera: CameraContext) -> Effect:
        """The effect a project's ``element`` (an instance of ``cls.model``) asks for."""
        raise NotImplementedError(f"{cls.__name__} is not built from a project element")

    @property
    def is_identity(self) -> bool:
        """True if the effect leaves every pixel as it is (e.g. a blur with σ = 0)."""
        return False

    @property
    def rank(self) -> float:
        if self.kind in EFFECT_ORDER:
            return EFFECT_ORDER.index(self.kind)
        return EFFECT_ORDER.index(self.runs_after) + 0.5

    @property
    def stage(self) -> str:
        return STAGE_OF.get(self.kind) or self.stage_name

    def apply(self, image: np.ndarray, frame_index: int, context: FrameContext) -> np.ndarray:
        raise NotImplementedError


def frame_key(seed: int, frame_index: int, stream: int = 0) -> np.uint64:
    """The 64-bit key of one frame's random numbers: the first word NumPy's
    SeedSequence([seed, frame_index]) (+ [stream] if > 0) generates.

    The same (seed, frame, stream) always gives the same numbers; different frames and
    streams get unrelated keys. ``stream`` separates effects that share a seed. The
    compiled kernels draw counter-based numbers from it (designer/effects/_sensor_kernels.py),
    so an image's noise does not depend on the number of threads.
    """
    for name, value in (("seed", seed), ("frame_index", frame_index), ("stream", stream)):
        if isinstance(value, bool) or not isinstance(value, int | np.integer) or value < 0:
            raise ParameterValueError(f"{name} = {value!r} must be a whole number >= 0",
                                      name=name, value=value, must="a whole number, at least 0")
    key = [int(seed), int(frame_index)] + ([int(stream)] if stream else [])
    return np.random.SeedSequence(key).generate_state(1, np.uint64)[0]


def channels_last(image: np.ndarray) -> np.ndarray:
    """(H, W) → (H, W, 1) view; (H, W, C) unchanged."""
    return image[:, :, None] if image.ndim == 2 else image
