"""Cost of the camera effects per frame at 20 MP (``designer bench effects``).

The camera is the example survey's (DJI Phantom 4 Pro: 5472 × 3648 px, 8.8 mm, Brown
k1 = −0.02, k2 = 0.01). Each case runs ``EffectChain.encode`` on one uint8 RGB pinhole
render of a textured scene (from the decoded render to the bytes of the output file,
what the render worker does per frame besides reading and writing files):

* example survey: the effects of resources/examples/survey (motion blur, distortion,
  vignetting, sensor with shot/dark/read noise and a 12-bit ADC, JPEG 95);
* every effect: those plus thin-lens defocus, a Gaussian blur and DN noise;
* one row per effect alone (its input already in its domain), to show where time goes.

Once per camera, not per frame: building the distortion warp (``warp build``) and, in a
new process, loading the compiled kernels (``first frame``).
"""

from __future__ import annotations

import time

import cv2
import numba
import numpy as np

from designer.bench.timing import best_of
from designer.core.distortion import BrownConrady
from designer.core.interior import InteriorOrientation
from designer.effects.base import FrameContext
from designer.effects.chain import EffectChain, convert_domain
from designer.effects.distortion_render import LensDistortion, pinhole_render_camera
from designer.effects.jpeg import JpegCompression
from designer.effects.motion import LinearMotionBlur
from designer.effects.optics import Defocus, GaussianBlur, RadialVignetting
from designer.effects.sensor import GaussianNoiseDN, SensorModel

CONTEXT = FrameContext(gsd_m=0.055, flight_direction_uv=(0.8, 0.6))


def _camera(scale: float) -> InteriorOrientation:
    w, h = max(64, round(5472 * scale**0.5)), max(48, round(3648 * scale**0.5))
    return InteriorOrientation(
        focal_length_mm=8.8, sensor_width_mm=13.2 * w / 5472, sensor_height_mm=8.8 * h / 3648,
        image_width_px=w, image_height_px=h,
        distortion=BrownConrady(k1=-0.02, k2=0.01),
    )


def _scene_image(width: int, height: int, seed: int = 0) -> np.ndarray:
    """A render-like uint8 BGR image: smooth patches with fine texture and sharp edges."""
    rng = np.random.default_rng(seed)
    coarse = rng.random((height // 64 + 2, width // 64 + 2, 3)).astype(np.float32)
    image = cv2.resize(coarse, (width, height), interpolation=cv2.INTER_CUBIC)
    fine = rng.random((height // 2 + 1, width // 2 + 1, 1)).astype(np.float32)
    image += 0.25 * cv2.resize(fine, (width, height), interpolation=cv2.INTER_NEAREST)[:, :, None]
    image[(np.arange(height) // 97 % 2 == 0)[:, None] & (np.arange(width) // 131 % 2 == 0)] *= 0.5
    return np.clip(image * 160 + 20, 0, 255).astype(np.uint8)


def _effects(interior: InteriorOrientation, warp, scale_px: float) -> dict[str, object]:
    return {
        "motion blur": LinearMotionBlur(0.001, 8.0, scale_px),
        "distortion": LensDistortion(warp),
        "vignetting": RadialVignetting.from_corner_falloff(interior, 0.2),
        "defocus": Defocus.from_thin_lens(interior, 2.8, 60.0, 80.0),
        "blur": GaussianBlur(0.5),
        "sensor": SensorModel(full_well_e=20000.0, exposure_scale=0.8, read_noise_e=3.0,
                              dark_current_e_per_s=0.5, exposure_time_s=0.001, adc_bits=12,
                              seed=5),
        "DN noise": GaussianNoiseDN(1.0, seed=5),
        "JPEG 95": JpegCompression(95),
    }


def run(repeats: int = 3, scale: float = 1.0) -> list[dict]:
    interior = _camera(scale)
    t0 = time.perf_counter()
    render_interior, warp = pinhole_render_camera(interior)
    warp_s = time.perf_counter() - t0
    W_r, H_r = render_interior.image_size_px
    render = _scene_image(W_r, H_r)
    effects = _effects(interior, warp, float(warp.oversample))
    example = EffectChain([effects[k] for k in ("motion blur", "distortion", "vignetting",
                                                 "sensor", "JPEG 95")])
    every = EffectChain(effects.values())
    W, H = interior.image_size_px
    mp = W * H / 1e6
    rows = [{"case": "warp build (once per camera)", "size": f"{W}x{H}", "seconds": warp_s}]
    t0 = time.perf_counter()
    example.encode(render, 0, ".jpg", CONTEXT)
    rows.append({"case": "first frame (compiles/loads kernels)", "size": f"{W}x{H}",
                 "seconds": time.perf_counter() - t0})
    for label, chain in (("example survey chain", example), ("every effect", every)):
        seconds, data = best_of(repeats, lambda c=chain: c.encode(render, 1, ".jpg", CONTEXT))
        rows.append({"case": label, "size": f"{W}x{H}", "seconds": seconds, "mp": mp,
                     "note": " → ".join(chain.kinds), "bytes": len(data)})
    # each effect alone, on its input in its own domain
    linear_render = convert_domain(render, "integer", "linear", np.uint8)
    linear = warp.apply(linear_render)
    for label, effect in effects.items():
        if label == "motion blur" or label == "distortion":
            src = linear_render
        elif effect.domain == "linear":
            src = linear
        elif effect.domain == "encoded":
            src = convert_domain(linear, "linear", "encoded", np.uint8)
        else:
            src = convert_domain(linear, "linear", "integer", np.uint8)
        if isinstance(effect, JpegCompression):
            seconds, _ = best_of(repeats, lambda e=effect, s=src: e.encode(s, CONTEXT))
        else:
            seconds, _ = best_of(repeats, lambda e=effect, s=src: e.apply(s, 1, CONTEXT))
        rows.append({"case": f"  {label} alone", "size": f"{src.shape[1]}x{src.shape[0]}",
                     "seconds": seconds, "mp": src.shape[0] * src.shape[1] / 1e6})
    for label, conv in (("  decode sRGB → linear", lambda: convert_domain(render, "integer",
                                                                      "linear", np.uint8)),
                        ("  encode linear → sRGB uint8", lambda: convert_domain(linear, "linear",
                                                                            "integer",
                                                                            np.uint8))):
        src = render if "decode" in label else linear
        seconds, _ = best_of(repeats, conv)
        rows.append({"case": label, "size": f"{src.shape[1]}x{src.shape[0]}",
                     "seconds": seconds, "mp": src.shape[0] * src.shape[1] / 1e6})
    return rows


def format_table(rows: list[dict]) -> str:
    lines = [f"{'case':<38} {'size':>10} {'seconds':>8} {'MP/s':>7}  effects", "-" * 100]
    for r in rows:
        rate = f"{r['mp'] / r['seconds']:>7.1f}" if "mp" in r else f"{'':>7}"
        lines.append(f"{r['case']:<38} {r['size']:>10} {r['seconds']:>8.3f} {rate}  "
                     f"{r.get('note', '')}")
    lines.append(f"(uint8 RGB; {numba.get_num_threads()} numba threads, "
                 f"{cv2.getNumThreads()} OpenCV threads; best of the repeats; sizes are the "
                 f"input of each step: effects before the warp see the larger pinhole render)")
    return "\n".join(lines)
