"""The effect chain: the effects a project asks for, in physical order, applied per frame.

Order (``designer.effects.base.EFFECT_ORDER``): optics (motion blur on the pinhole
render, distortion warp, vignetting, defocus, Gaussian blur) → sensor (shot noise, dark
current, read noise, ADC; then DN noise) → camera (JPEG). Effects that change nothing
(σ = 0, fall-off 0, …) are dropped, so a chain of them is empty.

Images are uint8 or uint16, (H, W) or (H, W, 3), sRGB-encoded as Blender writes them,
channels in OpenCV's B, G, R order unless ``FrameContext.channel_order`` says "RGB".
The chain decodes to float32 linear light for the physical effects, encodes back to
sRGB (still float) for DN noise, and rounds to the input's type once at the end (or
before JPEG). Passes are fused where the numbers stay the same: vignetting runs in the
sensor's pass when the sensor follows it, else in the warp's; the sensor and DN noise
write the next domain's values (sRGB-encoded, or the stored codes when nothing or JPEG
follows) in their own pass, the DN noise in the sensor's when it follows it. An empty
chain returns the image object
untouched, and ``process_file`` copies (or links, or moves) the file byte for byte
without decoding it.
"""

from __future__ import annotations

import os
import shutil
import time
from collections.abc import Iterable, Iterator
from pathlib import Path
from typing import Literal

import cv2
import numpy as np

from designer.atomic import atomic_path, write_bytes_atomic
from designer.effects.base import Domain, Effect, FrameContext
from designer.effects.distortion_render import DistortionWarp, LensDistortion
from designer.effects.jpeg import JpegCompression
from designer.effects.sensor import GaussianNoiseDN, SensorModel
from designer.effects.srgb import (
    decode_image,
    encode_image,
    linear_to_srgb,
    max_code,
    quantise,
    srgb_to_linear,
)
from designer.errors import DesignerError

_JPEG_SUFFIXES = {".jpg", ".jpeg"}
_SAME_FORMAT = {".jpeg": ".jpg", ".tiff": ".tif"}


class EffectChain:
    """An ordered, immutable sequence of effects (see the module docstring)."""

    def __init__(self, effects: Iterable[Effect] = ()) -> None:
        effects = list(effects)
        for e in effects:
            if not isinstance(e, Effect):
                raise TypeError(f"{e!r} is not an Effect")
        kept = [e for e in effects if not e.is_identity]
        self._effects = tuple(sorted(kept, key=lambda e: e.rank))  # stable: ties keep order

    @property
    def effects(self) -> tuple[Effect, ...]:
        return self._effects

    @property
    def kinds(self) -> tuple[str, ...]:
        """The effects' kinds in the order they run."""
        return tuple(e.kind for e in self._effects)

    @property
    def is_empty(self) -> bool:
        return not self._effects

    @property
    def warp(self) -> DistortionWarp | None:
        """The distortion warp, if any: the images given to ``apply`` must then be renders
        of ``warp.render_interior``."""
        for e in self._effects:
            if isinstance(e, LensDistortion):
                return e.warp
        return None

    def __iter__(self) -> Iterator[Effect]:
        return iter(self._effects)

    def __len__(self) -> int:
        return len(self._effects)

    def __repr__(self) -> str:
        return f"EffectChain({', '.join(self.kinds) or 'empty'})"

    # ----------------------------------------------------------------------- apply
    def apply(self, image: np.ndarray, frame_index: int, context: FrameContext | None = None
              ) -> np.ndarray:
        """Run every effect on ``image`` (uint8/uint16, sRGB) → an image of the same type."""
        return self._run(image, frame_index, context or FrameContext(), self._effects)

    def encode(self, image: np.ndarray, frame_index: int, suffix: str,
               context: FrameContext | None = None,
               timings: dict[str, float] | None = None) -> bytes:
        """Run the chain and return the bytes of an image file of type ``suffix``.

        '.jpg' needs a JPEG effect, which must be the last effect: its own compressed
        bytes are returned (never decoded and compressed again). '.png' and '.tif' are
        written losslessly. ``timings`` (see :func:`process_file`) gets the seconds of the
        lens warp, the other effects and the encoding added to it.
        """
        context = context or FrameContext()
        suffix = suffix.lower()
        if suffix in _JPEG_SUFFIXES:
            last = self._effects[-1] if self._effects else None
            if not isinstance(last, JpegCompression):
                raise DesignerError("writing .jpg images needs a JPEG effect (with its quality)")
            before = self._run(image, frame_index, context, self._effects[:-1], timings)
            t0 = time.perf_counter()
            data = last.encode(before, context)
            if timings is not None:
                _add(timings, "encode_s", time.perf_counter() - t0)
            return data
        out = self._run(image, frame_index, context, self._effects, timings)
        t0 = time.perf_counter()
        ok, buf = cv2.imencode(suffix, out)
        if not ok:
            raise DesignerError(f"OpenCV cannot write {out.dtype} images as {suffix}")
        if timings is not None:
            _add(timings, "encode_s", time.perf_counter() - t0)
        return buf.tobytes()

    @staticmethod
    def _run(image: np.ndarray, frame_index: int, context: FrameContext,
             effects: tuple[Effect, ...], timings: dict[str, float] | None = None
             ) -> np.ndarray:
        if not effects:
            return image
        t_start = time.perf_counter()
        warp_s = 0.0
        _check_image(image)
        dtype = image.dtype
        current, domain = image, "integer"
        k = 0
        while k < len(effects):
            effect = effects[k]
            current = convert_domain(current, domain, effect.domain, dtype)
            domain = effect.domain
            following = _at(effects, k + 1)
            if (isinstance(effect, LensDistortion) and _is_vignetting(following)
                    and not isinstance(_at(effects, k + 2), SensorModel)):
                # the warp multiplies by the vignetting gain as it writes each pixel
                t_warp = time.perf_counter()
                current = effect.apply(current, frame_index, context, gain=following.gain)
                warp_s += time.perf_counter() - t_warp
                k += 2
                continue
            gain = None
            if _is_vignetting(effect) and isinstance(following, SensorModel):
                gain, k = effect.gain, k + 1  # the sensor multiplies by it in its pass
                effect, following = effects[k], _at(effects, k + 1)
            ends = following is None or following.domain == "integer"
            after = _at(effects, k + 2)
            if isinstance(effect, SensorModel) and ends:
                # the sensor writes the stored codes in its pass
                current = effect.apply(current, frame_index, context, gain=gain, codes=dtype)
                domain = "integer"
            elif (isinstance(effect, SensorModel) and isinstance(following, GaussianNoiseDN)
                  and (after is None or after.domain == "integer")):
                # … and the DN noise too
                current = effect.apply(current, frame_index, context, gain=gain, codes=dtype,
                                       dn_noise=following)
                domain = "integer"
                k += 1
            elif isinstance(effect, SensorModel) and following.domain == "encoded":
                current = effect.apply(current, frame_index, context, gain=gain, encoded=True)
                domain = "encoded"
            elif isinstance(effect, GaussianNoiseDN) and ends:
                current = effect.apply(current, frame_index, context, codes=dtype)
                domain = "integer"
            else:
                t_warp = time.perf_counter()
                current = effect.apply(current, frame_index, context,
                                       **({} if gain is None else {"gain": gain}))
                if isinstance(effect, LensDistortion):
                    warp_s += time.perf_counter() - t_warp
            k += 1
        out = convert_domain(current, domain, "integer", dtype)
        if timings is not None:
            _add(timings, "distortion_s", warp_s)
            _add(timings, "effects_s", time.perf_counter() - t_start - warp_s)
        return out


def _at(effects: tuple[Effect, ...], k: int) -> Effect | None:
    return effects[k] if k < len(effects) else None


def _is_vignetting(effect: Effect | None) -> bool:
    return effect is not None and effect.kind == "vignetting"


def _check_image(image: np.ndarray) -> None:
    max_code(image.dtype)  # uint8 / uint16 only
    if not (image.ndim == 2 or (image.ndim == 3 and image.shape[2] == 3)):
        raise ValueError(f"images must be (H, W) or (H, W, 3), got {image.shape}")


def convert_domain(image: np.ndarray, src: Domain, dst: Domain, dtype: np.dtype) -> np.ndarray:
    """Between integer codes, float sRGB-encoded values and float linear light."""
    if src == dst:
        return image
    if src == "integer":
        if dst == "linear":
            return decode_image(image)
        return image.astype(np.float32) / np.float32(max_code(dtype))
    if src == "linear":
        return linear_to_srgb(image) if dst == "encoded" else encode_image(image, dtype)
    # src == "encoded"
    if dst == "integer":
        return quantise(image, dtype)
    return srgb_to_linear(np.clip(image, 0.0, 1.0))


# ------------------------------------------------------------------------------ files
def process_file(
    src: str | os.PathLike,
    dst: str | os.PathLike,
    chain: EffectChain,
    frame_index: int = 0,
    context: FrameContext | None = None,
    *,
    passthrough: Literal["copy", "link", "move"] = "copy",
    timings: dict[str, float] | None = None,
) -> None:
    """Apply ``chain`` to the image file ``src`` and write ``dst`` atomically.

    With an empty chain the file is never decoded: its bytes are copied exactly
    (``passthrough="copy"``), hard-linked ("link") or renamed ("move"); ``dst`` must then
    have the same format as ``src``. Otherwise ``src`` is read with OpenCV (B, G, R
    order, bit depth kept) and ``dst``'s suffix picks the format (see
    ``EffectChain.encode``).

    ``timings``, when given, gets the seconds of each step added to it: ``decode_s``,
    ``distortion_s`` (the lens warp), ``effects_s`` (the other effects) and ``encode_s``
    (encoding and writing the file).
    """
    src, dst = Path(src), Path(dst)
    if chain.is_empty:
        _pass_through(src, dst, passthrough)
        return
    t0 = time.perf_counter()
    image = cv2.imread(os.fspath(src), cv2.IMREAD_UNCHANGED)
    if image is None:
        raise DesignerError(f"cannot read the image {src}")
    if image.ndim == 3 and image.shape[2] == 4:
        raise DesignerError(f"{src} has an alpha channel; render RGB images")
    if timings is not None:
        _add(timings, "decode_s", time.perf_counter() - t0)
    data = chain.encode(image, frame_index, dst.suffix, context, timings=timings)
    t1 = time.perf_counter()
    write_bytes_atomic(dst, data)
    if timings is not None:
        _add(timings, "encode_s", time.perf_counter() - t1)


def _add(timings: dict[str, float], key: str, seconds: float) -> None:
    timings[key] = timings.get(key, 0.0) + seconds


def _pass_through(src: Path, dst: Path, how: str) -> None:
    def fmt(p: Path) -> str:
        s = p.suffix.lower()
        return _SAME_FORMAT.get(s, s)

    if fmt(src) != fmt(dst):
        raise DesignerError(f"no effects to apply, but {src.name} and {dst.name} have different "
                            f"formats: converting would re-encode the image; keep the format")
    if not src.is_file():
        raise DesignerError(f"cannot read the image {src}")
    if src.resolve() == dst.resolve():
        return
    if how == "move":
        os.replace(src, dst)
        return
    with atomic_path(dst) as tmp:
        if how == "link":
            tmp.unlink()
            try:
                os.link(src, tmp)
            except OSError:  # another file system, or links not supported: copy
                shutil.copyfile(src, tmp)
        elif how == "copy":
            shutil.copyfile(src, tmp)
        else:
            raise ValueError(f"passthrough = {how!r} must be 'copy', 'link' or 'move'")
