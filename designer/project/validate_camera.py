"""Semantic checks of one camera: the interior orientation of docs/conventions.md.

The checks follow ``InteriorOrientation.problems()`` but point at the element at
fault (focal length, sensor, image size, principal point); the core object is built
only from a camera that passed them, through the one model → core boundary
(``designer.project.interiors.interior_from_camera``), and the lens model's
invertibility over the image is asked of ``designer.core.distortion``.
"""

from __future__ import annotations

import math

from designer.errors import DesignerError
from designer.project import model as m
from designer.project.declare import declared_field
from designer.project.problems import Issue
from designer.project.validate_declared import element_issues
from designer.project.validate_shared import finite_issues


def camera_issues(cam: m.Camera, resolution_scale: float = 1.0) -> list[Issue]:
    """Problems of ``cam``; ``resolution_scale`` is render/resolution-scale."""
    if element_issues(cam):
        return []  # a value out of its declared range (validate_declared names it)
    out: list[Issue] = []
    out += _pixel_shape(cam)
    if abs(cam.principal_point_x_mm) >= cam.sensor_width_mm / 2 or \
            abs(cam.principal_point_y_mm) >= cam.sensor_height_mm / 2:
        out.append(Issue(cam, "principal-point", f"the principal point ({cam.principal_point_x_mm}"
                         f", {cam.principal_point_y_mm}) mm lies outside the sensor "
                         f"({cam.sensor_width_mm} x {cam.sensor_height_mm} mm); it is an offset "
                         "from the sensor centre in mm, not a position in pixels", attr="x-mm"))
    out += _scaled_size(cam, resolution_scale)
    if out:
        return out
    return _core_model(cam)


def _pixel_shape(cam: m.Camera) -> list[Issue]:
    from designer.core.interior import SQUARE_PIXEL_RTOL  # numpy: loaded when checking

    pitch_x = cam.sensor_width_mm / cam.image_width_px
    pitch_y = cam.sensor_height_mm / cam.image_height_px
    if cam.pixel_aspect is None:
        if abs(pitch_y - pitch_x) > SQUARE_PIXEL_RTOL * pitch_x:
            return [Issue(cam, "sensor", (
                f"pixels are not square: sensor {cam.sensor_width_mm:g} x "
                f"{cam.sensor_height_mm:g} mm over {cam.image_width_px} x "
                f"{cam.image_height_px} px gives {pitch_x * 1000:.6g} x {pitch_y * 1000:.6g} µm "
                "pixels; make width-mm / width-px equal height-mm / height-px (e.g. sensor "
                f"height {cam.sensor_width_mm * cam.image_height_px / cam.image_width_px:.6g} "
                "mm), or state the pixel aspect"), attr="height-mm", code="pixels-not-square")]
        return []
    aspect = cam.pixel_aspect  # its range: validate_declared
    if abs(pitch_y / pitch_x - aspect) > SQUARE_PIXEL_RTOL * aspect:
        return [Issue(cam, "pixel-aspect", f"pixel aspect {aspect!r} disagrees with the sensor "
                      f"and image sizes, which give {pitch_y / pitch_x:.9g}; correct one of "
                      "them")]
    return []


def _scaled_size(cam: m.Camera, scale: float) -> list[Issue]:
    if not (isinstance(scale, int | float) and math.isfinite(scale) and 0 < scale <= 1):
        return []  # reported with the render settings
    out = []
    for name in ("image_width_px", "image_height_px"):
        attr, size = declared_field(m.Camera, name).xml, getattr(cam, name)
        scaled = size * scale
        if abs(scaled - round(scaled)) > 1e-6 or round(scaled) < 1:
            out.append(Issue(cam, "image", (
                f"{attr} {size} x resolution-scale {scale:g} = {scaled:g} px is not a whole "
                "number of pixels; choose a scale that divides the image size (e.g. 0.5 or "
                "0.25) so the rendered pixels keep the camera's geometry"), attr=attr,
                key="image", code="scale-not-whole", value=scale))
    return out


def _core_model(cam: m.Camera) -> list[Issue]:
    """Build the core interior orientation; report what it refuses and lens folds."""
    from designer.project.interiors import interior_from_camera

    d = cam.distortion
    tag = "brown-conrady" if isinstance(d, m.BrownConradyDistortion) else "fisheye-equidistant"
    issues = finite_issues(d) if d is not None else []
    if issues:
        return [Issue(cam, tag, i.message, attr=i.attr) for i in issues]
    try:
        io = interior_from_camera(cam)
        core_d = io.distortion
        problem = None if core_d is None else core_d.invertibility_problem(
            io.fx_px, io.fy_px, io.cx_px, io.cy_px, io.image_width_px, io.image_height_px)
    except DesignerError as error:
        return [Issue(cam, "camera", f"{error}", attr="id")]
    if problem:
        return [Issue(cam, tag, problem, code="lens-folds")]
    return []
