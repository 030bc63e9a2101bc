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
* ``registry``: which effect implements which project element (``@implements``);
* ``from_model``: the project model's effects → a chain, through the registry.

Use, per camera and frame::

    render_interior, warp = pinhole_render_camera(interior)   # once; warp.save(cache)
    chain = effects_from_model(project.effects, interior, warp=warp)
    # Blender renders render_interior (blender_camera(render_interior)), then per frame:
    process_file(raw_png, out_png, chain, frame_index,
                 FrameContext(gsd_m=gsd, flight_direction_uv=direction))
"""

from typing import TYPE_CHECKING

from designer._lazy import attach

__getattr__, __dir__, __all__ = attach(__name__, {
    "CameraContext": "designer.effects.base",
    "Defocus": "designer.effects.optics",
    "DistortionWarp": "designer.effects.distortion_render",
    "EFFECT_ORDER": "designer.effects.base",
    "Effect": "designer.effects.base",
    "EffectChain": "designer.effects.chain",
    "FrameContext": "designer.effects.base",
    "GaussianBlur": "designer.effects.optics",
    "GaussianNoiseDN": "designer.effects.sensor",
    "JpegCompression": "designer.effects.jpeg",
    "LensDistortion": "designer.effects.distortion_render",
    "LinearMotionBlur": "designer.effects.motion",
    "NaturalVignetting": "designer.effects.optics",
    "RadialVignetting": "designer.effects.optics",
    "SensorModel": "designer.effects.sensor",
    "effects_from_model": "designer.effects.from_model",
    "encode_jpeg": "designer.effects.jpeg",
    "frame_key": "designer.effects.base",
    "gaussian_blur": "designer.effects.optics",
    "implements": "designer.effects.registry",
    "jpeg_roundtrip": "designer.effects.jpeg",
    "linear_motion_kernel": "designer.effects.motion",
    "linear_to_srgb": "designer.effects.srgb",
    "motion_blur": "designer.effects.motion",
    "pinhole_render_camera": "designer.effects.distortion_render",
    "process_file": "designer.effects.chain",
    "registered_effects": "designer.effects.registry",
    "simulate_sensor": "designer.effects.sensor",
    "srgb_to_linear": "designer.effects.srgb",
    "write_jpeg": "designer.effects.jpeg",
})

if TYPE_CHECKING:
    from designer.effects.base import (
        EFFECT_ORDER,
        CameraContext,
        Effect,
        FrameContext,
        frame_key,
    )
    from designer.effects.chain import EffectChain, process_file
    from designer.effects.distortion_render import (
        DistortionWarp,
        LensDistortion,
        pinhole_render_camera,
    )
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
    from designer.effects.registry import implements, registered_effects
    from designer.effects.sensor import GaussianNoiseDN, SensorModel, simulate_sensor
    from designer.effects.srgb import linear_to_srgb, srgb_to_linear
