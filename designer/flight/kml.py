"""KML 2.2 / KMZ: flight lines and photo points for Google Earth and GIS.

Format (OGC KML 2.2, OGC 07-147r2, http://www.opengis.net/kml/2.2; Google's KML
Reference, https://developers.google.com/kml/documentation/kmlreference):

* root ``kml`` in the namespace ``http://www.opengis.net/kml/2.2`` holding one
  ``Document``; ``Folder``s group ``Placemark``s;
* ``coordinates`` are ``lon,lat[,alt]`` tuples (decimal degrees WGS 84, altitude in
  metres) separated by white space; ``altitudeMode`` ``absolute`` means above sea
  level (written: project Z + height offset), ``relativeToGround`` above the terrain;
* ``ExtendedData``/``Data name=…``/``value`` carries per-photo values;
* KMZ is a ZIP archive whose first entry is the KML document (``doc.kml``).

Written: a "Flight lines" folder (one ``LineString`` per line, in flight order) and a
"Photos" folder (one ``Point`` per exposure, named by its image, with the gimbal
``yaw_deg`` (true north), ``pitch_deg``, ``roll_deg`` as ExtendedData). The checks
below apply the reference's required structure (namespace, Document, coordinates
syntax and ranges); no XSD is bundled.
"""

from __future__ import annotations

import io
import zipfile
from pathlib import Path

from lxml import etree

from designer.atomic import write_bytes_atomic
from designer.flight.checks import fail, number
from designer.flight.exposures import FlightSpec, FlownPoint

KML_NS = "http://www.opengis.net/kml/2.2"
_K = f"{{{KML_NS}}}"
ANGLES = ("yaw_deg", "pitch_deg", "roll_deg")


def _sub(parent, tag: str, text: str | None = None, **attrs):
    el = etree.SubElement(parent, _K + tag, **attrs)
    if text is not None:
        el.text = text
    return el


def _coord(spec: FlightSpec, e) -> str:
    return f"{e.lon_deg:.10f},{e.lat_deg:.10f},{spec.absolute_height(e.Z_m):.4f}"


def kml_document(spec: FlightSpec) -> bytes:
    root = etree.Element(_K + "kml", nsmap={None: KML_NS})
    doc = _sub(root, "Document")
    _sub(doc, "name", spec.name)
    _sub(doc, "description", f"{len(spec.exposures)} photos with camera "
                             f"{spec.camera.name or spec.camera.id}; heights above sea level")
    lines = _sub(doc, "Folder")
    _sub(lines, "name", "Flight lines")
    for k, line in enumerate(spec.lines):
        pm = _sub(lines, "Placemark")
        _sub(pm, "name", f"line {k + 1}")
        geom = _sub(pm, "LineString") if len(line) > 1 else _sub(pm, "Point")
        _sub(geom, "altitudeMode", "absolute")
        _sub(geom, "coordinates", " ".join(_coord(spec, e) for e in line))
    photos = _sub(doc, "Folder")
    _sub(photos, "name", "Photos")
    for e in spec.exposures:
        pm = _sub(photos, "Placemark")
        _sub(pm, "name", e.name)
        data = _sub(pm, "ExtendedData")
        for key, value in zip(ANGLES, (e.yaw_true_deg, e.pitch_deg, e.roll_deg), strict=True):
            _sub(_sub(data, "Data", name=key), "value", repr(float(value)))
        point = _sub(pm, "Point")
        _sub(point, "altitudeMode", "absolute")
        _sub(point, "coordinates", _coord(spec, e))
    return etree.tostring(root, xml_declaration=True, encoding="UTF-8", pretty_print=True)


def write_kml(spec: FlightSpec, path: Path) -> Path:
    """Write ``.kml`` or, for a ``.kmz`` suffix, a KMZ archive (doc.kml), atomically."""
    data = kml_document(spec)
    check_kml(etree.fromstring(data), str(path))
    if Path(path).suffix.lower() == ".kmz":
        buffer = io.BytesIO()
        with zipfile.ZipFile(buffer, "w", zipfile.ZIP_DEFLATED) as z:
            z.writestr("doc.kml", data)
        data = buffer.getvalue()
    write_bytes_atomic(path, data)
    return Path(path)


def parse_coordinates(text: str, source: str, place: str) -> list[tuple[float, float, float]]:
    out = []
    for tup in (text or "").split():
        parts = tup.split(",")
        if len(parts) not in (2, 3):
            raise fail(source, place, f"coordinate {tup!r} is not lon,lat[,alt]",
                       "write comma-separated tuples separated by spaces")
        lon, lat, *alt = (number(v, source, place, "coordinate") for v in parts)
        if not (-180 <= lon <= 180 and -90 <= lat <= 90):
            raise fail(source, place, f"lon,lat {lon},{lat} out of range",
                       "KML coordinates are longitude first, then latitude")
        out.append((lon, lat, alt[0] if alt else 0.0))
    if not out:
        raise fail(source, place, "empty coordinates", "give at least one lon,lat tuple")
    return out


def check_kml(root, source: str) -> None:
    """Namespace, Document and every coordinates element (module docstring)."""
    if root.tag != _K + "kml":
        raise fail(source, "root", f"root element {root.tag!r}",
                   f"a KML 2.2 file has a <kml> root in {KML_NS}")
    if root.find(_K + "Document") is None:
        raise fail(source, "kml", "no Document", "put the placemarks in a <Document>")
    for el in root.iter(_K + "coordinates"):
        parse_coordinates(el.text, source, f"line {el.sourceline} <coordinates>")
    for el in root.iter(_K + "altitudeMode"):
        if el.text not in ("clampToGround", "relativeToGround", "absolute"):
            raise fail(source, f"line {el.sourceline} <altitudeMode>", f"{el.text!r}",
                       "use clampToGround, relativeToGround or absolute")


def read_kml(path: Path, height_offset_m: float = 0.0) -> list[FlownPoint]:
    """The photo points (Point placemarks with the three angles) of a KML or KMZ."""
    source = str(path)
    try:
        data = Path(path).read_bytes()
        if zipfile.is_zipfile(io.BytesIO(data)):
            with zipfile.ZipFile(io.BytesIO(data)) as z:
                names = [n for n in z.namelist() if n.lower().endswith(".kml")]
                if not names:
                    raise fail(source, "", "the KMZ holds no .kml", "put doc.kml in the archive")
                data = z.read(names[0])
        root = etree.fromstring(data, etree.XMLParser(resolve_entities=False))
    except (OSError, etree.XMLSyntaxError, zipfile.BadZipFile) as error:
        raise fail(source, "", f"cannot read the KML ({error})",
                   "give a KML 2.2 or KMZ file") from None
    check_kml(root, source)
    points = []
    for pm in root.iter(_K + "Placemark"):
        point = pm.find(_K + "Point")
        values = {d.get("name"): d.findtext(_K + "value") for d in pm.iter(_K + "Data")}
        if point is None or not all(a in values for a in ANGLES):
            continue
        place = f"line {pm.sourceline} <Placemark>"
        lon, lat, alt = parse_coordinates(point.findtext(_K + "coordinates"), source, place)[0]
        yaw, pitch, roll = (number(values[a], source, place, a) for a in ANGLES)
        points.append(FlownPoint(pm.findtext(_K + "name"), lon, lat, alt - height_offset_m,
                                 yaw, pitch, roll))
    return points
