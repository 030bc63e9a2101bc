"""JPEG compression with OpenCV (libjpeg): baseline, 8 bits, 4:2:0 chroma subsampling.

Images are uint8, (H, W) grey or (H, W, 3) colour. OpenCV's encoder expects B, G, R
order: the YCbCr conversion weighs the channels differently, so an RGB array must be
declared (``channel_order="RGB"``) or its red and blue artefacts are swapped.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from typing import ClassVar

import cv2
import numpy as np

from designer.atomic import write_bytes_atomic
from designer.effects.base import CameraContext, ChannelOrder, Effect, FrameContext
from designer.effects.registry import implements
from designer.errors import DesignerError, ParameterValueError
from designer.project import model as m


def _check(image: np.ndarray, quality: int) -> None:
    if isinstance(quality, bool) or not isinstance(quality, int | np.integer) or not (
            1 <= quality <= 100):
        raise ParameterValueError(
            f"JPEG quality {quality!r} must be a whole number from 1 to 100", name="quality",
            value=quality, must="a whole number from 1 to 100")
    if image.dtype != np.uint8:
        raise DesignerError(f"JPEG stores 8 bits per channel, the image is {image.dtype}; "
                            f"render 8-bit images or drop the JPEG effect")
    if not (image.ndim == 2 or (image.ndim == 3 and image.shape[2] in (1, 3))):
        raise ValueError(f"JPEG needs (H, W) or (H, W, 3) images, got {image.shape}")


def encode_jpeg(image: np.ndarray, quality: int, channel_order: ChannelOrder = "BGR"
                ) -> bytes:
    """The bytes of a .jpg file holding ``image`` (uint8) at ``quality`` (1 … 100)."""
    _check(image, quality)
    if image.ndim == 3 and image.shape[2] == 3 and channel_order == "RGB":
        image = image[:, :, ::-1]
    params = [cv2.IMWRITE_JPEG_QUALITY, int(quality),
              cv2.IMWRITE_JPEG_SAMPLING_FACTOR, cv2.IMWRITE_JPEG_SAMPLING_FACTOR_420,
              cv2.IMWRITE_JPEG_PROGRESSIVE, 0, cv2.IMWRITE_JPEG_OPTIMIZE, 0]
    ok, buf = cv2.imencode(".jpg", np.ascontiguousarray(image), params)
    if not ok:
        raise DesignerError("OpenCV could not encode the image as JPEG")
    return buf.tobytes()


def decode_jpeg(data: bytes, channel_order: ChannelOrder = "BGR", grey: bool = False
                ) -> np.ndarray:
    """Decode .jpg bytes to uint8 (H, W, 3) in ``channel_order``, or (H, W) if ``grey``."""
    flag = cv2.IMREAD_GRAYSCALE if grey else cv2.IMREAD_COLOR
    image = cv2.imdecode(np.frombuffer(data, dtype=np.uint8), flag)
    if image is None:
        raise DesignerError("OpenCV could not decode the JPEG data")
    if not grey and channel_order == "RGB":
        image = np.ascontiguousarray(image[:, :, ::-1])
    return image


def jpeg_roundtrip(image: np.ndarray, quality: int, channel_order: ChannelOrder = "BGR"
                   ) -> np.ndarray:
    """``image`` as a camera saving JPEG at ``quality`` would store it (same shape)."""
    data = encode_jpeg(image, quality, channel_order)
    out = decode_jpeg(data, channel_order, grey=image.ndim == 2 or image.shape[2] == 1)
    return out.reshape(image.shape)


def write_jpeg(path: str | os.PathLike, image: np.ndarray, quality: int,
               channel_order: ChannelOrder = "BGR") -> None:
    """Write ``image`` as a .jpg file at ``quality``, atomically."""
    write_bytes_atomic(path, encode_jpeg(image, quality, channel_order))


@implements(m.Jpeg)
@dataclass(frozen=True)
class JpegCompression(Effect):
    """JPEG compression artefacts at ``quality``; works on the stored uint8 image."""

    quality: int
    kind: ClassVar[str] = "jpeg"
    domain: ClassVar[str] = "integer"

    def __post_init__(self) -> None:
        _check(np.zeros((1, 1), np.uint8), self.quality)

    @classmethod
    def from_model(cls, element: m.Jpeg, camera: CameraContext) -> JpegCompression:
        return cls(element.quality)

    def encode(self, image: np.ndarray, context: FrameContext) -> bytes:
        return encode_jpeg(image, self.quality, context.channel_order)

    def apply(self, image: np.ndarray, frame_index: int, context: FrameContext) -> np.ndarray:
        return jpeg_roundtrip(image, self.quality, context.channel_order)
