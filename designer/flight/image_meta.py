"""Positions and attitudes from image metadata (EXIF GPS, DJI XMP), read with pyexiv2.

Tags read (EXIF 2.32, CIPA DC-008, GPS attribute information; DJI "Photo File — XMP
Data List" in the Mavic 3E/3T and Zenmuse P1 user manuals):

* ``Exif.GPSInfo.GPSLatitude``/``GPSLongitude`` (three rationals: degrees, minutes,
  seconds) with ``…Ref`` N/S, E/W — WGS 84; ``GPSAltitude`` with ``GPSAltitudeRef``
  (1 = below sea level);
* ``Xmp.drone-dji.GimbalYawDegree``, ``GimbalPitchDegree``, ``GimbalRollDegree``:
  the camera's attitude in NED, rotation order ZYX, yaw from true north, pitch −90 =
  nadir (:mod:`designer.flight.gimbal`); the aircraft's ``FlightYawDegree`` etc. are not
  needed (the gimbal angles are absolute);
* ``Xmp.drone-dji.AbsoluteAltitude`` (preferred over GPSAltitude when present) and
  ``RelativeAltitude`` (above the take-off point);
* camera: ``Exif.Image.Make``, ``Exif.Image.Model``, ``Exif.Photo.FocalLength`` (mm),
  ``Exif.Photo.PixelXDimension``/``PixelYDimension`` (else the image's own size).

Height assumption: DJI calls AbsoluteAltitude "geodetic"; aircraft with RTK write
ellipsoidal heights, others a barometric height above mean sea level. The importer takes
it as the project's height plus an optional offset (``--height-offset-m``); with
``--altitude relative`` it uses RelativeAltitude + the take-off height instead.
"""

from __future__ import annotations

from pathlib import Path

from designer.flight.checks import fail
from designer.flight.photos import GIMBAL_TRUE, CameraInfo, FlownPhoto

DJI_NS = "http://www.dji.com/drone-dji/1.0/"
IMAGE_SUFFIXES = (".jpg", ".jpeg", ".tif", ".tiff", ".dng")


def _ratio(text: str, where: str, tag: str) -> float:
    try:
        num, _, den = text.partition("/")
        value = float(num) / float(den or 1)
    except (ValueError, ZeroDivisionError):
        raise fail(where, tag, f"{text!r} is not a rational", "rewrite the tag") from None
    return value


def _dms(text: str, ref: str | None, where: str, tag: str, negative: str) -> float:
    parts = text.split()
    if len(parts) != 3:
        raise fail(where, tag, f"{text!r} is not degrees minutes seconds",
                   "write three rationals")
    d, mnt, s = (_ratio(p, where, tag) for p in parts)
    value = d + mnt / 60.0 + s / 3600.0
    return -value if (ref or "").strip().upper() == negative else value


def _float(xmp: dict, key: str, where: str) -> float | None:
    text = xmp.get(f"Xmp.drone-dji.{key}")
    if text is None:
        return None
    try:
        return float(text)
    except ValueError:
        raise fail(where, f"drone-dji:{key}", f"{text!r} is not a number",
                   "write a decimal number") from None


def read_image(path: Path) -> FlownPhoto:
    """The GPS position, DJI gimbal attitude and camera of one image file."""
    import pyexiv2

    where = str(path)
    try:
        with pyexiv2.Image(str(path)) as image:
            exif = image.read_exif()
            xmp = image.read_xmp()
            size = (image.get_pixel_width(), image.get_pixel_height())
    except (OSError, RuntimeError) as error:
        raise fail(where, "", f"cannot read the image metadata ({error})",
                   "give JPEG/TIFF images with EXIF") from None
    g = "Exif.GPSInfo."
    if f"{g}GPSLatitude" not in exif or f"{g}GPSLongitude" not in exif:
        raise fail(where, "EXIF GPS", "no GPSLatitude/GPSLongitude tag",
                   "geotag the images, or import a geo.txt / reference CSV instead")
    lat = _dms(exif[f"{g}GPSLatitude"], exif.get(f"{g}GPSLatitudeRef"), where,
               "GPSLatitude", "S")
    lon = _dms(exif[f"{g}GPSLongitude"], exif.get(f"{g}GPSLongitudeRef"), where,
               "GPSLongitude", "W")
    z = _float(xmp, "AbsoluteAltitude", where)
    if z is None and f"{g}GPSAltitude" in exif:
        z = _ratio(exif[f"{g}GPSAltitude"], where, "GPSAltitude")
        if exif.get(f"{g}GPSAltitudeRef", "0").strip() == "1":
            z = -z
    angles = [_float(xmp, f"Gimbal{a}Degree", where) for a in ("Yaw", "Pitch", "Roll")]
    if any(a is None for a in angles):
        raise fail(where, "XMP drone-dji", "no GimbalYawDegree/GimbalPitchDegree/"
                   "GimbalRollDegree", "import images with DJI gimbal metadata, or a geo.txt "
                   "/ reference CSV with yaw, pitch and roll")
    focal = exif.get("Exif.Photo.FocalLength")
    width = exif.get("Exif.Photo.PixelXDimension")
    height = exif.get("Exif.Photo.PixelYDimension")
    camera = CameraInfo(
        make=(exif.get("Exif.Image.Make") or "").strip() or None,
        model=(exif.get("Exif.Image.Model") or "").strip() or None,
        focal_length_mm=None if focal is None else _ratio(focal, where, "FocalLength"),
        image_width_px=int(width) if width else size[0],
        image_height_px=int(height) if height else size[1])
    return FlownPhoto(path.name, where, "EPSG:4326", lon, lat, z,
                      _float(xmp, "RelativeAltitude", where),
                      (GIMBAL_TRUE, *angles), camera)


def read_image_folder(folder: Path) -> list[FlownPhoto]:
    """Every image of a folder (sorted by name)."""
    files = sorted(p for p in Path(folder).iterdir() if p.suffix.lower() in IMAGE_SUFFIXES)
    if not files:
        raise fail(str(folder), "", "no images (.jpg, .tif, .dng)",
                   "give the folder of the flight's photos")
    return [read_image(p) for p in files]
