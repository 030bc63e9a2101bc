"""OpenDroneMap's and OpenSfM's readers of gcp_list.txt and geo.txt, re-implemented from
their code and docs, agree with designer's exports.

Re-implemented here (not imported: neither program is installed):

* ODM opendm/location.py ``parse_srs_header``: strip, split on single spaces;
  ``WGS84 UTM <zone><pole>`` only with exactly those two words (case matters), zone =
  int(word 3 minus its last character), pole upper-cased, 'S' = south; else '+proj' in
  the line → ``CRS.from_proj4``; else a line starting with 'epsg:' in any case →
  ``CRS.from_epsg``; else an error;
* ODM opendm/gcp.py ``GCPFile.read`` and opendm/geo.py ``GeoFile``: whole file
  stripped, split on '\\n', each line stripped; line 1 is the CRS; blank lines and lines
  starting with '#' are skipped; gcp rows need >= 6 words, geo rows >= 3
  (name x y [z [yaw pitch roll [horizontal vertical accuracy]]]); geo.txt x, y, z are
  converted to longitude/latitude with that CRS (always_xy);
* OpenSfM opensfm/io.py ``_read_gcp_list_lines`` (on the UTM copy ODM hands it):
  ``line.split(None, 5)``, the first five words floats, rows with identical
  (easting, northing, alt) are one point.
"""

import math

import pytest
from pyproj import CRS, Geod, Transformer

from designer.core.crs import odm_accepts_crs, odm_crs, odm_crs_problem
from designer.core.rotation import heading_tilt_roll_from_rotation
from designer.export.odm import odm_gcp_list_text, odm_geo_text
from tests.synthetic import survey


class OdmRejects(Exception):
    pass


def odm_parse_srs_header(header: str) -> CRS:
    header = header.strip()
    ref = header.split(" ")
    try:
        if ref[0] == "WGS84" and ref[1] == "UTM":
            pole = ref[2][-1].upper()
            zone = int(ref[2][:-1])
            proj4 = f"+proj=utm +zone={zone} +datum=WGS84 +units=m +no_defs=True"
            if pole == "S":
                proj4 += " +south=True"
            return CRS.from_proj4(proj4)
        if "+proj" in header:
            return CRS.from_proj4(header.strip("'"))
        if header.lower().startswith("epsg:"):
            return CRS.from_epsg(header.lower()[5:])
    except Exception as exc:  # ODM wraps every failure into "Could not parse"
        raise OdmRejects(header) from exc
    raise OdmRejects(header)


def odm_lines(text: str) -> tuple[str, list[str]]:
    lines = [ln.strip() for ln in text.strip().split("\n")]
    return lines[0], [ln for ln in lines[1:] if ln != "" and ln[0] != "#"]


def odm_read_geo(text: str) -> dict[str, dict]:
    header, rows = odm_lines(text)
    srs = odm_parse_srs_header(header)
    to_lonlat = Transformer.from_crs(srs, CRS.from_epsg(4326), always_xy=True)
    entries = {}
    for row in rows:
        parts = row.split()
        assert len(parts) >= 3
        x, y = (float(p) for p in parts[1:3])
        z = float(parts[3]) if len(parts) >= 4 else None
        lon, lat = to_lonlat.transform(x, y)
        entry = dict(lon=lon, lat=lat, z=z)
        if len(parts) >= 7:
            entry.update(zip(("yaw", "pitch", "roll"), (float(p) for p in parts[4:7]),
                             strict=True))
        if len(parts) >= 9:
            entry.update(zip(("h_acc", "v_acc"), (float(p) for p in parts[7:9]), strict=True))
        entries[parts[0]] = entry
    return entries


HEADERS = [
    "EPSG:32632", "epsg:32632", "EPSG:25832", "EPSG:2056", "WGS84 UTM 32N", "WGS84 UTM 33S",
    "WGS84 UTM 1N", "WGS84 UTM 60S", "+proj=utm +zone=32 +datum=WGS84 +units=m",
    # rejected by designer:
    "wgs84 utm 32N", "WGS84 utm 32N", "WGS84 UTM 0N", "WGS84 UTM 61N", "WGS84 UTM 32",
    "WGS84 UTM 32X", "EPSG:4326", "+proj=longlat +datum=WGS84", "EPSG:2263", "UTM 32N",
    "ETRS89 / UTM zone 32N",
]


@pytest.mark.parametrize("header", HEADERS)
def test_designer_accepts_a_header_only_when_odm_reads_it_as_projected_metres(header):
    problem = odm_crs_problem(header)
    try:
        crs = odm_parse_srs_header(header)
    except OdmRejects:
        crs = None
    if problem is None:
        assert odm_accepts_crs(header)
        assert crs is not None and crs.is_projected
        assert {a.unit_name for a in crs.axis_info[:2]} <= {"metre", "meter"}
        assert crs == odm_crs(header)  # designer builds the CRS ODM builds
    else:
        # ODM refuses it, reads something else than written (a pole that is neither N
        # nor S is north), or it would turn metres into degrees or feet
        assert (crs is None or not crs.is_projected
                or {a.unit_name for a in crs.axis_info[:2]} - {"metre", "meter"}
                or header.split()[-1][-1] not in "NS")


def test_odm_reads_every_gcp_row_with_designers_fields():
    _interior, _poses, gcps, obs = survey(40)
    text = odm_gcp_list_text(gcps, obs, "WGS84 UTM 32N")
    header, rows = odm_lines(text)
    assert odm_parse_srs_header(header) == odm_crs("WGS84 UTM 32N")
    by_id = {g.gcp_id: g for g in gcps}
    control = [o for o in obs if by_id[o.gcp_id].role == "control"]
    assert len(rows) == len(control)
    for row, o in zip(rows, control, strict=True):
        parts = row.split()
        assert len(parts) >= 6
        assert [float(v) for v in parts[:3]] == by_id[o.gcp_id].surveyed_xyz.tolist()
        assert (float(parts[3]) + 0.5, float(parts[4]) + 0.5) == tuple(o.uv_px.tolist())
        assert parts[5] == o.image_name and " ".join(parts[6:]) == o.gcp_id


def test_opensfm_groups_the_rows_into_one_point_per_control_gcp():
    _interior, _poses, gcps, obs = survey(41)
    _header, rows = odm_lines(odm_gcp_list_text(gcps, obs, "WGS84 UTM 32N"))
    points: dict[tuple[float, float, float], set[str]] = {}
    for row in rows:
        words = row.split(None, 5)
        e, n, alt, _px, _py = map(float, words[:5])
        points.setdefault((e, n, alt), set()).add(words[5].split()[1])
    # one point per GCP, and every point carries one GCP's rows only
    assert all(len(ids) == 1 for ids in points.values())
    seen = {o.gcp_id for o in obs if next(g for g in gcps if g.gcp_id == o.gcp_id).role ==
            "control"}
    assert len(points) == len(seen)


@pytest.mark.parametrize("crs", ["EPSG:32632", "WGS84 UTM 32N"])
def test_odm_reads_geo_txt_positions_and_true_north_yaw(crs):
    _interior, poses, _gcps, _obs = survey(42)
    entries = odm_read_geo(odm_geo_text(poses, crs, 0.05, 0.1))
    assert list(entries) == [p.image_name for p in poses]
    to_lonlat = Transformer.from_crs(CRS.from_epsg(32632), CRS.from_epsg(4326),
                                     always_xy=True)
    for p in poses:
        e = entries[p.image_name]
        lon, lat = to_lonlat.transform(*p.C_world[:2])
        assert (e["lon"], e["lat"]) == pytest.approx((lon, lat), abs=1e-11)
        assert e["z"] == p.C_world[2] and (e["h_acc"], e["v_acc"]) == (0.05, 0.1)
        # the image top's true azimuth, measured on the ellipsoid: a point 1 m along the
        # image top's grid direction, back to lon/lat, against the meridian
        heading, _tilt, _roll = heading_tilt_roll_from_rotation(p.R_cam_to_world)
        E2 = p.C_world[0] + math.sin(heading)
        N2 = p.C_world[1] + math.cos(heading)
        lon2, lat2 = to_lonlat.transform(E2, N2)
        true_az = Geod(ellps="WGS84").inv(lon, lat, lon2, lat2)[0] % 360.0
        diff = (e["yaw"] - true_az + 180.0) % 360.0 - 180.0
        assert abs(diff) < 1e-5, (e["yaw"], true_az)
