"""Camera effects applied to rendered images: numpy, SciPy and OpenCV only, never bpy.

Blender renders an exact pinhole image; this package adds only the effects a project asks
for, in physical order (``chain.EffectChain``):

* ``distortion_render``: the enlarged pinhole camera to render and the warp through the
  lens (Brown–Conrady or fisheye), exact to 1e-6 px;
* ``optics``: vignetting, Gaussian blur, thin-lens defocus;
* ``motion``: linear motion blur of a camera translating over flat ground;
* ``sensor``: shot noise, dark current, read noise, ADC; Gaussian DN noise;
* ``jpeg``: JPEG compression;
* ``srgb``: the exact sRGB transfer function;
* ``from_model``: the project model's effects → a chain.

Use, per camera and frame::

    render_interior, warp = pinhole_render_camera(interior)   # once; warp.save(cache)
    chain = effects_from_model(project.effects, interior, warp=warp)
    # Blender renders render_interior (blender_camera(render_interior)), then per frame:
    process_file(raw_png, out_png, chain, frame_index,
                 FrameContext(gsd_m=gsd, flight_direction_uv=direction))
"""

from designer.effects.base import EFFECT_ORDER, Effect, FrameContext, frame_key
from designer.effects.chain import EffectChain, process_file
from designer.effects.distortion_render import DistortionWarp, LensDistortion, pinhole_render_camera
from designer.effects.from_model import effects_from_model
from designer.effects.jpeg import JpegCompression, encode_jpeg, jpeg_roundtrip, write_jpeg
from designer.effects.motion import LinearMotionBlur, linear_motion_kernel, motion_blur
from designer.effects.optics import (
    Defocus,
    GaussianBlur,
    NaturalVignetting,
    RadialVignetting,
    gaussian_blur,
)
from designer.effects.sensor import GaussianNoiseDN, SensorModel, simulate_sensor
from designer.effects.srgb import linear_to_srgb, srgb_to_linear

__all__ = [
    "EFFECT_ORDER", "Defocus", "DistortionWarp", "Effect", "EffectChain", "FrameContext",
    "GaussianBlur", "GaussianNoiseDN", "JpegCompression", "LensDistortion", "LinearMotionBlur",
    "NaturalVignetting", "RadialVignetting", "SensorModel", "effects_from_model",
    "encode_jpeg", "frame_key", "gaussian_blur", "jpeg_roundtrip", "linear_motion_kernel",
    "linear_to_srgb", "motion_blur", "pinhole_render_camera", "process_file",
    "simulate_sensor", "srgb_to_linear", "write_jpeg",
]
