"""DJI WPML route files (KMZ with ``wpmz/template.kml`` and ``wpmz/waylines.wpml``) for
DJI Pilot 2 and FlightHub 2.

Format (DJI Cloud API, "DJI WPML": Overview, template.kml, waylines.wpml and Common
Elements, https://developer.dji.com/doc/cloud-api-tutorial/en/api-reference/dji-wpml/):

* a KMZ (ZIP) holding ``wpmz/template.kml`` (the editable template) and
  ``wpmz/waylines.wpml`` (what the aircraft executes); both are KML 2.2 documents with
  the extension namespace ``http://www.dji.com/wpmz/1.0.x`` (written: 1.0.2);
* ``wpml:missionConfig`` (both files, required): flyToWaylineMode, finishAction,
  exitOnRCLost, executeRCLostAction, takeOffSecurityHeight, globalTransitionalSpeed,
  globalRTHHeight (return-to-home height, m above the take-off point), droneInfo
  (droneEnumValue, droneSubEnumValue) and payloadInfo; the template may add
  ``takeOffRefPoint`` "lat,lon,height" (height above the WGS 84 ellipsoid);
* template ``Folder``: templateType ("waypoint"), templateId,
  waylineCoordinateSysParam (coordinateMode WGS84; heightMode EGM96,
  relativeToStartPoint, aboveGroundLevel or realTimeFollowSurface), autoFlightSpeed;
  its ``Placemark``s: Point, index, ellipsoidHeight, height, useGlobal* switches, and
  gimbalPitchAngle where the folder's gimbalPitchMode is usePointSetting;
* waylines ``Folder``: templateId, waylineId, executeHeightMode (WGS84 = ellipsoidal
  height, relativeToStartPoint, realTimeFollowSurface = above the surface measured in
  flight), autoFlightSpeed; its ``Placemark``s: Point ``lon,lat``, index,
  executeHeight, waypointSpeed, waypointHeadingParam (waypointHeadingMode,
  waypointHeadingAngle in degrees from TRUE north, −180..180), waypointTurnParam;
* ``wpml:actionGroup`` (actionGroupId, actionGroupStartIndex/EndIndex,
  actionGroupMode, actionTrigger/actionTriggerType ``reachPoint``) with actions
  ``gimbalRotate`` (gimbalHeadingYawBase north, gimbalRotateMode absoluteAngle,
  pitch/roll/yaw angles and their enables, payloadPositionIndex) then ``takePhoto``.

Heights written: ``amsl`` → waylines WGS84 with project Z + height offset (the offset is
the geoid undulation when the project's Z is orthometric) and template EGM96 with Z;
``relative`` → relativeToStartPoint with Z − take-off height; a terrain-following plan
→ per-waypoint heights (DJI documents realTimeFollowSurface for mapping templates only,
not for a waypoint template): waylines WGS84 with each waypoint's project Z + height
offset, template aboveGroundLevel with its height above the project's terrain. The drone
and payload enumeration values (Cloud API "Product Support") follow the camera: the
Zenmuse P1 preset flies on an M350 RTK (89 / payload 50), anything else is declared as
a Mavic 3E (77 / payload 66) — change it in Pilot 2 for another aircraft.
"""

from __future__ import annotations

import io
import math
import re
import time
import zipfile
from collections.abc import Callable
from pathlib import Path

from lxml import etree

from designer.atomic import write_bytes_atomic
from designer.flight.checks import fail, number
from designer.flight.exposures import FlightSpec, FlownPoint
from designer.flight.kml import KML_NS, parse_coordinates
from designer.project.camera_presets import matching_preset

WPML_NS = "http://www.dji.com/wpmz/1.0.2"
_NS_RE = re.compile(r"^http://www\.dji\.com/wpmz/1\.0\.\d+$")
_K = f"{{{KML_NS}}}"
TEMPLATE = "wpmz/template.kml"
WAYLINES = "wpmz/waylines.wpml"
#: the lowest return-to-home height written (m above the take-off point)
MIN_RTH_HEIGHT_M = 20
EXECUTE_HEIGHT_MODES = ("WGS84", "relativeToStartPoint", "realTimeFollowSurface")
TEMPLATE_HEIGHT_MODES = ("EGM96", "relativeToStartPoint", "aboveGroundLevel",
                         "realTimeFollowSurface")
_DRONES = {"p1": (89, 0, 50)}
_DEFAULT_DRONE = (77, 0, 66)


class _Writer:
    def __init__(self, ns: str = WPML_NS):
        self.ns = ns

    def el(self, parent, tag: str, text=None):
        if tag.startswith("wpml:"):
            name = f"{{{self.ns}}}{tag[5:]}"
        else:
            name = _K + tag
        node = etree.SubElement(parent, name)
        if text is not None:
            node.text = text if isinstance(text, str) else _num(text)
        return node

    def tree(self, pairs: dict, parent):
        for key, value in pairs.items():
            if isinstance(value, dict):
                self.tree(value, self.el(parent, key))
            else:
                self.el(parent, key, value)


def _num(v) -> str:
    return str(int(v)) if isinstance(v, bool | int) else repr(float(v))


def _modes(spec: FlightSpec) -> tuple[str, str]:
    """(waylines executeHeightMode, template heightMode). Terrain following is flown as
    per-waypoint heights: the planner already put each waypoint its height above the
    project's terrain, so the aircraft gets their ellipsoidal heights (WGS84) and the
    template their heights above ground (aboveGroundLevel); DJI documents
    realTimeFollowSurface for mapping templates only."""
    if spec.terrain_following:
        return "WGS84", "aboveGroundLevel"
    if spec.altitude == "relative":
        return "relativeToStartPoint", "relativeToStartPoint"
    return "WGS84", "EGM96"


def _execute_height(spec: FlightSpec, e) -> float:
    if spec.terrain_following:
        return spec.absolute_height(e.Z_m)
    if spec.altitude == "relative":
        return spec.relative_height(e.Z_m)
    return spec.absolute_height(e.Z_m)


def _template_height(spec: FlightSpec, e) -> float:
    if spec.terrain_following:
        return e.Z_m - e.ground_m
    return e.Z_m if _modes(spec)[1] == "EGM96" else _execute_height(spec, e)


def _mission_config(spec: FlightSpec, template: bool) -> dict:
    preset = matching_preset(spec.camera)
    drone, sub, payload = _DRONES.get(preset.key if preset else "", _DEFAULT_DRONE)
    config = {
        "wpml:flyToWaylineMode": "safely", "wpml:finishAction": "goHome",
        "wpml:exitOnRCLost": "executeLostAction", "wpml:executeRCLostAction": "goBack",
        "wpml:takeOffSecurityHeight": 20,
        "wpml:globalTransitionalSpeed": spec.speed_m_s,
        # return-to-home height above the take-off point (required): the route's
        # highest photo rounded up, at least the take-off security height
        "wpml:globalRTHHeight": _rth_height_m(spec),
    }
    if template:
        config["wpml:takeOffRefPoint"] = (
            f"{spec.takeoff_lat_deg!r},{spec.takeoff_lon_deg!r},"
            f"{spec.absolute_height(spec.takeoff_Z_m)!r}")
    config["wpml:droneInfo"] = {"wpml:droneEnumValue": drone, "wpml:droneSubEnumValue": sub}
    config["wpml:payloadInfo"] = {"wpml:payloadEnumValue": payload,
                                  "wpml:payloadPositionIndex": 0}
    return config


def _rth_height_m(spec: FlightSpec) -> int:
    highest = max(spec.relative_height(e.Z_m) for e in spec.exposures)
    return max(MIN_RTH_HEIGHT_M, math.ceil(highest))


def _heading(e) -> dict:
    return {"wpml:waypointHeadingMode": "smoothTransition",
            "wpml:waypointHeadingAngle": e.yaw_true_deg,
            "wpml:waypointPoiPoint": "0.000000,0.000000,0.000000",
            "wpml:waypointHeadingPathMode": "followBadArc"}


def _actions(k: int, e) -> dict:
    gimbal = {
        "wpml:gimbalHeadingYawBase": "north", "wpml:gimbalRotateMode": "absoluteAngle",
        "wpml:gimbalPitchRotateEnable": 1, "wpml:gimbalPitchRotateAngle": e.pitch_deg,
        "wpml:gimbalRollRotateEnable": 1, "wpml:gimbalRollRotateAngle": e.roll_deg,
        "wpml:gimbalYawRotateEnable": 1, "wpml:gimbalYawRotateAngle": e.yaw_true_deg,
        "wpml:gimbalRotateTimeEnable": 0, "wpml:gimbalRotateTime": 0,
        "wpml:payloadPositionIndex": 0}
    photo = {"wpml:payloadPositionIndex": 0, "wpml:fileSuffix": Path(e.name).stem,
             "wpml:useGlobalPayloadLensIndex": 0}
    return {"wpml:actionGroupId": k, "wpml:actionGroupStartIndex": k,
            "wpml:actionGroupEndIndex": k, "wpml:actionGroupMode": "sequence",
            "wpml:actionTrigger": {"wpml:actionTriggerType": "reachPoint"}}, gimbal, photo


def _add_actions(w: _Writer, pm, k: int, e) -> None:
    head, gimbal, photo = _actions(k, e)
    group = w.el(pm, "wpml:actionGroup")
    w.tree(head, group)
    for action_id, (func, params) in enumerate((("gimbalRotate", gimbal),
                                                ("takePhoto", photo))):
        action = w.el(group, "wpml:action")
        w.el(action, "wpml:actionId", action_id)
        w.el(action, "wpml:actionActuatorFunc", func)
        w.tree(params, w.el(action, "wpml:actionActuatorFuncParam"))


def _document(w: _Writer):
    root = etree.Element(_K + "kml", nsmap={None: KML_NS, "wpml": w.ns})
    return root, w.el(root, "Document")


def template_kml(spec: FlightSpec) -> bytes:
    w = _Writer()
    root, doc = _document(w)
    now_ms = int(time.time() * 1000)
    w.tree({"wpml:author": "designer", "wpml:createTime": now_ms, "wpml:updateTime": now_ms,
            "wpml:missionConfig": _mission_config(spec, True)}, doc)
    folder = w.el(doc, "Folder")
    w.tree({"wpml:templateType": "waypoint", "wpml:templateId": 0,
            "wpml:waylineCoordinateSysParam": {"wpml:coordinateMode": "WGS84",
                                               "wpml:heightMode": _modes(spec)[1]},
            "wpml:autoFlightSpeed": spec.speed_m_s,
            "wpml:globalHeight": _template_height(spec, spec.exposures[0]),
            "wpml:caliFlightEnable": 0, "wpml:gimbalPitchMode": "usePointSetting",
            "wpml:globalWaypointHeadingParam": _heading(spec.exposures[0]),
            "wpml:globalWaypointTurnMode": "toPointAndStopWithDiscontinuityCurvature",
            "wpml:globalUseStraightLine": 1}, folder)
    for k, e in enumerate(spec.exposures):
        pm = w.el(folder, "Placemark")
        w.el(w.el(pm, "Point"), "coordinates", f"{e.lon_deg!r},{e.lat_deg!r}")
        w.tree({"wpml:index": k, "wpml:ellipsoidHeight": spec.absolute_height(e.Z_m),
                "wpml:height": _template_height(spec, e), "wpml:useGlobalHeight": 0,
                "wpml:useGlobalSpeed": 1, "wpml:useGlobalHeadingParam": 0,
                "wpml:waypointHeadingParam": _heading(e), "wpml:useGlobalTurnParam": 1,
                "wpml:useStraightLine": 1,
                # required with the folder's gimbalPitchMode usePointSetting
                "wpml:gimbalPitchAngle": e.pitch_deg}, pm)
        _add_actions(w, pm, k, e)
    w.tree({"wpml:payloadParam": {"wpml:payloadPositionIndex": 0,
                                  "wpml:imageFormat": "visable"}}, folder)
    return etree.tostring(root, xml_declaration=True, encoding="UTF-8", pretty_print=True)


def waylines_wpml(spec: FlightSpec) -> bytes:
    w = _Writer()
    root, doc = _document(w)
    w.tree({"wpml:missionConfig": _mission_config(spec, False)}, doc)
    folder = w.el(doc, "Folder")
    w.tree({"wpml:templateId": 0, "wpml:executeHeightMode": _modes(spec)[0],
            "wpml:waylineId": 0, "wpml:autoFlightSpeed": spec.speed_m_s}, folder)
    for k, e in enumerate(spec.exposures):
        pm = w.el(folder, "Placemark")
        w.el(w.el(pm, "Point"), "coordinates", f"{e.lon_deg!r},{e.lat_deg!r}")
        w.tree({"wpml:index": k, "wpml:executeHeight": _execute_height(spec, e),
                "wpml:waypointSpeed": spec.speed_m_s, "wpml:waypointHeadingParam": _heading(e),
                "wpml:waypointTurnParam": {
                    "wpml:waypointTurnMode": "toPointAndStopWithDiscontinuityCurvature",
                    "wpml:waypointTurnDampingDist": 0},
                "wpml:useStraightLine": 1}, pm)
        _add_actions(w, pm, k, e)
    return etree.tostring(root, xml_declaration=True, encoding="UTF-8", pretty_print=True)


def write_wpml(spec: FlightSpec, path: Path) -> Path:
    """Check and write the KMZ atomically."""
    files = {TEMPLATE: template_kml(spec), WAYLINES: waylines_wpml(spec)}
    for name, data in files.items():
        check_wpml(etree.fromstring(data), f"{path}:{name}", name == TEMPLATE)
    buffer = io.BytesIO()
    with zipfile.ZipFile(buffer, "w", zipfile.ZIP_DEFLATED) as z:
        for name, data in files.items():
            z.writestr(name, data)
    write_bytes_atomic(path, buffer.getvalue())
    return Path(path)


# ------------------------------------------------------------------------ checks, reading
_MISSION_REQUIRED = ("flyToWaylineMode", "finishAction", "exitOnRCLost",
                     "takeOffSecurityHeight", "globalTransitionalSpeed", "globalRTHHeight",
                     "droneInfo")
_TEMPLATE_FOLDER = ("templateType", "templateId", "waylineCoordinateSysParam",
                    "autoFlightSpeed")
_WAYLINES_FOLDER = ("templateId", "executeHeightMode", "waylineId", "autoFlightSpeed")
_WAYLINES_PLACEMARK = ("index", "executeHeight", "waypointSpeed", "waypointHeadingParam",
                       "waypointTurnParam")


def _wpml_ns(root, source: str) -> str:
    ns = root.nsmap.get("wpml")
    if root.tag != _K + "kml" or not ns or not _NS_RE.match(ns):
        raise fail(source, "root", "not a KML 2.2 document with the wpml namespace",
                   "the root is <kml> declaring xmlns:wpml=\"http://www.dji.com/wpmz/1.0.x\"")
    return ns


def check_wpml(root, source: str, template: bool) -> None:
    """The required elements of the DJI WPML documents (module docstring)."""
    W = f"{{{_wpml_ns(root, source)}}}"
    doc = root.find(_K + "Document")
    if doc is None:
        raise fail(source, "kml", "no Document", "put missionConfig and Folder in <Document>")
    config = doc.find(W + "missionConfig")
    if config is None:
        raise fail(source, "Document", "no wpml:missionConfig", "add the mission config")
    for tag in _MISSION_REQUIRED:
        if config.find(W + tag) is None:
            raise fail(source, "wpml:missionConfig", f"no wpml:{tag}", "add it (DJI WPML)")
    if config.findtext(f"{W}droneInfo/{W}droneEnumValue") is None:
        raise fail(source, "wpml:droneInfo", "no wpml:droneEnumValue", "name the aircraft")
    folders = doc.findall(_K + "Folder")
    if not folders:
        raise fail(source, "Document", "no Folder", "add the route's <Folder>")
    for folder in folders:
        place = f"line {folder.sourceline} <Folder>"
        for tag in _TEMPLATE_FOLDER if template else _WAYLINES_FOLDER:
            if folder.find(W + tag) is None:
                raise fail(source, place, f"no wpml:{tag}", "add it (DJI WPML)")
        mode = (folder.findtext(f"{W}waylineCoordinateSysParam/{W}heightMode") if template
                else folder.findtext(W + "executeHeightMode"))
        allowed = TEMPLATE_HEIGHT_MODES if template else EXECUTE_HEIGHT_MODES
        if mode not in allowed:
            raise fail(source, place, f"height mode {mode!r}", f"use one of {', '.join(allowed)}")
        for pm in folder.findall(_K + "Placemark"):
            pplace = f"line {pm.sourceline} <Placemark>"
            coords = pm.findtext(f"{_K}Point/{_K}coordinates")
            if coords is None:
                raise fail(source, pplace, "no Point/coordinates", "give lon,lat")
            parse_coordinates(coords, source, pplace)
            for tag in ("index",) if template else _WAYLINES_PLACEMARK:
                if pm.find(W + tag) is None:
                    raise fail(source, pplace, f"no wpml:{tag}", "add it (DJI WPML)")
            if (template and folder.findtext(W + "gimbalPitchMode") == "usePointSetting"
                    and pm.find(W + "gimbalPitchAngle") is None):
                raise fail(source, pplace, "no wpml:gimbalPitchAngle",
                           "give each waypoint's gimbal pitch (gimbalPitchMode "
                           "usePointSetting needs it, DJI WPML)")


def read_wpml(
    path: Path, height_offset_m: float = 0.0,
    ground_at: Callable[[float, float], float] | None = None,
) -> list[FlownPoint]:
    """The photo waypoints of a WPML KMZ (waylines.wpml, take-off from template.kml).

    ``ground_at(lon, lat)`` gives the project height of the ground, needed for
    realTimeFollowSurface routes. Heights come back as project heights.
    """
    source = str(path)
    try:
        with zipfile.ZipFile(path) as z:
            names = set(z.namelist())
            for need in (TEMPLATE, WAYLINES):
                if need not in names:
                    raise fail(source, need, "missing from the KMZ",
                               "a WPML route holds wpmz/template.kml and wpmz/waylines.wpml")
            parser = etree.XMLParser(resolve_entities=False)
            template = etree.fromstring(z.read(TEMPLATE), parser)
            waylines = etree.fromstring(z.read(WAYLINES), parser)
    except (OSError, zipfile.BadZipFile, etree.XMLSyntaxError) as error:
        raise fail(source, "", f"cannot read the KMZ ({error})", "give a DJI WPML .kmz") from None
    check_wpml(template, f"{source}:{TEMPLATE}", True)
    check_wpml(waylines, f"{source}:{WAYLINES}", False)
    W = f"{{{waylines.nsmap['wpml']}}}"
    WT = f"{{{template.nsmap['wpml']}}}"
    ref = template.findtext(f"{_K}Document/{WT}missionConfig/{WT}takeOffRefPoint")
    src = f"{source}:{WAYLINES}"
    points = []
    for folder in waylines.find(_K + "Document").findall(_K + "Folder"):
        mode = folder.findtext(W + "executeHeightMode")
        for pm in folder.findall(_K + "Placemark"):
            place = f"line {pm.sourceline} <Placemark>"
            lon, lat, _ = parse_coordinates(pm.findtext(f"{_K}Point/{_K}coordinates"),
                                            src, place)[0]
            h = number(pm.findtext(W + "executeHeight"), src, place, "executeHeight")
            if mode == "WGS84":
                Z = h - height_offset_m
            elif mode == "relativeToStartPoint":
                if ref is None:
                    raise fail(source, TEMPLATE, "no wpml:takeOffRefPoint for relative heights",
                               "add 'lat,lon,height' of the take-off point")
                Z = h + number(ref.split(",")[-1], source, "takeOffRefPoint",
                               "height") - height_offset_m
            else:
                if ground_at is None:
                    raise fail(src, place, "heights follow the surface",
                               "give the terrain to turn them into project heights")
                Z = h + ground_at(lon, lat)
            gimbal = None
            for action in pm.iter(W + "action"):
                if action.findtext(W + "actionActuatorFunc") == "gimbalRotate":
                    gimbal = action.find(W + "actionActuatorFuncParam")
            yaw = number(pm.findtext(f"{W}waypointHeadingParam/{W}waypointHeadingAngle"),
                         src, place, "waypointHeadingAngle")
            pitch, roll = -90.0, 0.0
            if gimbal is not None:
                def angle(name, default, gimbal=gimbal, place=place):
                    if gimbal.findtext(W + f"gimbal{name}RotateEnable") != "1":
                        return default
                    return number(gimbal.findtext(W + f"gimbal{name}RotateAngle"), src, place,
                                  f"gimbal{name}RotateAngle")
                pitch, roll, yaw = angle("Pitch", pitch), angle("Roll", roll), angle("Yaw", yaw)
            name = None
            for action in pm.iter(W + "action"):
                if action.findtext(W + "actionActuatorFunc") == "takePhoto":
                    name = action.findtext(f"{W}actionActuatorFuncParam/{W}fileSuffix")
            points.append(FlownPoint(name, lon, lat, Z, yaw, pitch, roll))
    return points
