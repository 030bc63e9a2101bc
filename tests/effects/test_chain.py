"""The effect chain: order, pass-through without effects, linear-light processing, files."""

import os

import cv2
import numpy as np
import pytest

from designer.core.distortion import BrownConrady
from designer.effects import (
    EFFECT_ORDER,
    EffectChain,
    FrameContext,
    GaussianBlur,
    GaussianNoiseDN,
    JpegCompression,
    LensDistortion,
    LinearMotionBlur,
    RadialVignetting,
    SensorModel,
    effects_from_model,
    encode_jpeg,
    pinhole_render_camera,
    process_file,
)
from designer.effects.optics import Defocus
from designer.effects.srgb import decode_image, encode_image
from designer.errors import DesignerError
from designer.project import model as m
from tests.synthetic import pixel_camera

PLAIN = pixel_camera(64, 48, 60.0, None)
DISTORTED = pixel_camera(64, 48, 60.0, BrownConrady(k1=-0.15, p1=1e-3))
CTX = FrameContext(gsd_m=0.05, flight_direction_uv=(1.0, 0.2))


def image(dtype=np.uint8, size=(48, 64), seed=0):
    rng = np.random.default_rng(seed)
    top = np.iinfo(dtype).max
    return (rng.random(size + (3,)) * top).astype(dtype)


def every_effect(interior=DISTORTED):
    _, warp = pinhole_render_camera(interior)
    return [JpegCompression(90), GaussianNoiseDN(1.0, 3), SensorModel(seed=3),
            GaussianBlur(0.7), Defocus(1.5, 1.5),
            RadialVignetting.from_corner_falloff(interior, 0.3),
            LensDistortion(warp), LinearMotionBlur(1 / 250, 10.0)]


def test_order_is_optics_then_sensor_then_camera():
    chain = EffectChain(every_effect())
    assert chain.kinds == EFFECT_ORDER
    assert chain.kinds == ("motion_blur", "distortion", "vignetting", "defocus", "blur",
                           "sensor", "noise_dn", "jpeg")
    stages = [e.stage for e in chain]
    assert stages == sorted(stages, key=["optics", "sensor", "camera"].index)
    assert repr(chain).startswith("EffectChain(motion_blur, distortion")


def test_every_effect_runs_and_keeps_the_type():
    chain = EffectChain(every_effect())
    render = chain.warp.render_interior
    src = image(np.uint8, render.image_size_px[::-1])
    before = src.copy()
    out = chain.apply(src, 5, CTX)
    assert out.dtype == np.uint8 and out.shape == (48, 64, 3)
    np.testing.assert_array_equal(src, before)  # input untouched
    np.testing.assert_array_equal(out, chain.apply(src, 5, CTX))  # reproducible per frame
    assert not np.array_equal(out, chain.apply(src, 6, CTX))
    no_jpeg = EffectChain([e for e in every_effect() if e.kind != "jpeg"])
    out16 = no_jpeg.apply(image(np.uint16, render.image_size_px[::-1]), 0, CTX)
    assert out16.dtype == np.uint16 and out16.shape == (48, 64, 3)


def test_empty_chain_returns_the_image_itself():
    chain = EffectChain([GaussianBlur(0.0), GaussianNoiseDN(0.0), LinearMotionBlur(0.0, 5.0),
                         RadialVignetting.from_corner_falloff(PLAIN, 0.0)])
    assert chain.is_empty and len(chain) == 0
    img = image()
    assert chain.apply(img, 0) is img


def test_physics_happens_in_linear_light():
    effect = RadialVignetting.from_corner_falloff(PLAIN, 0.4)
    img = image(np.uint16, seed=4)
    out = EffectChain([effect]).apply(img, 0)
    expect = encode_image(decode_image(img) * effect.gain[:, :, None], np.uint16)
    np.testing.assert_array_equal(out, expect)


def test_dn_noise_is_in_stored_digital_numbers():
    img = np.full((200, 300), 128, np.uint8)
    out = EffectChain([GaussianNoiseDN(2.0, seed=1)]).apply(img, 0).astype(np.float64)
    assert out.mean() == pytest.approx(128, abs=0.05)
    assert out.std() == pytest.approx(np.sqrt(4 + 1 / 12), rel=0.03)  # + rounding
    img16 = np.full((200, 300), 30000, np.uint16)
    out16 = EffectChain([GaussianNoiseDN(2.0, seed=1)]).apply(img16, 0).astype(np.float64)
    assert out16.std() == pytest.approx(2.0 * 257, rel=0.03)  # scaled for 16 bit


# ------------------------------------------------------------------------------ files
def write_png(path, img):
    cv2.imwrite(os.fspath(path), img, [cv2.IMWRITE_PNG_COMPRESSION, 9])


@pytest.mark.parametrize("how", ["copy", "link", "move"])
def test_empty_chain_passes_files_through_byte_for_byte(tmp_path, how):
    src, dst = tmp_path / "render.png", tmp_path / "out" / "IMG_0001.png"
    dst.parent.mkdir()
    img = image(np.uint16)
    write_png(src, img)
    original = src.read_bytes()
    _, reencoded = cv2.imencode(".png", cv2.imread(os.fspath(src), cv2.IMREAD_UNCHANGED))
    assert reencoded.tobytes() != original  # so a decode + encode would be caught
    process_file(src, dst, effects_from_model(m.Effects(blur=m.Blur(0.0)), PLAIN),
                 passthrough=how)
    assert dst.read_bytes() == original
    if how == "link":
        assert os.path.samefile(src, dst)
    assert src.exists() == (how != "move")
    assert sorted(p.name for p in dst.parent.iterdir()) == ["IMG_0001.png"]


def test_empty_chain_refuses_a_format_change(tmp_path):
    src = tmp_path / "a.png"
    write_png(src, image())
    with pytest.raises(DesignerError, match="re-encode"):
        process_file(src, tmp_path / "a.jpg", EffectChain())
    process_file(src, tmp_path / "b.PNG", EffectChain())  # same format, other case


def test_process_file_with_effects(tmp_path):
    chain = effects_from_model(m.Effects(blur=m.Blur(1.0), jpeg=m.Jpeg(80)), DISTORTED)
    render = chain.warp.render_interior
    src = tmp_path / "r.png"
    write_png(src, image(np.uint8, render.image_size_px[::-1]))
    process_file(src, tmp_path / "o.png", chain, 2)
    out = cv2.imread(os.fspath(tmp_path / "o.png"), cv2.IMREAD_UNCHANGED)
    assert out.shape == (48, 64, 3)
    np.testing.assert_array_equal(out, chain.apply(cv2.imread(os.fspath(src)), 2))
    # .jpg: the JPEG effect's own bytes, compressed once
    process_file(src, tmp_path / "o.jpg", chain, 2)
    before_jpeg = EffectChain([e for e in chain if e.kind != "jpeg"]).apply(
        cv2.imread(os.fspath(src)), 2)
    assert (tmp_path / "o.jpg").read_bytes() == encode_jpeg(before_jpeg, 80)
    with pytest.raises(DesignerError, match="JPEG effect"):
        process_file(src, tmp_path / "x.jpg",
                     effects_from_model(m.Effects(blur=m.Blur(1.0)), DISTORTED), 2)


# ------------------------------------------------------------------------ the adapter
def test_effects_from_model():
    assert effects_from_model(None, PLAIN).is_empty
    assert effects_from_model(m.Effects(), PLAIN).is_empty
    zero = m.Effects(vignetting=m.Vignetting(0.0), sensor_noise=m.SensorNoise(0.0, 1),
                     blur=m.Blur(0.0), motion_blur=m.MotionBlur(0.0, 12.0))
    assert effects_from_model(zero, PLAIN).is_empty
    full = m.Effects(vignetting=m.Vignetting(0.2), sensor_noise=m.SensorNoise(1.5, 5),
                     blur=m.Blur(0.7), motion_blur=m.MotionBlur(1 / 1000, 12.0),
                     jpeg=m.Jpeg(90))
    chain = effects_from_model(full, PLAIN)
    assert chain.kinds == ("motion_blur", "vignetting", "blur", "noise_dn", "jpeg")
    assert chain.warp is None
    noise = next(e for e in chain if e.kind == "noise_dn")
    assert (noise.sigma_dn, noise.seed) == (1.5, 5)
    # distortion comes from the camera, even without effects
    distorted = effects_from_model(None, DISTORTED)
    assert distorted.kinds == ("distortion",)
    _, warp = pinhole_render_camera(DISTORTED, 2)
    chain = effects_from_model(full, DISTORTED, warp=warp)
    assert chain.warp is warp and chain.kinds[:2] == ("motion_blur", "distortion")
    motion = chain.effects[0]
    assert motion.pixels_per_output_px == 2.0  # it runs on the 2× render
    with pytest.raises(ValueError, match="another camera"):
        effects_from_model(full, PLAIN, warp=warp)
    # the vignetting's polynomial and cos⁴ terms, and thin-lens defocus
    more = m.Effects(vignetting=m.Vignetting(0.1, 0.02, 0.0, natural_cos4=True),
                     defocus=m.Defocus(2.8, 30.0, 60.0))
    chain = effects_from_model(more, PLAIN)
    assert chain.kinds == ("vignetting", "defocus")
    vignetting, defocus = chain.effects
    assert vignetting.coefficients == (-0.1, 0.02, 0.0) and vignetting.natural_cos4
    assert (defocus.f_number, defocus.focus_distance_m, defocus.object_distance_m) == (
        2.8, 30.0, 60.0)


def test_images_the_chain_refuses():
    chain = EffectChain([GaussianBlur(1.0)])
    with pytest.raises(TypeError, match="uint8 or uint16"):
        chain.apply(np.zeros((4, 4, 3), np.float32), 0)
    with pytest.raises(ValueError, match=r"\(H, W, 3\)"):
        chain.apply(np.zeros((4, 4, 4), np.uint8), 0)
    grey = chain.apply(np.full((20, 30), 77, np.uint8), 0)
    assert grey.shape == (20, 30) and (grey == 77).all()


@pytest.mark.parametrize("dtype", [np.uint8, np.uint16])
def test_every_code_survives_the_chain_without_clipping_or_rounding(dtype):
    """Every code of the type, from black to full white, through decode → linear-light
    effect → encode: an effect that changes nothing (a blur narrower than a pixel's
    kernel) gives back the very same codes, and a plain gain moves every code to the
    nearest code of the scaled light (none clipped, none off by one)."""
    top = np.iinfo(dtype).max
    codes = np.arange(top + 1, dtype=dtype).reshape(-1, 256)
    codes = np.stack([codes] * 3, axis=-1)
    same = EffectChain([GaussianBlur(1e-6)]).apply(codes, 0)
    np.testing.assert_array_equal(same, codes)
    interior = pixel_camera(256, codes.shape[0], 300.0, None)  # gain 1 at the centre, ½ in corners
    vignetting = RadialVignetting(interior, (-0.5,))
    half = EffectChain([vignetting]).apply(codes, 0)
    expected = encode_image(decode_image(codes).astype(np.float64)
                            * vignetting.gain[:, :, None].astype(np.float64), dtype)
    np.testing.assert_array_equal(half, expected)
    assert half[0, 0, 0] == 0 and half[-1, -1, 0] < top  # the brightest code lies in a corner
