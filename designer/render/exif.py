"""The moment a photo is taken, written into its EXIF (pyexiv2), as cameras do.

Tags (EXIF 2.32, CIPA DC-008): ``Exif.Photo.DateTimeOriginal`` 'YYYY:MM:DD HH:MM:SS',
``Exif.Photo.SubSecTimeOriginal`` the fraction of that second as six digits
(microseconds, the time line's resolution) and ``Exif.Photo.OffsetTimeOriginal``
'+00:00' (the time line is in UTC). Written only when the project asks for image
metadata (``<output metadata="exif">``), into JPEG and TIFF files.
"""

from __future__ import annotations

import datetime as _dt
from pathlib import Path

DATE_TIME = "Exif.Photo.DateTimeOriginal"
SUB_SEC = "Exif.Photo.SubSecTimeOriginal"
OFFSET = "Exif.Photo.OffsetTimeOriginal"


def exif_time_tags(time_utc: str) -> dict[str, str]:
    """The three EXIF tags of an ISO 8601 UTC moment ('2026-06-21T09:30:04.250000Z')."""
    moment = _dt.datetime.fromisoformat(time_utc).astimezone(_dt.UTC)
    return {DATE_TIME: moment.strftime("%Y:%m:%d %H:%M:%S"),
            SUB_SEC: f"{moment.microsecond:06d}", OFFSET: "+00:00"}


def write_time(path: Path, time_utc: str) -> None:
    """Write the moment's tags into the image file at ``path`` (modified in place: give
    a file not yet renamed into place)."""
    import pyexiv2

    with pyexiv2.Image(str(path)) as image:
        image.modify_exif(exif_time_tags(time_utc))


def read_time(path: Path) -> _dt.datetime | None:
    """The moment an image's EXIF says it was taken (aware), or None without the tags."""
    import pyexiv2

    with pyexiv2.Image(str(path)) as image:
        exif = image.read_exif()
    if DATE_TIME not in exif:
        return None
    moment = _dt.datetime.strptime(exif[DATE_TIME], "%Y:%m:%d %H:%M:%S")
    sub = exif.get(SUB_SEC, "0").strip() or "0"
    moment += _dt.timedelta(seconds=float("0." + sub))
    offset = exif.get(OFFSET, "+00:00").strip()
    sign = -1 if offset.startswith("-") else 1
    hours, _, minutes = offset.lstrip("+-").partition(":")
    tz = _dt.timezone(sign * _dt.timedelta(hours=int(hours), minutes=int(minutes or 0)))
    return moment.replace(tzinfo=tz)
