"""QGroundControl ``.plan`` files: the survey as a waypoint mission with a camera trigger.

Format (QGroundControl Developer Guide, "Plan File Format",
https://docs.qgroundcontrol.com/master/en/qgc-dev-guide/file_formats/plan.html; MAVLink
common message set, MAV_CMD and MAV_FRAME, https://mavlink.io/en/messages/common.html):

* top level (JSON): ``fileType`` = "Plan", ``version`` = 1, ``groundStation``,
  ``mission``, ``geoFence`` {circles, polygons, version 2}, ``rallyPoints``
  {points, version 2};
* ``mission``: ``version`` 2, ``firmwareType`` (MAV_AUTOPILOT; 12 = PX4),
  ``vehicleType`` (MAV_TYPE; 2 = quadrotor), ``cruiseSpeed``, ``hoverSpeed`` (m/s),
  ``globalPlanAltitudeMode``, ``plannedHomePosition`` [lat, lon, alt AMSL] and
  ``items`` (at least one);
* a SimpleItem: ``type`` "SimpleItem", ``autoContinue``, ``command``, ``doJumpId``,
  ``frame``, ``params`` (seven numbers or null), and for navigation items
  ``AltitudeMode`` and ``Altitude`` and ``AMSLAltAboveTerrain``. ``AltitudeMode`` and
  ``globalPlanAltitudeMode`` are QGC's ``enum AltMode`` (``QGroundControlQmlGlobal.h`` in
  QGC's repository, src/QmlControls): 0 Mixed (the plan's items differ), 1 Relative
  (frame 3, MAV_FRAME_GLOBAL_RELATIVE_ALT), 2 Absolute (frame 0, MAV_FRAME_GLOBAL),
  3 CalcAboveTerrain (frame 0, the AMSL altitude QGC computed from terrain data in
  ``AMSLAltAboveTerrain``), 4 TerrainFrame (frame 10); QGC's own test plans
  (test/plans/*.plan) pair them so.

Commands written: MAV_CMD_NAV_WAYPOINT (16; params hold, acceptance radius, pass
radius, yaw [deg, true north], latitude, longitude, altitude), MAV_CMD_DO_MOUNT_CONTROL
(205; pitch, roll, yaw relative to the vehicle [deg], …, mode 2 = MAVLink targeting)
before a waypoint whose gimbal attitude changes, MAV_CMD_DO_SET_CAM_TRIGG_DIST (206;
distance [m], shutter, trigger once immediately = 1) after the first waypoint of a line
and with distance 0 after its last, and MAV_CMD_IMAGE_START_CAPTURE (2000; id,
interval 0, total images 1) after a lone waypoint and after each imported photo's
(explicit exterior orientations need not be evenly spaced). The waypoints are the
exposures themselves, one trigger distance apart along a planned line, so the trigger
fires on them.

Frames: 3 = MAV_FRAME_GLOBAL_RELATIVE_ALT (altitude above the take-off point, the
``relative`` choice) and 0 = MAV_FRAME_GLOBAL (AMSL, the ``amsl`` choice). A plan that
follows the terrain writes QGC's "calculated above terrain" items: frame 0 with the AMSL
altitude of each waypoint (project Z + height offset), ``Altitude`` = the height above
the ground below it. Reading accepts frames 0 and 3 (a terrain frame 10 needs QGC's
terrain tiles and is refused).
"""

from __future__ import annotations

import json
import math
from pathlib import Path

from designer.atomic import write_text_atomic
from designer.flight.checks import fail, number
from designer.flight.exposures import FlightSpec, FlownPoint

NAV_WAYPOINT = 16
DO_MOUNT_CONTROL = 205
DO_SET_CAM_TRIGG_DIST = 206
IMAGE_START_CAPTURE = 2000
FRAME_GLOBAL = 0
FRAME_MISSION = 2
FRAME_GLOBAL_RELATIVE_ALT = 3
#: QGC's enum AltMode (see the module docstring)
ALT_MODE_MIXED, ALT_MODE_RELATIVE, ALT_MODE_ABSOLUTE, ALT_MODE_CALC_ABOVE_TERRAIN = 0, 1, 2, 3
ALT_MODE_TERRAIN_FRAME = 4
#: the MAV_FRAME each AltMode of a waypoint goes with, as QGC writes them
ALT_MODE_FRAMES = {ALT_MODE_RELATIVE: FRAME_GLOBAL_RELATIVE_ALT, ALT_MODE_ABSOLUTE: FRAME_GLOBAL,
                   ALT_MODE_CALC_ABOVE_TERRAIN: FRAME_GLOBAL, ALT_MODE_TERRAIN_FRAME: 10}
FIRMWARE_PX4 = 12
VEHICLE_QUADROTOR = 2


def plan_document(spec: FlightSpec) -> dict:
    """The .plan JSON document of a flight (module docstring)."""
    items: list[dict] = []

    def add(command: int, params: list, frame: int = FRAME_MISSION, **extra) -> None:
        items.append({"autoContinue": True, "command": command, "doJumpId": len(items) + 1,
                      "frame": frame, "params": params, "type": "SimpleItem", **extra})

    gimbal = None
    for line in spec.lines:
        for k, e in enumerate(line):
            if gimbal != (e.pitch_deg, e.roll_deg):
                gimbal = (e.pitch_deg, e.roll_deg)
                add(DO_MOUNT_CONTROL, [e.pitch_deg, e.roll_deg, 0.0, 0, 0, 0, 2])
            add(NAV_WAYPOINT, [0, 0, 0, e.yaw_true_deg, e.lat_deg, e.lon_deg,
                               *_altitude(spec, e)[:1]], **_altitude_fields(spec, e))
            if len(line) == 1 or spec.trigger_distance_m is None or not e.planned:
                add(IMAGE_START_CAPTURE, [0, 0, 1, 0, 0, 0, 0])
            elif k == 0:
                add(DO_SET_CAM_TRIGG_DIST, [spec.trigger_distance_m, 0, 1, 0, 0, 0, 0])
            elif k == len(line) - 1:
                add(DO_SET_CAM_TRIGG_DIST, [0, 0, 0, 0, 0, 0, 0])
    mode = (ALT_MODE_CALC_ABOVE_TERRAIN if spec.terrain_following else
            ALT_MODE_RELATIVE if spec.altitude == "relative" else ALT_MODE_ABSOLUTE)
    return {
        "fileType": "Plan", "version": 1, "groundStation": "designer",
        "geoFence": {"circles": [], "polygons": [], "version": 2},
        "rallyPoints": {"points": [], "version": 2},
        "mission": {
            "version": 2, "firmwareType": FIRMWARE_PX4, "vehicleType": VEHICLE_QUADROTOR,
            "cruiseSpeed": spec.speed_m_s, "hoverSpeed": spec.speed_m_s,
            "globalPlanAltitudeMode": mode,
            "plannedHomePosition": [spec.takeoff_lat_deg, spec.takeoff_lon_deg,
                                    spec.absolute_height(spec.takeoff_Z_m)],
            "items": items,
        },
    }


def _altitude(spec: FlightSpec, e) -> tuple[float, int]:
    if spec.terrain_following or spec.altitude == "amsl":
        return spec.absolute_height(e.Z_m), FRAME_GLOBAL
    return spec.relative_height(e.Z_m), FRAME_GLOBAL_RELATIVE_ALT


def _altitude_fields(spec: FlightSpec, e) -> dict:
    value, frame = _altitude(spec, e)
    if spec.terrain_following:
        return {"frame": frame, "AltitudeMode": ALT_MODE_CALC_ABOVE_TERRAIN,
                "Altitude": e.Z_m - e.ground_m, "AMSLAltAboveTerrain": value}
    return {"frame": frame,
            "AltitudeMode": (ALT_MODE_RELATIVE if frame == FRAME_GLOBAL_RELATIVE_ALT
                             else ALT_MODE_ABSOLUTE),
            "Altitude": value, "AMSLAltAboveTerrain": None}


def write_plan(spec: FlightSpec, path: Path) -> Path:
    """Check and write the .plan atomically."""
    doc = plan_document(spec)
    check_plan(doc, str(path))
    write_text_atomic(path, json.dumps(doc, indent=4) + "\n")
    return Path(path)


# ------------------------------------------------------------------------ checks, reading
def check_plan(doc, source: str) -> None:
    """The documented required fields and types (module docstring); FlightFileError."""
    if not isinstance(doc, dict):
        raise fail(source, "", "the file is not a JSON object", "give a QGroundControl .plan")
    for key, kind in (("fileType", str), ("version", int), ("groundStation", str),
                      ("mission", dict)):
        if not isinstance(doc.get(key), kind):
            raise fail(source, key, f"missing or not a {kind.__name__}",
                       "write the top-level keys of the Plan File Format")
    if doc["fileType"] != "Plan" or doc["version"] != 1:
        raise fail(source, "fileType/version", f"{doc['fileType']!r} version {doc['version']}",
                   "a .plan has fileType 'Plan' and version 1")
    mission = doc["mission"]
    for key in ("version", "firmwareType", "vehicleType", "cruiseSpeed", "hoverSpeed",
                "plannedHomePosition", "items"):
        if key not in mission:
            raise fail(source, f"mission.{key}", "missing", "add it (Plan File Format)")
    home = mission["plannedHomePosition"]
    if not (isinstance(home, list) and len(home) == 3):
        raise fail(source, "mission.plannedHomePosition", "must be [lat, lon, alt]",
                   "write three numbers")
    for k, v in enumerate(home):
        number(v, source, f"mission.plannedHomePosition[{k}]", "value")
    items = mission["items"]
    if not (isinstance(items, list) and items):
        raise fail(source, "mission.items", "no mission items", "a plan needs at least one")
    for k, item in enumerate(items):
        place = f"mission.items[{k}]"
        if not isinstance(item, dict) or item.get("type") not in ("SimpleItem", "ComplexItem"):
            raise fail(source, place, "type must be SimpleItem or ComplexItem",
                       "write a mission item object")
        if item["type"] == "ComplexItem":
            continue
        for key, kind in (("autoContinue", bool), ("command", int), ("doJumpId", int),
                          ("frame", int), ("params", list)):
            if not isinstance(item.get(key), kind):
                raise fail(source, f"{place}.{key}", f"missing or not {kind.__name__}",
                           "write every SimpleItem field")
        if len(item["params"]) != 7:
            raise fail(source, f"{place}.params", f"{len(item['params'])} values",
                       "a mission item has seven params")


def read_plan(path: Path, height_offset_m: float = 0.0) -> list[FlownPoint]:
    """The photo positions of a .plan written as above: waypoints where the camera fires.

    Heights come back as project heights: frame 3 altitudes + home altitude, frame 0
    altitudes as they are, both minus ``height_offset_m``.
    """
    source = str(path)
    try:
        doc = json.loads(Path(path).read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as error:
        raise fail(source, "", f"cannot read the plan ({error})",
                   "give a .plan JSON file") from None
    check_plan(doc, source)
    mission = doc["mission"]
    home_alt = float(mission["plannedHomePosition"][2])
    points: list[FlownPoint] = []
    pitch, roll, yaw_rel = -90.0, 0.0, 0.0
    last = None  # the last waypoint, as a FlownPoint
    photo_taken = False
    triggering = False
    for k, item in enumerate(mission["items"]):
        if item["type"] != "SimpleItem":
            raise fail(source, f"mission.items[{k}]", "complex items (surveys drawn in QGC) "
                       "are not read", "export the plan from designer or flatten it in QGC")
        place = f"mission.items[{k}]"
        p = [None if v is None else number(v, source, place, "param") for v in item["params"]]
        command = item["command"]
        if command == DO_MOUNT_CONTROL:
            pitch, roll, yaw_rel = p[0] or 0.0, p[1] or 0.0, p[2] or 0.0
        elif command == NAV_WAYPOINT:
            frame = item["frame"]
            if frame not in (FRAME_GLOBAL, FRAME_GLOBAL_RELATIVE_ALT):
                raise fail(source, f"{place}.frame", f"frame {frame} is not read",
                           "use frame 0 (AMSL) or 3 (relative to home)")
            alt = p[6] + (home_alt if frame == FRAME_GLOBAL_RELATIVE_ALT else 0.0)
            yaw = (p[3] if p[3] is not None and math.isfinite(p[3]) else 0.0) + yaw_rel
            last = FlownPoint(None, p[5], p[4], alt - height_offset_m, yaw, pitch, roll)
            photo_taken = False
            if triggering:
                points.append(last)
                photo_taken = True
        elif command == DO_SET_CAM_TRIGG_DIST:
            triggering = (p[0] or 0.0) > 0
            if triggering and p[2] == 1 and last is not None and not photo_taken:
                points.append(last)
                photo_taken = True
        elif command == IMAGE_START_CAPTURE and last is not None and not photo_taken:
            points.append(last)
            photo_taken = True
    return points
