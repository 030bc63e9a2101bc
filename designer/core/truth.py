"""Ground truth of a virtual survey as plain value types: camera poses, GCPs, GCP image points.

The bottom layer (numpy and designer.core only): survey, evaluate, sfm, render and the
exporters all use these types; nothing here knows a file format.

Conventions (designer's own, docs/conventions.md; every exporter converts
from these at its boundary):

* world frame: X = Easting, Y = Northing, Z = height, metres, float64 (UTM-sized
  values are fine: nothing here goes through float32);
* ``R_cam_to_world`` maps photogrammetric camera axes (x = image right, y = image
  top, z = backwards; the camera looks along −z) to world: X = C + R · x_cam;
* pixel coordinates ``uv_px`` are continuous with the origin at the top-left
  CORNER of the top-left pixel, u right, v down; pixel (i, j) has its centre at
  (i + 0.5, j + 0.5) — COLMAP's convention;
* GCP sigmas are one standard deviation per axis (E, N, H) in metres.

The dataclasses copy their arrays into read-only float64 arrays, so an instance
never changes after construction.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass

import numpy as np

from designer.core.interior import InteriorOrientation
from designer.core.projection import project_points
from designer.core.rotation import is_rotation_matrix
from designer.errors import InvalidDataError

#: the roles a ground control point can play in an accuracy experiment
GCP_ROLES = ("control", "check")


#: characters no identifier may contain: the exchange formats split on whitespace
#: (COLMAP, ODM) or commas (CSV), quotes would need escaping some readers do not undo,
#: and '#' starts a comment in readers that strip comments anywhere on a line
_FORBIDDEN = set(',"\'#')


def check_name(name: object, what: str) -> str:
    """An image name or GCP id as a non-empty string without whitespace, commas, quotes
    or '#'."""
    if not isinstance(name, str) or not name:
        raise InvalidDataError(f"{what} {name!r} must be a non-empty string")
    bad = sorted({c for c in name if c.isspace() or c in _FORBIDDEN})
    if bad:
        raise InvalidDataError(
            f"{what} {name!r} contains {', '.join(repr(c) for c in bad)}; COLMAP and "
            f"OpenDroneMap split lines on whitespace, CSV on commas, and '#' starts a "
            f"comment: rename it"
        )
    return name


def check_unique(names: Iterable[str], what: str) -> None:
    """Raise InvalidDataError naming the first repeated name."""
    seen: set[str] = set()
    for n in names:
        if n in seen:
            raise InvalidDataError(f"{what} {n!r} occurs more than once; names must be unique")
        seen.add(n)


def _frozen_array(value, shape: tuple[int, ...], what: str) -> np.ndarray:
    arr = np.array(value, dtype=np.float64)  # a copy: the caller's array stays theirs
    if arr.shape != shape:
        raise InvalidDataError(f"{what} must have shape {shape}, got {arr.shape}")
    if not np.isfinite(arr).all():
        raise InvalidDataError(f"{what} must be finite, got {arr.tolist()}")
    arr.flags.writeable = False
    return arr


@dataclass(frozen=True, eq=False)
class CameraPose:
    """Exterior orientation of one image.

    Attributes:
        image_name: file name of the image (no whitespace, commas or quotes).
        C_world: perspective centre (3,), world metres.
        R_cam_to_world: (3, 3) rotation, photogrammetric camera axes → world.
    """

    image_name: str
    C_world: np.ndarray
    R_cam_to_world: np.ndarray

    def __post_init__(self) -> None:
        check_name(self.image_name, "image name")
        object.__setattr__(self, "C_world", _frozen_array(self.C_world, (3,), "C_world"))
        R = _frozen_array(self.R_cam_to_world, (3, 3), "R_cam_to_world")
        if not is_rotation_matrix(R):
            raise InvalidDataError(
                f"R_cam_to_world of {self.image_name!r} is not a rotation matrix "
                "(orthonormal, det +1, to 1e-9)"
            )
        object.__setattr__(self, "R_cam_to_world", R)


@dataclass(frozen=True)
class ImageTime:
    """When an image is taken on the flight's time line, and the sun it is lit by.

    Attributes:
        image_name: file name of the image.
        time_s: seconds after take-off (the time line's first photo is at 0).
        time_utc: the same moment, ISO 8601 UTC text ('2026-06-21T09:30:04.250000Z').
        sun_azimuth_deg: the sun's direction, degrees clockwise from grid north.
        sun_elevation_deg: the sun's angle above the horizon, degrees.
    """

    image_name: str
    time_s: float
    time_utc: str
    sun_azimuth_deg: float
    sun_elevation_deg: float

    def __post_init__(self) -> None:
        check_name(self.image_name, "image name")


@dataclass(frozen=True, eq=False)
class GroundControlPoint:
    """A ground control or check point.

    Attributes:
        gcp_id: its label (no whitespace, commas or quotes).
        role: "control" (used to georeference) or "check" (held back to measure error).
        true_xyz: the point's exact position (3,), world metres — what the images show.
        surveyed_xyz: the position as a survey reports it (3,), world metres — what the
            SfM software is given.
        sigma_xyz: survey standard deviation per axis (3,), metres, >= 0.
    """

    gcp_id: str
    role: str
    true_xyz: np.ndarray
    surveyed_xyz: np.ndarray
    sigma_xyz: np.ndarray

    def __post_init__(self) -> None:
        check_name(self.gcp_id, "GCP id")
        if self.role not in GCP_ROLES:
            raise InvalidDataError(
                f"GCP {self.gcp_id!r} has role {self.role!r}; use one of {', '.join(GCP_ROLES)}"
            )
        for name in ("true_xyz", "surveyed_xyz", "sigma_xyz"):
            object.__setattr__(self, name, _frozen_array(getattr(self, name), (3,), name))
        if (self.sigma_xyz < 0).any():
            raise InvalidDataError(f"GCP {self.gcp_id!r}: sigma_xyz must be >= 0 m")


@dataclass(frozen=True, eq=False)
class GcpObservation:
    """Where a GCP's TRUE position appears in one image.

    Attributes:
        gcp_id: the GCP's id.
        image_name: the image's file name.
        uv_px: (2,) pixel coordinates, designer's convention (origin at the top-left
            corner of the top-left pixel, u right, v down).
    """

    gcp_id: str
    image_name: str
    uv_px: np.ndarray

    def __post_init__(self) -> None:
        check_name(self.gcp_id, "GCP id")
        check_name(self.image_name, "image name")
        object.__setattr__(self, "uv_px", _frozen_array(self.uv_px, (2,), "uv_px"))


def observe_gcps(
    gcps: Sequence[GroundControlPoint],
    poses: Sequence[CameraPose],
    interior: InteriorOrientation,
    visible_fn: Callable[[int, int], bool] | None = None,
) -> list[GcpObservation]:
    """Project every GCP's TRUE position into every image; keep those inside the image.

    A GCP is kept in an image when it is in front of the camera (within the lens
    model's field), projects inside [0, W) × [0, H), and — if ``visible_fn`` is given —
    ``visible_fn(gcp_index, pose_index)`` is true (occlusion is decided elsewhere).
    Returns observations ordered by GCP, then by image, in the input orders.
    """
    check_unique((g.gcp_id for g in gcps), "GCP id")
    check_unique((p.image_name for p in poses), "image name")
    if not gcps or not poses:
        return []
    points = np.stack([g.true_xyz for g in gcps])
    C = np.stack([p.C_world for p in poses])
    R = np.stack([p.R_cam_to_world for p in poses])
    proj = project_points(points, C, R, interior)
    out: list[GcpObservation] = []
    for i, gcp in enumerate(gcps):
        for m, pose in enumerate(poses):
            if not proj.in_image[m, i]:
                continue
            if visible_fn is not None and not visible_fn(i, m):
                continue
            out.append(GcpObservation(gcp.gcp_id, pose.image_name, proj.uv_px[m, i]))
    return out


@dataclass(frozen=True, eq=False)
class CameraSet:
    """Several physical cameras in one survey (a multi-camera rig).

    Attributes:
        interiors: camera id → its interior orientation, in the order the exporters
            number the cameras (COLMAP CAMERA_ID 1, 2, …).
        image_camera: image name → the id of the camera that took it.
    """

    interiors: dict[str, InteriorOrientation]
    image_camera: dict[str, str]

    def __post_init__(self) -> None:
        object.__setattr__(self, "interiors", dict(self.interiors))
        object.__setattr__(self, "image_camera", dict(self.image_camera))
        if not self.interiors:
            raise InvalidDataError("a camera set needs at least one camera")
        for camera_id in self.interiors:
            check_name(camera_id, "camera id")
        unknown = sorted(set(self.image_camera.values()) - set(self.interiors))
        if unknown:
            raise InvalidDataError(f"images refer to unknown camera(s) {unknown}")

    def interior_of(self, image_name: str) -> InteriorOrientation:
        """The interior orientation of the camera that took ``image_name``."""
        try:
            return self.interiors[self.image_camera[image_name]]
        except KeyError:
            raise InvalidDataError(f"image {image_name!r} has no camera in the set") from None

    def camera_of(self, image_name: str) -> str:
        return self.image_camera[image_name]

    def covers(self, image_names: Iterable[str]) -> None:
        """Raise InvalidDataError naming the first image without a camera."""
        missing = next((n for n in image_names if n not in self.image_camera), None)
        if missing is not None:
            raise InvalidDataError(f"image {missing!r} has no camera in the camera set")
