"""Lens distortion as a post-process: render a pinhole image, then warp it through the lens.

Blender renders an ideal pinhole camera. For a camera with distortion, designer renders
an enlarged pinhole camera with the same focal length in pixels whose image covers every
ray the distorted camera sees, then resamples it: output pixel (sample) centre
→ distorted normalised coordinates → exact inverse (to 1e-6 px) → undistorted
normalised coordinates → pixel of the pinhole render. The map is the same for every
frame of a camera, so it is computed once (``DistortionWarp``) and can be cached on
disk (``save`` / ``load``).

The render's extent is the bounding box of the undistorted positions of every output
sample (the warp needs them all anyway, so this is exact even where tangential terms put
an extreme inside an edge) plus the resampler's reach plus a 2 px margin. For a fisheye
the rays through the image border are checked first, so a field too wide for a pinhole
fails at once with an explanation. The render's principal point is moved by under a
pixel so that its pixel grid coincides with the output's at the principal point.

Accuracy (tests/effects/test_distortion_render.py, 800 × 600 px): forward check ≤ 1e-6 px
(the inverse's tolerance); checkerboard corners in the warped image against
cv2.projectPoints / cv2.fisheye.projectPoints: |mean| ≤ 0.011 px, RMS 0.068–0.073 px for
k1 = −0.3, k1 = +0.2, p1/p2 and a 149° fisheye; cornerSubPix on an image area-sampled
directly through the lens model gives 0.036–0.079 px RMS, so that is the detector.
Cost at 20 MP (5472 × 3648, k1 = −0.3, k2 = 0.1): building the warp 15 s and 320 MB of
maps (cache it), the render 7072 × 4718 px; applying it: `designer bench effects`.

Frames and units: normalised coordinates are CV-frame (x/z, y/z); pixel coordinates are
continuous with the origin at the top-left corner of the top-left pixel
(docs/conventions.md); a pixel's centre is (i + 0.5, j + 0.5).

Limits: a pinhole image cannot hold rays 90° or more off axis, and its size grows with
tan θ, so fisheye cameras are rendered this way up to a 150° field (``max_field_deg``).
Where the pinhole render is much denser than the output (fisheye edges, strong barrel
corners) the warp samples it at points: scene detail finer than an output pixel can
alias there; ``oversample`` > 1 renders finer and averages oversample² samples per
output pixel.
"""

from __future__ import annotations

import json
import math
import os
from dataclasses import dataclass, fields, replace
from typing import ClassVar

import numpy as np

from designer.atomic import atomic_path
from designer.core.distortion import BrownConrady, FisheyeEquidistant
from designer.core.interior import UNDISTORT_TOL_PX, InteriorOrientation
from designer.effects.base import Effect, FrameContext
from designer.effects.resample import SUPPORT_PX, check_order, warp_image
from designer.errors import DesignerError, NotInvertibleError, ParameterValueError

#: safety margin (render px) around the region the warp samples, beyond the kernel's reach
MARGIN_PX = 2.0
#: widest fisheye field (full angle, degrees) rendered through a pinhole camera
MAX_FISHEYE_FIELD_DEG = 150.0
#: the warp is rejected if its forward check is worse than this (px)
MAX_MAPPING_ERROR_PX = 1e-3
_FORMAT = "designer-distortion-warp-1"
_ROWS_PER_CHUNK = 64


def pinhole_render_camera(
    interior: InteriorOrientation,
    oversample: int = 1,
    *,
    order: int = 3,
    margin_px: float = MARGIN_PX,
    max_field_deg: float = MAX_FISHEYE_FIELD_DEG,
) -> tuple[InteriorOrientation, DistortionWarp | None]:
    """The pinhole camera to render for ``interior`` and the warp from it to ``interior``.

    Without distortion (or with all-zero Brown–Conrady coefficients) returns
    ``(interior without distortion, None)``: nothing to pay. Otherwise the render camera
    has the focal length in pixels of ``interior`` × ``oversample`` (the same pixel
    aspect), no distortion, and an image just large enough to hold every position the
    warp samples plus the interpolation kernel's reach (``order``: 1 bilinear, 3 cubic)
    plus ``margin_px`` render pixels, with the principal point placed accordingly
    (principal point offset x0 = (cx − W/2)·pitch_x, y0 = (H/2 − cy)·pitch_y mm,
    sensor W·pitch × H·pitch mm, pitch = f / f_px).
    ``oversample`` > 1 renders that much finer and averages oversample² samples per
    output pixel: 4× the render cost, and the corner bias drops to ≤ 0.002 px.

    Raises NotInvertibleError naming how many output pixels have no unique undistorted
    position (the lens map folds over), and DesignerError for a fisheye field wider than
    ``max_field_deg``.
    """
    if isinstance(oversample, bool) or not isinstance(oversample, int) or oversample < 1:
        raise ParameterValueError(f"oversample = {oversample!r} must be a whole number >= 1",
                                  name="oversample", value=oversample,
                                  must="a whole number, at least 1")
    check_order(order)
    lens = interior.distortion
    if lens is None or (isinstance(lens, BrownConrady) and lens.is_identity):
        return _without_distortion(interior), None
    if isinstance(lens, FisheyeEquidistant):
        _check_fisheye_field(interior, oversample, max_field_deg)
    map_u, map_v = _undistorted_samples(interior, oversample)
    pad = margin_px + SUPPORT_PX[order]
    render = _render_camera(interior, oversample, pad, (map_u.min(), map_u.max()),
                            (map_v.min(), map_v.max()))
    # normalised → render pixels, in place (the maps are large)
    map_u *= render.fx_px
    map_u += render.cx_px
    map_v *= render.fy_px
    map_v += render.cy_px
    error = _mapping_error_px(interior, render, oversample, map_u, map_v)
    if not error <= MAX_MAPPING_ERROR_PX:
        raise ArithmeticError(f"distortion warp misses by {error:.3g} px (bug)")
    warp = DistortionWarp(map_u, map_v, render, oversample, order, error,
                          _interior_key(interior))
    return render, warp


def _without_distortion(interior: InteriorOrientation) -> InteriorOrientation:
    return interior if interior.distortion is None else replace(interior, distortion=None)


def _sample_positions(n_px: int, oversample: int) -> np.ndarray:
    """Continuous coordinates of the sample centres along one axis: (s + 0.5) / oversample."""
    return (np.arange(n_px * oversample, dtype=np.float64) + 0.5) / oversample


def _outline(interior: InteriorOrientation, oversample: int, step: float = 0.5) -> np.ndarray:
    """(N, 2) points along the outline of the sample grid, at most ``step`` px apart."""
    W, H = interior.image_size_px
    lo = 0.5 / oversample
    us = np.linspace(lo, W - lo, math.ceil(W / step) + 1)
    vs = np.linspace(lo, H - lo, math.ceil(H / step) + 1)
    def row(v):
        return np.column_stack([us, np.full_like(us, v)])

    def col(u):
        return np.column_stack([np.full_like(vs, u), vs])

    return np.concatenate([row(lo), row(H - lo), col(lo), col(W - lo)])


def _normalised(interior: InteriorOrientation, uv: np.ndarray) -> np.ndarray:
    return (uv - [interior.cx_px, interior.cy_px]) / [interior.fx_px, interior.fy_px]


def _tol(interior: InteriorOrientation) -> float:
    return UNDISTORT_TOL_PX / max(interior.fx_px, interior.fy_px)


def _check_fisheye_field(interior: InteriorOrientation, oversample: int, max_field_deg: float
                         ) -> None:
    """Raise if the rays through the image border are too far off axis for a pinhole."""
    xy = _normalised(interior, _outline(interior, oversample))
    try:
        rays = interior.distortion.rays_from_distorted(xy, tol=_tol(interior))
    except NotInvertibleError:
        return  # the full pass counts the pixels that fail and says why
    theta = np.degrees(np.arccos(np.clip(rays[:, 2], -1.0, 1.0)))
    field = 2.0 * float(theta.max())
    if field > max_field_deg:
        i = int(np.argmax(theta))
        raise DesignerError(
            f"the fisheye camera sees {theta[i]:.1f}° off axis at the image border (a "
            f"{field:.1f}° field), but designer renders distortion through a pinhole camera, "
            f"whose image size grows with tan θ and is infinite at 90° (a 180° field): "
            f"fields up to {max_field_deg:g}° are supported (a pinhole image "
            f"{math.tan(math.radians(max_field_deg / 2)) / math.radians(max_field_deg / 2):.1f}"
            f"× the fisheye's radius); use a longer focal length, a smaller sensor or "
            f"image, or a principal point nearer the centre"
        )


def _undistorted_samples(interior: InteriorOrientation, oversample: int
                         ) -> tuple[np.ndarray, np.ndarray]:
    """Undistorted normalised (x, y) of every sample centre, each (H·os, W·os) float64.

    Raises NotInvertibleError naming the number of output pixels without an inverse.
    """
    W, H = interior.image_size_px
    us, vs = _sample_positions(W, oversample), _sample_positions(H, oversample)
    map_x = np.empty((len(vs), len(us)))
    map_y = np.empty_like(map_x)
    bad_pixels: list[np.ndarray] = []  # flat output pixel indices without an inverse
    tol = _tol(interior)
    for start in range(0, len(vs), _ROWS_PER_CHUNK):
        rows = vs[start:start + _ROWS_PER_CHUNK]
        uv = np.column_stack([np.tile(us, len(rows)), np.repeat(rows, len(us))])
        xy, ok = interior.distortion.undistort_with_status(_normalised(interior, uv), tol=tol)
        map_x[start:start + len(rows)] = xy[:, 0].reshape(len(rows), -1)
        map_y[start:start + len(rows)] = xy[:, 1].reshape(len(rows), -1)
        if not ok.all():
            col, row = np.floor(uv[~ok]).astype(np.int64).T
            bad_pixels.append(np.unique(row * W + col))
    if bad_pixels:
        bad = np.unique(np.concatenate(bad_pixels))
        first = (int(bad[0] % W), int(bad[0] // W))
        raise NotInvertibleError(
            f"{bad.size} of {W * H} output pixels have no unique undistorted position "
            f"with {interior.distortion!r} (the lens map folds over or leaves the model's "
            f"range), the first at pixel ({first[0]}, {first[1]}); reduce the distortion "
            f"coefficients or the image size/field of view"
        )
    return map_x, map_y


def _render_camera(interior: InteriorOrientation, oversample: int, pad: float,
                   x_range: tuple[float, float], y_range: tuple[float, float]
                   ) -> InteriorOrientation:
    """Pinhole camera with fx, fy = interior's × oversample covering the normalised box
    x_range × y_range plus at least ``pad`` render pixels on every side.

    The principal point is shifted by less than a pixel so that near it the render's pixel
    centres fall exactly on output sample centres (c_render − oversample · c_output is a
    whole number): where distortion is small the warp then samples at whole pixels, and
    the interpolation neither blurs nor biases edges there.
    """
    fx, fy = interior.fx_px * oversample, interior.fy_px * oversample
    size, centre = [], []
    for f, c_out, (lo, hi) in ((fx, interior.cx_px, x_range), (fy, interior.cy_px, y_range)):
        first = pad - f * lo  # the principal point that puts the box's low edge at pad
        c = first + (oversample * c_out - first) % 1.0
        size.append(math.ceil(c + f * hi + pad - 1e-9))
        centre.append(c)
    (W, H), (cx, cy) = size, centre
    pitch_x, pitch_y = interior.focal_length_mm / fx, interior.focal_length_mm / fy
    return InteriorOrientation(
        focal_length_mm=interior.focal_length_mm,
        sensor_width_mm=W * pitch_x,
        sensor_height_mm=H * pitch_y,
        image_width_px=W,
        image_height_px=H,
        principal_point_x_mm=(cx - W / 2) * pitch_x,
        principal_point_y_mm=(H / 2 - cy) * pitch_y,
        pixel_aspect=interior.pixel_aspect,
    )


def _mapping_error_px(interior, render, oversample, map_u, map_v) -> float:
    """Largest distance (output px) between a sample centre and its map position projected
    back through the lens: the warp's forward check."""
    us = _sample_positions(interior.image_size_px[0], oversample)
    vs = _sample_positions(interior.image_size_px[1], oversample)
    worst = 0.0
    for start in range(0, len(vs), _ROWS_PER_CHUNK):
        sl = slice(start, start + _ROWS_PER_CHUNK)
        xy = np.column_stack([((map_u[sl] - render.cx_px) / render.fx_px).ravel(),
                              ((map_v[sl] - render.cy_px) / render.fy_px).ravel()])
        xd = interior.distortion.distort(xy)
        du = xd[:, 0] * interior.fx_px + interior.cx_px - np.tile(us, len(vs[sl]))
        dv = xd[:, 1] * interior.fy_px + interior.cy_px - np.repeat(vs[sl], len(us))
        worst = max(worst, float(np.sqrt(du * du + dv * dv).max()))
    return worst


# ------------------------------------------------------------------------------ the warp
@dataclass(frozen=True, eq=False)
class DistortionWarp:
    """Where every output sample lies in the pinhole render, for one camera.

    Attributes:
        map_u_px, map_v_px: (H·oversample, W·oversample) float64 continuous pixel
            coordinates in the pinhole render of the output sample centres
            ((s + 0.5) / oversample in output pixels).
        render_interior: the pinhole camera the render must use (no distortion).
        oversample: samples per output pixel along each axis (averaged by ``apply``).
        order: interpolation order, 1 (bilinear) or 3 (cubic B-spline).
        max_mapping_error_px: forward check: largest distance, output px, between a
            sample centre and its map position projected back through the lens.
        source_key: JSON description of the distorted camera the warp was made for.
    """

    map_u_px: np.ndarray
    map_v_px: np.ndarray
    render_interior: InteriorOrientation
    oversample: int
    order: int
    max_mapping_error_px: float
    source_key: str

    @property
    def output_size_px(self) -> tuple[int, int]:
        """(width, height) of the output image."""
        h, w = self.map_u_px.shape
        return (w // self.oversample, h // self.oversample)

    @property
    def render_size_px(self) -> tuple[int, int]:
        return self.render_interior.image_size_px

    def matches(self, interior: InteriorOrientation) -> bool:
        """True if this warp was made for ``interior`` (same camera and lens)."""
        return self.source_key == _interior_key(interior)

    def apply(self, image: np.ndarray, gain: np.ndarray | None = None) -> np.ndarray:
        """Pinhole render (H_r, W_r[, C]) → distorted output image (H, W[, C]).

        Float images give float32; uint8/uint16 are rounded and clipped back to their
        type. Resampling is linear in the values given: pass linear light. ``gain``
        (H, W) multiplies the output (a vignetting, in the same pass).
        """
        W_r, H_r = self.render_size_px
        if image.shape[:2] != (H_r, W_r):
            raise ValueError(f"the warp expects a {W_r} x {H_r} px render, got "
                             f"{image.shape[1]} x {image.shape[0]} px")
        out = warp_image(image, self.map_u_px, self.map_v_px, self.order, self.oversample,
                         gain=gain)
        if np.issubdtype(image.dtype, np.integer):
            info = np.iinfo(image.dtype)
            return np.clip(np.rint(out), info.min, info.max).astype(image.dtype)
        return out

    # ----------------------------------------------------------------------- caching
    def save(self, path: str | os.PathLike) -> None:
        """Write the warp to an .npz file (atomically)."""
        with atomic_path(path) as tmp, open(tmp, "wb") as f:
            np.savez(f, format=_FORMAT, map_u_px=self.map_u_px, map_v_px=self.map_v_px,
                     render_interior=_interior_key(self.render_interior),
                     oversample=self.oversample, order=self.order,
                     max_mapping_error_px=self.max_mapping_error_px,
                     source_key=self.source_key)

    @classmethod
    def load(cls, path: str | os.PathLike, interior: InteriorOrientation | None = None
             ) -> DistortionWarp:
        """Read a warp written by ``save``; with ``interior``, refuse one made for another
        camera (a stale cache) with a DesignerError."""
        with np.load(path, allow_pickle=False) as data:
            if str(data.get("format", "")) != _FORMAT:
                raise DesignerError(f"{os.fspath(path)} is not a designer distortion warp "
                                    f"({_FORMAT})")
            warp = cls(
                data["map_u_px"].astype(np.float64), data["map_v_px"].astype(np.float64),
                _interior_from_key(str(data["render_interior"])), int(data["oversample"]),
                int(data["order"]), float(data["max_mapping_error_px"]),
                str(data["source_key"]),
            )
        if interior is not None and not warp.matches(interior):
            raise DesignerError(f"the distortion warp in {os.fspath(path)} was made for "
                                f"another camera; delete it so it is computed again")
        return warp


@dataclass(frozen=True)
class LensDistortion(Effect):
    """The distortion warp as a chain effect: pinhole render → distorted image."""

    warp: DistortionWarp
    kind: ClassVar[str] = "distortion"

    def apply(self, image: np.ndarray, frame_index: int, context: FrameContext,
              gain: np.ndarray | None = None) -> np.ndarray:
        return self.warp.apply(image, gain)


# ------------------------------------------------------------------- interior ↔ JSON
_MODELS = {"brown_conrady": BrownConrady, "fisheye_equidistant": FisheyeEquidistant}


def _interior_key(interior: InteriorOrientation) -> str:
    d = {f.name: getattr(interior, f.name) for f in fields(interior)}
    d["distortion"] = None if interior.distortion is None else interior.distortion.to_dict()
    return json.dumps(d, sort_keys=True)


def _interior_from_key(key: str) -> InteriorOrientation:
    d = json.loads(key)
    lens = d.pop("distortion")
    if lens is not None:
        lens = _MODELS[lens.pop("model")](**lens)
    return InteriorOrientation(**d, distortion=lens)

