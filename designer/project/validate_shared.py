"""Shared pieces of the semantic checks (``validate*.py``): the coordinate limit, element
names, number checks and formats (the scene's limits: ``designer.project.scene_limits``;
the checks beyond validation: :mod:`designer.checks`)."""

from __future__ import annotations

import math

from designer.project import model as m
from designer.project.problems import Issue

#: no coordinate or length in a project may exceed this (m); larger values are typos
MAX_ABS_COORDINATE_M = 1e8
BIT_DEPTHS = {"png": (8, 16), "jpeg": (8,), "tiff": (8, 16, 32), "exr": (16, 32)}
EXTENSIONS = {"png": (".png",), "jpeg": (".jpg", ".jpeg"), "tiff": (".tif", ".tiff"),
              "exr": (".exr",)}

TAGS = {
    m.Origin: "origin", m.Extent: "extent", m.FlatTerrain: "flat",
    m.ProceduralTerrain: "procedural", m.ProceduralTexture: "procedural",
    m.Texture: "tiling", m.TruePosition: "true", m.Target: "target",
    m.Sun: "sun", m.SunPosition: "sun-position", m.Lighting: "lighting",
    m.SunOverTime: "sun-over-time", m.TimeLine: "time-line", m.CloudShadows: "cloud-shadows",
    m.PoseNoise: "pose-noise", m.Vignetting: "vignetting", m.SensorNoise: "sensor-noise",
    m.Sensor: "sensor",
    m.Blur: "blur", m.MotionBlur: "motion-blur", m.Jpeg: "jpeg", m.Render: "render",
    m.BrownConradyDistortion: "brown-conrady",
    m.FisheyeEquidistantDistortion: "fisheye-equidistant",
}


def finite_issues(*objs: object) -> list[Issue]:
    """Non-finite or absurdly large floats in the direct fields of ``objs``."""
    out = []
    for obj in objs:
        for name, value in vars(obj).items():
            # whole numbers (seeds, counts) are finite; their ranges are checked elsewhere
            if isinstance(value, float) and not (
                    math.isfinite(value) and abs(value) <= MAX_ABS_COORDINATE_M):
                out.append(Issue(obj, TAGS.get(type(obj), "project"),
                                 f"{name.replace('_', '-')} = {value!r} is not a finite number "
                                 f"of at most {MAX_ABS_COORDINATE_M:g} in size; give a "
                                 "finite value", attr=name.replace("_", "-")))
    return out


def plain_number(value: float, decimals: int = 3) -> str:
    """A number as a user writes it: at most ``decimals`` places, without trailing zeros
    and never in exponent form (a UTM northing reads 5405950, not 5.40595e+06)."""
    text = f"{float(value):.{decimals}f}"
    if "." in text:
        text = text.rstrip("0").rstrip(".")
    return "0" if text in ("-0", "") else text


def plain_m(value: float) -> str:
    """A length or coordinate (m) to the mm, as :func:`plain_number` writes it."""
    return plain_number(value, 3)


def plain_extent(extent: m.Extent) -> str:
    """The terrain extent as a user reads it: ``X 511950..512050, Y 5405950..5406050``."""
    return (f"X {plain_m(extent.min_X)}..{plain_m(extent.max_X)}, "
            f"Y {plain_m(extent.min_Y)}..{plain_m(extent.max_Y)}")


def is_ok(value: float | None) -> bool:
    return value is not None and math.isfinite(value) and abs(value) <= MAX_ABS_COORDINATE_M


def file_issue(obj: object, tag: str, problem: str | None) -> list[Issue]:
    return [] if problem is None else [Issue(obj, tag, problem, attr="file")]
