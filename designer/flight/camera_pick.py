"""The camera of a flown survey, from its photos' metadata.

Rule (decision): a photo's EXIF Model that one of the presets
(:mod:`designer.project.camera_presets`) lists, with the preset's focal length (within
1 %) and image size (either way round), names that preset. Its geometry is used — the
base project's own camera when that has the same geometry (so its calibration is kept),
else the preset as a new camera. Without such a preset the base project's camera is
used when the metadata's focal length and image size (those it states) fit it. Anything
else is an unknown camera: an error naming what the metadata says. Sources without
camera metadata (geo.txt, CSV) use the base project's camera.
"""

from __future__ import annotations

from collections.abc import Sequence

from designer.errors import DesignerError
from designer.flight.photos import CameraInfo
from designer.project import model as m
from designer.project.camera_presets import PRESETS, CameraPreset, matching_preset

FOCAL_TOLERANCE = 0.01


def _fits(info: CameraInfo, focal_mm: float, width: int, height: int) -> bool:
    if info.focal_length_mm is not None and (
            abs(info.focal_length_mm - focal_mm) > FOCAL_TOLERANCE * focal_mm):
        return False
    if info.image_width_px is not None and info.image_height_px is not None:
        return {info.image_width_px, info.image_height_px} == {width, height}
    return True


def named_preset(info: CameraInfo) -> CameraPreset | None:
    """The preset the metadata names (model) and confirms (focal length, size)."""
    model = (info.model or "").strip().lower()
    for p in PRESETS:
        if model and model in (name.lower() for name in p.exif_models) and _fits(
                info, p.focal_length_mm, p.image_width_px, p.image_height_px):
            return p
    return None


def pick_camera(infos: Sequence[CameraInfo | None], base_camera: m.Camera) -> m.Camera:
    """The project camera for photos with this metadata (module docstring)."""
    known = [i for i in infos if i is not None]
    if not known:
        return base_camera
    distinct = sorted({i.describe() for i in known})
    if len(distinct) > 1:
        raise DesignerError(f"the photos come from several cameras ({'; '.join(distinct)}); "
                            "import each camera's photos separately")
    info = known[0]
    preset = named_preset(info)
    if preset is not None:
        same = matching_preset(base_camera)
        return base_camera if same is preset else preset.camera()
    if _fits(info, base_camera.focal_length_mm, base_camera.image_width_px,
             base_camera.image_height_px):
        return base_camera
    raise DesignerError(
        f"unknown camera: the photos say {info.describe()}, which matches no preset and not "
        f"the base project's camera '{base_camera.id}' ({base_camera.focal_length_mm:g} mm, "
        f"{base_camera.image_width_px} x {base_camera.image_height_px} px); put a camera with "
        "that focal length and image size into the base project")
