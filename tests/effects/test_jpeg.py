"""JPEG compression: quality changes the bytes, stays within a PSNR bound, writes atomically."""

import cv2
import numpy as np
import pytest

from designer.effects.base import FrameContext
from designer.effects.jpeg import (
    JpegCompression,
    decode_jpeg,
    encode_jpeg,
    jpeg_roundtrip,
    write_jpeg,
)
from designer.errors import DesignerError


def photo(seed=0, size=(240, 320)):
    """A textured colour image: smooth gradients plus fine seeded detail."""
    rng = np.random.default_rng(seed)
    v, u = np.mgrid[0:size[0], 0:size[1]]
    base = np.stack([u / size[1], v / size[0], 0.5 + 0.3 * np.sin(u / 9.0)], axis=-1)
    detail = cv2.GaussianBlur(rng.random(size + (3,)), (0, 0), 1.2)
    return np.clip(255 * (0.7 * base + 0.3 * detail), 0, 255).astype(np.uint8)


def psnr(a, b):
    mse = np.mean((a.astype(np.float64) - b.astype(np.float64)) ** 2)
    return 10 * np.log10(255**2 / mse)


@pytest.mark.parametrize(("quality", "min_psnr"), [(95, 38.5), (75, 35.0), (30, 32.0)])
def test_quality_bounds_the_error(quality, min_psnr):
    img = photo()
    out = jpeg_roundtrip(img, quality)
    assert out.shape == img.shape and out.dtype == np.uint8
    assert min_psnr <= psnr(img, out) < 60  # lossy, but not by more than the bound


def test_quality_changes_the_bytes_and_size():
    img = photo()
    sizes = [len(encode_jpeg(img, q)) for q in (30, 75, 95)]
    assert sizes[0] < sizes[1] < sizes[2]
    assert encode_jpeg(img, 75) == encode_jpeg(img, 75)  # deterministic
    assert psnr(img, jpeg_roundtrip(img, 95)) > psnr(img, jpeg_roundtrip(img, 30))


def test_channel_order_matters_and_is_honoured():
    bgr = photo(1)
    rgb = np.ascontiguousarray(bgr[:, :, ::-1])
    a = jpeg_roundtrip(bgr, 60, "BGR")
    b = jpeg_roundtrip(rgb, 60, "RGB")
    np.testing.assert_array_equal(a, b[:, :, ::-1])
    wrong = jpeg_roundtrip(rgb, 60, "BGR")[:, :, ::-1]
    assert not np.array_equal(a, wrong)


def test_grey_images_and_16_bit_refusal():
    grey = photo()[:, :, 1]
    assert jpeg_roundtrip(grey, 80).shape == grey.shape
    with pytest.raises(DesignerError, match="8 bits"):
        encode_jpeg(grey.astype(np.uint16), 80)
    with pytest.raises(ValueError):
        JpegCompression(0)


def test_write_jpeg_is_the_encoded_bytes(tmp_path):
    img = photo(2)
    path = tmp_path / "a.jpg"
    write_jpeg(path, img, 85)
    assert path.read_bytes() == encode_jpeg(img, 85)
    assert [p.name for p in tmp_path.iterdir()] == ["a.jpg"]  # no temporary left
    np.testing.assert_array_equal(decode_jpeg(path.read_bytes()),
                                  JpegCompression(85).apply(img, 0, FrameContext()))
