"""Where a frame's render time goes: the stages the worker times for every image.

The worker (:mod:`designer.render.worker`) reports each frame's stages in seconds; the
manifest stores them per image (``images.NAME.stages``) and ``designer bench render``
prints their means. Stages that did not run for a frame are absent from its record.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping

#: stage key → what it measures, in the order a frame runs through them
FRAME_STAGES: dict[str, str] = {
    "setup_s": "frame set-up (camera, light step, plants, moving objects)",
    "cycles_s": "Cycles render (path tracing in Blender)",
    "cycles_cpu_s": "CPU-seconds of the Cycles render (all its threads)",
    "void_s": "the void map read (share of the image that sees no object)",
    "blender_write_s": "Blender writes the raw image file",
    "decode_s": "the raw image decoded for the effects",
    "distortion_s": "lens distortion resample (with vignetting when fused)",
    "effects_s": "the other camera effects (sensor, blur, …)",
    "encode_s": "the final image encoded and written",
    "exif_s": "EXIF time written",
    "effects_total_s": "everything after Blender's write, until the image is in place",
}

#: the columns ``designer bench render`` prints (short names)
STAGE_COLUMNS: dict[str, str] = {
    "setup_s": "set-up",
    "cycles_s": "Cycles",
    "blender_write_s": "write",
    "decode_s": "decode",
    "distortion_s": "distort",
    "effects_s": "effects",
    "encode_s": "encode",
}


def mean_stages(records: Iterable[Mapping[str, float]]) -> dict[str, float]:
    """Mean seconds per image of each stage over ``records`` (a stage missing from a
    record counts as 0 s for it)."""
    records = [r for r in records if r]
    if not records:
        return {}
    keys = [k for k in FRAME_STAGES if any(k in r for r in records)]
    return {k: sum(float(r.get(k, 0.0)) for r in records) / len(records) for k in keys}


def round_stages(stages: Mapping[str, float]) -> dict[str, float]:
    """The stages as the manifest stores them (ms resolution)."""
    return {k: round(float(v), 4) for k, v in stages.items()}
