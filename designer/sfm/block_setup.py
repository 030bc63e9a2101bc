"""The set-up both final bundle adjustments share (designer.sfm.adjustment, COLMAP's
Ceres problem, and designer.sfm.rolling_adjustment, the vectorised rolling-shutter
solver): which images take part and through which pose, which camera parameters are
estimated, the camera-position priors and the gauge.

* A rig's images share their station's pose (a COLMAP frame's ``rig_from_world``) and
  project through their mount's fixed ``cam_from_rig`` (designer.sfm.rigs); any other
  image is the reference sensor of its own trivial rig (no ``cam_from_rig``).
* A station has one pose, so one GNSS/RTK position prior: its first image's by name.
* Without a datum (no control, no priors) the gauge is the first station's pose and the
  second station's largest translation component (the scale), as COLMAP's two-camera
  gauge.

Everything is in the local frame (world − offset, m, float64).
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class PosedImage:
    """An image in the adjustment: its ids, and its mount on the station's rig
    (``cam_from_rig``, a pycolmap.Rigid3d; None for the rig's reference camera)."""

    name: str
    image_id: int
    frame_id: int
    camera_id: int
    cam_from_rig: object | None


def posed_images(rec) -> dict[str, PosedImage]:
    """Every image of ``rec`` with a pose, by name, in the reconstruction's order."""
    import pycolmap

    out = {}
    for image in rec.images.values():
        if not image.has_pose:
            continue
        frame = rec.frames[image.frame_id]
        rig = rec.rigs[frame.rig_id]
        sensor = pycolmap.sensor_t(pycolmap.SensorType.CAMERA, image.camera_id)
        mount = None if rig.is_ref_sensor(sensor) else rig.sensor_from_rig(sensor)
        out[image.name] = PosedImage(image.name, image.image_id, image.frame_id,
                                     image.camera_id, mount)
    return out


def constant_params(variable: Iterable[int], n_params: int) -> list[int]:
    """Indices of a camera's ``n_params`` parameters held constant when the FULL_OPENCV
    indices ``variable`` are estimated (indices past a shorter model's end are ignored)."""
    variable = set(variable)
    return [i for i in range(n_params) if i not in variable]


def prior_sigmas_m(priors) -> np.ndarray:
    """σ (m) of a camera-position prior along X, Y, Z (horizontal, horizontal, vertical)."""
    return np.array([priors.sigma_h_m, priors.sigma_h_m, priors.sigma_v_m], float)


def station_priors(priors, frame_of: Callable[[str], int | None]) -> list[tuple[int, np.ndarray]]:
    """(frame id, measured centre, local m) of each station in the adjustment, one per
    station: its first image's by name. ``frame_of(name)``: the image's frame id, None
    for an image not in the adjustment."""
    out, posed = [], set()
    for name, C in sorted(priors.C_local.items()):
        f = frame_of(name)
        if f is not None and f not in posed:
            posed.add(f)
            out.append((f, np.asarray(C, float)))
    return out


def reprojection_cost(camera, cov_uv: np.ndarray, uv: np.ndarray, image: PosedImage):
    """COLMAP's reprojection cost of a mark ``uv`` (px, covariance px²) in ``image``: on
    the station's pose through the mount, or on the image's own pose."""
    from pycolmap import cost_functions as cf

    if image.cam_from_rig is not None:
        return cf.RigReprojErrorCost(camera.model, cov_uv, uv, image.cam_from_rig)
    return cf.ReprojErrorCost(camera.model, cov_uv, uv)


def two_station_gauge(frames: list[int], t: Callable[[int], np.ndarray]
                      ) -> tuple[int, int | None, int | None]:
    """(first station, second station, the second's held translation component) of the
    gauge without a datum; ``frames`` in the adjustment's order, ``t(f)`` a station's
    rig_from_world translation. (first, None, None) with one station."""
    first = frames[0]
    if len(frames) < 2:
        return first, None, None
    second = frames[1]
    return first, second, int(np.argmax(np.abs(t(second) - t(first))))
