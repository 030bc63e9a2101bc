"""A flown photo as read from any source, before it is put into the project's frame."""

from __future__ import annotations

from dataclasses import dataclass

#: rotation conventions of :attr:`FlownPhoto.angles_deg`
GIMBAL_TRUE = "gimbal"  # DJI gimbal yaw (true north), pitch (−90 nadir), roll; NED ZYX
YPR_GRID = "ypr"  # ODM-style yaw (from the source CRS's north), pitch (0 nadir), roll
YPR_TRUE = "ypr-true"  # ODM geo.txt: yaw from TRUE north (ODM's compute_opk), pitch, roll
OPK_GRID = "opk"  # ω φ κ in the source CRS's grid (designer's definition)


@dataclass(frozen=True)
class CameraInfo:
    """What a photo's metadata says of its camera (None where it says nothing)."""

    make: str | None = None
    model: str | None = None
    focal_length_mm: float | None = None
    image_width_px: int | None = None
    image_height_px: int | None = None

    def describe(self) -> str:
        parts = [" ".join(p for p in (self.make, self.model) if p) or "unnamed camera"]
        if self.focal_length_mm is not None:
            parts.append(f"{self.focal_length_mm:g} mm")
        if self.image_width_px is not None:
            parts.append(f"{self.image_width_px} x {self.image_height_px} px")
        return ", ".join(parts)


@dataclass(frozen=True)
class FlownPhoto:
    """One photo: ``x, y`` in ``crs`` (lon, lat for a geographic CRS), its absolute
    height ``z_m`` and/or height above the take-off point, and its attitude as
    ``(convention, a, b, c)`` degrees; ``where`` names the file (and line) it came from."""

    name: str
    where: str
    crs: str
    x: float
    y: float
    z_m: float | None
    relative_altitude_m: float | None
    angles_deg: tuple[str, float, float, float] | None
    camera: CameraInfo | None = None
