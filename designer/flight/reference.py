"""Flown positions from text: OpenDroneMap geo.txt and Metashape/Pix4D-style reference CSVs.

geo.txt (ODM docs, source/geo.rst "Image Geolocation Files"): the first line names the
CRS (``EPSG:<code>``, ``WGS84 UTM <zone><N|S>`` or a PROJ string), then one row per
image: ``image_name geo_x geo_y [geo_z] [yaw pitch roll] [horz_acc vert_acc]
[extras]``, white-space separated; EPSG:4326 rows are longitude latitude. The angles
use ODM's normalised convention as :mod:`designer.export.odm` writes them: yaw
clockwise from TRUE north (ODM's compute_opk takes north as the direction of
increasing latitude), pitch 0 = nadir and positive towards the image top, roll with
ODM's aerospace sign. The importer needs
the height and the three angles.

Reference CSV (Metashape "Import Reference" and its own camera export; Pix4D "Image
Geolocation" files): one header row — or, as Metashape writes, the last ``#`` comment
line before the data — then one row per image; separator ``,``, ``;`` or tab. Headers
are matched case-insensitively, ignoring a leading ``#``, spaces and underscores:

* label: Label, Name, Image, ImageName, Filename, File, Photo, Camera, PhotoID;
* position: X/Easting, Easting, X, East — or Longitude, Lon, Long (then the CSV is
  WGS 84); Y/Northing, Northing, Y, North — or Latitude, Lat; Z/Altitude, Altitude,
  Alt, Z, Height, Elevation, Ellipsoidal height;
* attitude, one set: Omega, Phi, Kappa (designer's ω φ κ in the CSV's grid, which is
  what Metashape writes with Rotation angles = Omega, Phi, Kappa); or Yaw, Pitch, Roll
  (geo.txt's convention above); or GimbalYawDegree, GimbalPitchDegree,
  GimbalRollDegree (DJI gimbal angles, yaw from true north, pitch −90 = nadir).

Projected CSV coordinates are in the CRS given with ``--csv-crs`` (default: the
project's CRS).
"""

from __future__ import annotations

import csv
import io
import re
from pathlib import Path

from designer.core.crs import odm_accepts_crs
from designer.flight.checks import fail, number
from designer.flight.photos import GIMBAL_TRUE, OPK_GRID, YPR_GRID, YPR_TRUE, FlownPhoto

_UTM = re.compile(r"^WGS84 UTM (\d{1,2})([NS])$", re.IGNORECASE)

HEADERS = {
    "label": ("label", "name", "image", "imagename", "filename", "file", "photo", "camera",
              "photoid"),
    "east": ("x/easting", "easting", "x", "east"),
    "lon": ("longitude", "lon", "long", "x/longitude"),
    "north": ("y/northing", "northing", "y", "north"),
    "lat": ("latitude", "lat", "y/latitude"),
    "z": ("z/altitude", "altitude", "alt", "z", "height", "elevation", "ellipsoidalheight"),
    "omega": ("omega",), "phi": ("phi",), "kappa": ("kappa",),
    "yaw": ("yaw", "heading"), "pitch": ("pitch",), "roll": ("roll",),
    "gyaw": ("gimbalyawdegree",), "gpitch": ("gimbalpitchdegree",),
    "groll": ("gimbalrolldegree",),
}
ANGLE_SETS = ((OPK_GRID, ("omega", "phi", "kappa")), (YPR_GRID, ("yaw", "pitch", "roll")),
              (GIMBAL_TRUE, ("gyaw", "gpitch", "groll")))


def _odm_crs(line: str) -> str:
    match = _UTM.match(line.strip())
    if match:
        zone, hemi = int(match.group(1)), match.group(2).upper()
        return f"EPSG:{(32600 if hemi == 'N' else 32700) + zone}"
    return line.strip()


def read_geo_txt(path: Path) -> list[FlownPhoto]:
    """The photos of an ODM geo.txt (module docstring)."""
    source = str(path)
    lines = _text(path).splitlines()
    rows = [(k + 1, ln.split()) for k, ln in enumerate(lines) if ln.strip()]
    if not rows:
        raise fail(source, "line 1", "empty file", "the first line names the CRS")
    first_no, first = rows[0]
    header = " ".join(first)
    if not odm_accepts_crs(header):
        raise fail(f"{source}:{first_no}", "CRS line", f"{header!r} is not a CRS",
                   "start with EPSG:<code>, 'WGS84 UTM <zone><N|S>' or a PROJ string")
    crs = _odm_crs(header)
    out = []
    for no, f in rows[1:]:
        where = f"{source}:{no}"
        if len(f) < 7:
            raise fail(where, f[0], f"{len(f) - 1} values after the image name",
                       "give 'image x y z yaw pitch roll': the importer needs the height "
                       "and the camera angles")
        x, y, z, yaw, pitch, roll = (number(v, where, f[0], "value") for v in f[1:7])
        out.append(FlownPhoto(f[0], where, crs, x, y, z, None, (YPR_TRUE, yaw, pitch, roll)))
    if not out:
        raise fail(source, "", "no image rows", "add one row per image after the CRS line")
    return out


def _key(header: str) -> str:
    return re.sub(r"[\s_#]", "", header).lower()


def read_reference_csv(path: Path, crs: str) -> list[FlownPhoto]:
    """The photos of a reference CSV (module docstring); ``crs`` for projected X/Y."""
    source = str(path)
    text = _text(path)
    lines = text.splitlines()
    header_no = None
    for k, line in enumerate(lines):
        if not line.strip():
            continue
        if line.lstrip().startswith("#"):
            header_no = k
            continue
        if header_no is None or not lines[header_no].lstrip().startswith("#"):
            header_no = k
        break
    if header_no is None:
        raise fail(source, "", "no header row", "name the columns in the first row")
    body = "\n".join([lines[header_no].lstrip().lstrip("#")] + lines[header_no + 1:])
    try:
        dialect = csv.Sniffer().sniff(lines[header_no], delimiters=",;\t")
    except csv.Error:
        dialect = csv.excel
    reader = csv.reader(io.StringIO(body), dialect)
    header = [_key(h) for h in next(reader)]
    col = {}
    for role, names in HEADERS.items():
        for name in names:
            if name in header:
                col[role] = header.index(name)
                break
    geographic = "lon" in col and "lat" in col
    need = ["label", "lon", "lat", "z"] if geographic else ["label", "east", "north", "z"]
    missing = [r for r in need if r not in col]
    angles = next(((conv, names) for conv, names in ANGLE_SETS
                   if all(n in col for n in names)), None)
    if missing or angles is None:
        what = ", ".join(missing) if missing else "camera angles"
        raise fail(f"{source}:{header_no + 1}", "header", f"no column for {what}",
                   "name the columns Label, X/Easting (or Longitude), Y/Northing (or Latitude), "
                   "Z/Altitude and Omega/Phi/Kappa, Yaw/Pitch/Roll or GimbalYawDegree/"
                   "GimbalPitchDegree/GimbalRollDegree")
    xk, yk = ("lon", "lat") if geographic else ("east", "north")
    out = []
    for no, row in enumerate(reader, start=header_no + 2):
        if not row or not "".join(row).strip() or row[0].lstrip().startswith("#"):
            continue
        where = f"{source}:{no}"
        if len(row) < len(header):
            raise fail(where, "row", f"{len(row)} fields, the header has {len(header)}",
                       "fill every column")
        label = row[col["label"]].strip()
        x, y, z = (number(row[col[r]], where, label, r) for r in (xk, yk, "z"))
        a = [number(row[col[n]], where, label, n) for n in angles[1]]
        out.append(FlownPhoto(label, where, "EPSG:4326" if geographic else crs, x, y, z,
                              None, (angles[0], *a)))
    if not out:
        raise fail(source, "", "no data rows", "add one row per image")
    return out


def _text(path: Path) -> str:
    try:
        return Path(path).read_text(encoding="utf-8-sig")
    except (OSError, UnicodeDecodeError) as error:
        raise fail(str(path), "", f"cannot read the file ({error})",
                   "give a UTF-8 text file") from None
