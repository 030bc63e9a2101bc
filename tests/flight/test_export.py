"""Flight plans out: each format is written, checked against its documented fields and
read back to the planned poses (≤ 1 cm, ≤ 0.01°)."""

import dataclasses
import json
import zipfile
from pathlib import Path

import numpy as np
import pytest
from lxml import etree

from designer.cli.main import main
from designer.flight.checks import FlightFileError
from designer.flight.export import export_flight
from designer.flight.exposures import pose_of
from designer.flight.geodesy import Georef
from designer.flight.kml import read_kml
from designer.flight.qgc import read_plan
from designer.flight.wpml import read_wpml
from designer.project import load_project
from designer.project import model as m
from designer.project.interiors import interior_from_camera
from designer.scene.build import build_heightfield
from designer.survey.project_poses import flight_plan_for
from tests.flight.helpers import EXAMPLE, rotation_error_deg, shifted
from tests.synthetic import small_survey, write_project_file

READERS = {"qgc": read_plan, "kml": read_kml, "wpml": read_wpml}
SUFFIX = {"qgc": ".plan", "kml": ".kmz", "wpml": ".kmz"}


def planned(project, base_dir):
    """The plan's stations without noise, straight from the planner."""
    plan = project.trajectory.flight_plan
    hf = build_heightfield(project.scene.terrain, base_dir)
    return flight_plan_for(plan, interior_from_camera(project.camera(plan.camera)), hf,
                           ".png").stations, hf


def compare(points, stations, georef):
    assert len(points) == len(stations)
    dC = dR = 0.0
    for point, station in zip(points, stations, strict=True):
        C, R = pose_of(point, georef)
        dC = max(dC, float(np.abs(C - station.C_world).max()))
        dR = max(dR, rotation_error_deg(R, station.R_cam_to_world))
    return dC, dR


@pytest.fixture(scope="module")
def example():
    return load_project(EXAMPLE)


@pytest.mark.parametrize("fmt", ["qgc", "kml", "wpml"])
@pytest.mark.parametrize("altitude", ["relative", "amsl"])
def test_written_flight_reads_back_to_the_plan(tmp_path, example, fmt, altitude):
    out = tmp_path / f"flight{SUFFIX[fmt]}"
    spec = export_flight(example, EXAMPLE.parent, fmt, out, altitude=altitude,
                         height_offset_m=47.5)
    stations, _ = planned(example, EXAMPLE.parent)
    points = READERS[fmt](out, height_offset_m=47.5)
    dC, dR = compare(points, stations, Georef(example.crs))
    assert dC <= 0.01 and dR <= 0.01, (dC, dR)
    assert len(spec.lines) == len({s.line_index for s in stations}) > 1


def test_a_tilted_portrait_crosshatch_reads_back(tmp_path, example):
    plan = dataclasses.replace(example.trajectory.flight_plan, tilt_deg=25.0,
                               orientation="portrait", crosshatch=True, grid_angle_deg=30.0)
    project = dataclasses.replace(
        shifted(example, -60_000.0),  # west of the central meridian
        trajectory=dataclasses.replace(example.trajectory, flight_plan=dataclasses.replace(
            plan, area=tuple((x - 60_000.0, y) for x, y in plan.area))))
    stations, _ = planned(project, EXAMPLE.parent)
    georef = Georef(project.crs)
    assert float(georef.true_north_azimuth_deg(*stations[0].C_world[:2])) > 0.3
    for fmt in READERS:
        out = tmp_path / f"tilted{SUFFIX[fmt]}"
        export_flight(project, EXAMPLE.parent, fmt, out)
        dC, dR = compare(READERS[fmt](out), stations, georef)
        assert dC <= 0.01 and dR <= 0.01, (fmt, dC, dR)


def test_qgc_plan_fields(tmp_path, example):
    out = tmp_path / "f.plan"
    spec = export_flight(example, EXAMPLE.parent, "qgc", out)
    doc = json.loads(out.read_text())
    assert doc["fileType"] == "Plan" and doc["version"] == 1
    mission = doc["mission"]
    items = mission["items"]
    waypoints = [i for i in items if i["command"] == 16]
    assert {i["frame"] for i in waypoints} == {3}  # relative to take-off
    assert all(len(i["params"]) == 7 for i in items)
    triggers = [i["params"][0] for i in items if i["command"] == 206]
    assert len(triggers) == 2 * len(spec.lines)
    assert triggers[0] == pytest.approx(spec.trigger_distance_m) and triggers[1] == 0
    # home is the take-off point on the terrain: the first waypoint's relative altitude
    # is the flight height above it
    assert waypoints[0]["params"][6] == pytest.approx(spec.exposures[0].Z_m
                                                      - spec.exposures[0].ground_m)
    assert [i["doJumpId"] for i in items] == list(range(1, len(items) + 1))


def test_terrain_following_plans(tmp_path, example):
    plan = dataclasses.replace(example.trajectory.flight_plan, terrain_following=True)
    project = dataclasses.replace(example, trajectory=dataclasses.replace(
        example.trajectory, flight_plan=plan))
    stations, _hf = planned(project, EXAMPLE.parent)
    georef = Georef(project.crs)
    out = tmp_path / "tf.kmz"
    export_flight(project, EXAMPLE.parent, "wpml", out)
    with zipfile.ZipFile(out) as z:
        assert sorted(z.namelist()) == ["wpmz/template.kml", "wpmz/waylines.wpml"]
        way = etree.fromstring(z.read("wpmz/waylines.wpml"))
        template = etree.fromstring(z.read("wpmz/template.kml"))
    W = "{http://www.dji.com/wpmz/1.0.2}"
    # per-waypoint heights (DJI: realTimeFollowSurface is for mapping templates only):
    # the aircraft's file has each waypoint's absolute height, the template its height
    # above the terrain
    assert way.findtext(f".//{W}executeHeightMode") == "WGS84"
    assert template.findtext(f".//{W}heightMode") == "aboveGroundLevel"
    assert "realTimeFollowSurface" not in etree.tostring(way).decode()
    agl = [float(h.text) for h in template.iter(W + "height")]
    assert np.allclose(agl, 50.0)  # the AGL height of the example's plan
    heights = np.array([float(h.text) for h in way.iter(W + "executeHeight")])
    assert np.ptp(heights) > 5.0  # they follow the hills

    dC, dR = compare(read_wpml(out), stations, georef)
    assert dC <= 0.01 and dR <= 0.01
    plan_out = tmp_path / "tf.plan"
    export_flight(project, EXAMPLE.parent, "qgc", plan_out)
    items = [i for i in json.loads(plan_out.read_text())["mission"]["items"]
             if i["command"] == 16]
    # QGC's AltitudeModeCalcAboveTerrain (3), frame 0 (designer.flight.qgc docstring)
    assert {(i["AltitudeMode"], i["frame"]) for i in items} == {(3, 0)}
    assert json.loads(plan_out.read_text())["mission"]["globalPlanAltitudeMode"] == 3
    assert np.allclose([i["Altitude"] for i in items], 50.0)
    dC, dR = compare(read_plan(plan_out), stations, georef)
    assert dC <= 0.01 and dR <= 0.01


def test_kml_structure(tmp_path, example):
    out = tmp_path / "f.kml"
    spec = export_flight(example, EXAMPLE.parent, "kml", out)
    root = etree.parse(str(out)).getroot()
    K = "{http://www.opengis.net/kml/2.2}"
    assert root.tag == K + "kml"
    lines = list(root.iter(K + "LineString"))
    assert len(lines) == len(spec.lines)
    first = lines[0].findtext(K + "coordinates").split()[0].split(",")
    assert float(first[0]) == pytest.approx(spec.exposures[0].lon_deg)  # lon first
    assert [p.name for p in read_kml(out)] == [e.name for e in spec.exposures]


@pytest.mark.parametrize(("fmt", "damage", "message"), [
    ("qgc", lambda d: d.pop("fileType"), "fileType"),
    ("qgc", lambda d: d["mission"]["items"][1]["params"].pop(), "seven params"),
    ("qgc", lambda d: d["mission"].pop("plannedHomePosition"), "plannedHomePosition"),
])
def test_broken_plans_are_refused(tmp_path, example, fmt, damage, message):
    out = tmp_path / "f.plan"
    export_flight(example, EXAMPLE.parent, fmt, out)
    doc = json.loads(out.read_text())
    damage(doc)
    out.write_text(json.dumps(doc))
    with pytest.raises(FlightFileError, match=message):
        read_plan(out)


@pytest.mark.parametrize(("member", "old", "new", "message"), [
    ("wpmz/waylines.wpml", b"<wpml:executeHeightMode>relativeToStartPoint",
     b"<wpml:executeHeightMode>sea", "height mode 'sea'"),
    ("wpmz/waylines.wpml", b"<wpml:droneInfo>", b"<wpml:droneInfoX>", "droneInfo"),
    ("wpmz/template.kml", b"<wpml:templateType>waypoint</wpml:templateType>", b"",
     "templateType"),
])
def test_broken_wpml_is_refused(tmp_path, example, member, old, new, message):
    out = tmp_path / "f.kmz"
    export_flight(example, EXAMPLE.parent, "wpml", out)
    with zipfile.ZipFile(out) as z:
        files = {n: z.read(n) for n in z.namelist()}
    assert old in files[member]
    files[member] = files[member].replace(old, new).replace(
        old.replace(b"<", b"</").split(b">")[0] + b">", new.replace(b"<", b"</").split(b">")[0]
        + b">" if new else b"")
    with zipfile.ZipFile(out, "w") as z:
        for n, data in files.items():
            z.writestr(n, data)
    with pytest.raises(FlightFileError, match=message):
        read_wpml(out)


def test_cli_writes_and_refuses_cleanly(tmp_path, capsys):
    out = tmp_path / "f.plan"
    assert main(["export-flight", str(EXAMPLE), "--format", "qgc", "-o", str(out)]) == 0
    assert "60 photos" in capsys.readouterr().out and out.is_file()
    bad = tmp_path / "f.txt"
    assert main(["export-flight", str(EXAMPLE), "--format", "qgc", "-o", str(bad)]) == 2
    err = capsys.readouterr().err.strip()
    assert "f.txt" in err and ".plan" in err and len(err.splitlines()) == 1
    assert not bad.exists()
    missing = tmp_path / "no" / "f.kmz"
    assert main(["export-flight", str(EXAMPLE), "--format", "wpml", "-o", str(missing)]) == 2
    assert "does not exist" in capsys.readouterr().err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["f.plan"]  # nothing half-written


def test_the_cli_lists_both_commands(capsys):
    with pytest.raises(SystemExit):
        main(["--help"])
    text = capsys.readouterr().out
    assert "export-flight" in text and "import-flight" in text


def test_files_from_the_cli_match_the_api(tmp_path):
    a, b = tmp_path / "a.kmz", tmp_path / "b.kmz"
    assert main(["export-flight", str(EXAMPLE), "--format", "kml", "-o", str(a)]) == 0
    export_flight(load_project(EXAMPLE), Path(EXAMPLE).parent, "kml", b)
    assert [(p.lon_deg, p.Z_m) for p in read_kml(a)] == [(p.lon_deg, p.Z_m) for p in read_kml(b)]


#: QGroundControl's enum AltMode (src/QmlControls/QGroundControlQmlGlobal.h): name →
#: (value, the MAV_FRAME of a waypoint in that mode as QGC's test plans in test/plans/
#: write it). Built from QGC's source, independently of designer.flight.qgc.
QGC_ALT_MODES = {"Mixed": (0, None), "Relative": (1, 3), "Absolute": (2, 0),
                 "CalcAboveTerrain": (3, 0), "TerrainFrame": (4, 10)}


@pytest.mark.parametrize("altitude, mode", [("relative", "Relative"), ("amsl", "Absolute")])
def test_qgc_altitude_modes_are_qgcs_enum(tmp_path, example, altitude, mode):
    out = tmp_path / f"{altitude}.plan"
    export_flight(example, EXAMPLE.parent, "qgc", out, altitude=altitude)
    mission = json.loads(out.read_text())["mission"]
    value, frame = QGC_ALT_MODES[mode]
    assert mission["globalPlanAltitudeMode"] == value
    waypoints = [i for i in mission["items"] if i["command"] == 16]
    assert waypoints and {(i["AltitudeMode"], i["frame"]) for i in waypoints} == {(value, frame)}


def test_the_kml_message_says_the_heights_it_wrote(tmp_path, capsys):
    out = tmp_path / "f.kml"
    assert main(["export-flight", str(EXAMPLE), "--format", "kml", "-o", str(out)]) == 0
    said = capsys.readouterr().out
    modes = {el.text for el in etree.parse(str(out)).getroot().iter(
        "{http://www.opengis.net/kml/2.2}altitudeMode")}
    assert modes == {"absolute"} and "heights AMSL" in said and "relative" not in said
    plan = tmp_path / "f.plan"
    assert main(["export-flight", str(EXAMPLE), "--format", "qgc", "-o", str(plan)]) == 0
    assert "heights relative" in capsys.readouterr().out


#: fields DJI's WPML reference (Cloud API, "DJI WPML": template.kml, waylines.wpml,
#: Common Elements) marks required, per file and for the mode designer writes: (element
#: path from Document, condition) — the table the written files are checked against
WPML_REQUIRED = {
    "template": ["wpml:missionConfig/wpml:globalRTHHeight",
                 "wpml:missionConfig/wpml:takeOffSecurityHeight",
                 "Folder/wpml:templateType", "Folder/wpml:gimbalPitchMode",
                 "Folder/wpml:waylineCoordinateSysParam/wpml:heightMode",
                 "Folder/Placemark/wpml:gimbalPitchAngle"],  # gimbalPitchMode usePointSetting
    "waylines": ["wpml:missionConfig/wpml:globalRTHHeight",
                 "wpml:missionConfig/wpml:takeOffSecurityHeight",
                 "Folder/wpml:executeHeightMode", "Folder/Placemark/wpml:executeHeight"],
}


def test_wpml_has_every_required_field(tmp_path, example):
    out = tmp_path / "f.kmz"
    spec = export_flight(example, EXAMPLE.parent, "wpml", out)
    ns = {"kml": "http://www.opengis.net/kml/2.2", "wpml": "http://www.dji.com/wpmz/1.0.2"}
    with zipfile.ZipFile(out) as z:
        docs = {"template": etree.fromstring(z.read("wpmz/template.kml")),
                "waylines": etree.fromstring(z.read("wpmz/waylines.wpml"))}
    for name, paths in WPML_REQUIRED.items():
        doc = docs[name].find("kml:Document", ns)
        for path in paths:
            xpath = "/".join(p if p.startswith("wpml:") else f"kml:{p}" for p in path.split("/"))
            found = doc.findall(xpath, ns)
            if "Placemark" in path:
                assert len(found) == len(spec.exposures), (name, path)
            else:
                assert found, (name, path)
    rth = float(docs["waylines"].find("kml:Document/wpml:missionConfig/wpml:globalRTHHeight",
                                      ns).text)
    highest = max(spec.relative_height(e.Z_m) for e in spec.exposures)
    assert rth >= highest and rth >= 20
    pitch = [float(x.text) for x in docs["template"].iterfind(
        "kml:Document/kml:Folder/kml:Placemark/wpml:gimbalPitchAngle", ns)]
    assert pitch == pytest.approx([e.pitch_deg for e in spec.exposures])



#: the height modes the reference gives each choice (DJI WPML, waylines.wpml
#: executeHeightMode and Common Elements waylineCoordinateSysParam/heightMode), and the
#: per-waypoint height elements each file must carry in that mode
WPML_MODES = {
    "relative": ("relativeToStartPoint", "relativeToStartPoint", ("height",)),
    "amsl": ("WGS84", "EGM96", ("height", "ellipsoidHeight")),
    "terrain": ("WGS84", "aboveGroundLevel", ("height",)),
}


@pytest.mark.parametrize("mode", sorted(WPML_MODES))
def test_wpml_height_modes_and_their_fields(tmp_path, example, mode):
    project = example
    if mode == "terrain":
        plan = dataclasses.replace(example.trajectory.flight_plan, terrain_following=True)
        project = dataclasses.replace(example, trajectory=dataclasses.replace(
            example.trajectory, flight_plan=plan))
    out = tmp_path / f"{mode}.kmz"
    spec = export_flight(project, EXAMPLE.parent, "wpml", out,
                         altitude="amsl" if mode == "amsl" else "relative")
    ns = {"kml": "http://www.opengis.net/kml/2.2", "wpml": "http://www.dji.com/wpmz/1.0.2"}
    with zipfile.ZipFile(out) as z:
        template = etree.fromstring(z.read("wpmz/template.kml"))
        way = etree.fromstring(z.read("wpmz/waylines.wpml"))
    execute, height_mode, fields = WPML_MODES[mode]
    assert way.findtext(".//wpml:executeHeightMode", namespaces=ns) == execute
    assert template.findtext(".//wpml:waylineCoordinateSysParam/wpml:heightMode",
                             namespaces=ns) == height_mode
    for field in fields:
        assert len(template.findall(f".//kml:Placemark/wpml:{field}", ns)) == \
            len(spec.exposures), field
    assert len(way.findall(".//kml:Placemark/wpml:executeHeight", ns)) == len(spec.exposures)


def photos_in_lines(camera_id: str, E0: float, N0: float, Z: float, prefix: str = "IMG_"):
    """Twelve imported photos flown in three serpentine lines of four (north, south,
    north; 10 m apart, photos 6 m apart along a line), as a pose list."""
    photos = []
    for line, x in enumerate((-10.0, 0.0, 10.0)):
        north = line % 2 == 0
        ys = (-9.0, -3.0, 3.0, 9.0) if north else (9.0, 3.0, -3.0, -9.0)
        photos += [m.ExteriorOrientation(f"{prefix}{4 * line + k:03d}.png", camera_id,
                                         E0 + x, N0 + y, Z, 0.0, 0.0, 0.0 if north else 180.0)
                   for k, y in enumerate(ys)]
    return tuple(photos)


def kml_lines(path: Path) -> list[list[str]]:
    """The photo names along each LineString of a KML, by the photos' coordinates."""
    K = "{http://www.opengis.net/kml/2.2}"
    root = etree.parse(str(path)).getroot()
    folders = {f.findtext(K + "name"): f for f in root.iter(K + "Folder")}
    at = {pm.findtext(f"{K}Point/{K}coordinates"): pm.findtext(K + "name")
          for pm in folders["Photos"].iter(K + "Placemark")}
    return [[at[c] for c in pm.findtext(f".//{K}coordinates").split()]
            for pm in folders["Flight lines"].iter(K + "Placemark")]


def test_imported_photos_are_exported_in_the_lines_they_were_flown(tmp_path, capsys):
    project = small_survey(origin=(500000.0, 5000000.0, 250.0))
    project = dataclasses.replace(project, trajectory=m.Trajectory(
        exterior_orientations=photos_in_lines("cam", 500000.0, 5000000.0, 280.0)))
    path = write_project_file(project, tmp_path / "photos")
    out = tmp_path / "photos.kml"
    assert main(["export-flight", str(path), "--format", "kml", "-o", str(out)]) == 0
    assert "12 photos on 3 lines" in capsys.readouterr().out
    names = [f"IMG_{k:03d}.png" for k in range(12)]
    assert kml_lines(out) == [names[0:4], names[4:8], names[8:12]]
    # QGC: each imported photo is taken at its own waypoint (no trigger distance: the
    # photos need not be evenly spaced), all of them read back in order
    plan = tmp_path / "photos.plan"
    assert main(["export-flight", str(path), "--format", "qgc", "-o", str(plan)]) == 0
    assert "12 photos on 3 lines" in capsys.readouterr().out
    commands = [i["command"] for i in json.loads(plan.read_text())["mission"]["items"]]
    assert commands.count(2000) == 12 and 206 not in commands
    assert len(read_plan(plan)) == 12


def test_imported_lines_before_a_plan_keep_the_camera_at_their_photos(tmp_path, example):
    E0, N0 = 512000.0, 5406000.0
    project = dataclasses.replace(example, trajectory=dataclasses.replace(
        example.trajectory, exterior_orientations=photos_in_lines("p4p", E0, N0, 60.0)))
    stations, _ = planned(example, EXAMPLE.parent)
    out = tmp_path / "mixed.plan"
    spec = export_flight(project, EXAMPLE.parent, "qgc", out)
    planned_lines = len({s.line_index for s in stations})
    assert len(spec.lines) == 3 + planned_lines
    assert [[e.name for e in line] for line in spec.lines[:3]] == [
        [f"IMG_{k:03d}.png" for k in range(4 * n, 4 * n + 4)] for n in range(3)]
    commands = [i["command"] for i in json.loads(out.read_text())["mission"]["items"]]
    # the trigger distance is the plan's: it runs on the plan's lines only
    assert commands.count(206) == 2 * planned_lines and commands.count(2000) == 12
    assert len(read_plan(out)) == 12 + len(stations)
