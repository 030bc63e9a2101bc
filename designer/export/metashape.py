"""Agisoft Metashape inputs: camera calibration XML and reference CSVs (cameras, markers).

Conventions at this boundary (Metashape User Manual, Appendix C "Camera models", as
implemented by glimpse: ezwelty/glimpse glimpse/convert/converters/agisoft.py;
nerfstudio process_data/metashape_utils.py; Agisoft forum on ω φ κ axes):

* camera frame: Metashape projects in the CV frame (X right, Y down, Z forward);
  x = X/Z, y = Y/Z, r² = x² + y²,
  x' = x(1 + K1 r² + K2 r⁴ + K3 r⁶ + K4 r⁸) + P1 (r² + 2x²) + 2 P2 x y,
  y' = y(1 + K1 r² + K2 r⁴ + K3 r⁶ + K4 r⁸) + P2 (r² + 2y²) + 2 P1 x y,
  u = W/2 + cx + x' (f + B1) + y' B2,  v = H/2 + cy + y' f.
* coefficient swap: Metashape's P1 multiplies (r² + 2x²), which is OpenCV's p2, so
  <p1> = OpenCV p2 and <p2> = OpenCV p1. K1..K3 are OpenCV's k1..k3 (K4 = 0).
* pixel origin: u = W/2 + cx puts the principal point at the image centre when
  cx = 0, i.e. Metashape's pixel coordinates have their origin at the top-left
  CORNER, like designer's: <cx> = cx_px − W/2, <cy> = cy_px − H/2 (pixels, offsets of
  the principal point from the image centre) and marker projections need no shift.
  Pinned by a round-trip test against the formula above.
* focal length: <f> = fy in pixels; non-square pixels go to <b1> = fx − fy (left out
  when it is only rounding noise, |fx − fy| <= 1e-14 fy).
* fisheye: <projection>fisheye</projection>; Appendix C's fisheye model divides x, y
  by r/atan(r) before the same polynomial, which with P1 = P2 = 0 is OpenCV's
  equidistant model, so <k1>..<k4> = OpenCV fisheye k1..k4.
* reference CSV: comma separated, '#' comment lines first (the last one names the
  columns, like Metashape's own export), coordinates in the given CRS in metres
  (X = Easting, Y = Northing, Z = height), angles ω φ κ in degrees: in Metashape set
  Reference Settings → Rotation angles to "Omega, Phi, Kappa". ω φ κ use the classical
  camera axes (x right, y image top, z backwards), R = Rx(ω)·Ry(φ)·Rz(κ) camera →
  world — designer's definition, so angles pass through unchanged.
* numbers: exact shortest repr of each float64.

Markers XML (``markers.xml``: Reference pane → Import Markers, or File → Import →
Markers) follows the chunk XML Metashape itself writes with File → Export → Export
Markers (the layout of its project ``doc.xml``; Metashape Python API Reference:
Marker.reference.location / .accuracy / .enabled and Marker.projections[camera] =
Marker.Projection(coord, pinned)):

* ``<document version="1.2.0"><chunk label="…">``;
* ``<cameras>``: one ``<camera id="k" sensor_id="s" label="IMAGE_STEM"/>`` per image,
  ids 0, 1, … in pose order; labels are the image file names without their extension,
  as Metashape names the cameras it adds (it matches cameras by label);
* ``<markers>``: one ``<marker id="m" label="GCP_ID">`` per GCP with
  ``<reference x y z sx sy sz enabled/>``: SURVEYED coordinates and their standard
  deviations (m); ``enabled="true"`` for control points and ``"false"`` for check
  points — an unticked marker in the Reference pane is a check point (used to score,
  not to georeference);
* a multi-camera rig (:class:`designer.core.truth.CameraSet`): ``<sensors>`` with one
  ``<sensor id="s" label="CAMERA_ID" type="frame">`` per physical camera (its
  ``<resolution>`` and fixed ``<calibration>``, the values of its calibration XML), and
  each camera's ``sensor_id`` is its sensor's; one camera writes one
  ``<sensor id="0" label="camera">`` the same way (the ``sensor_id="0"`` of every
  camera then refers to it). Each sensor's calibration is also written as
  ``calibration_<CAMERA_ID>.xml`` (one camera: ``calibration.xml``) for Tools → Camera
  Calibration → Load;
* ``<frames><frame id="0"><markers>``: per marker ``<marker marker_id="m">`` with one
  ``<location camera_id="k" pinned="true" x y/>`` per image point (pinned = placed by
  hand, i.e. a measured projection). x, y are Metashape pixel coordinates, origin at
  the top-left CORNER (see above): designer's ``uv_px`` unchanged;
* ``<reference>``: the CRS as WKT (pyproj; Metashape stores WKT there), when the
  CRS label can be read, else the label itself.
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from pathlib import Path

import numpy as np
from lxml import etree

from designer.core.distortion import BrownConrady, FisheyeEquidistant
from designer.core.interior import InteriorOrientation
from designer.core.rotation import opk_from_rotation
from designer.core.truth import CameraPose, CameraSet, GcpObservation, GroundControlPoint
from designer.export._text import (
    ExportError,
    check_crs,
    check_unique,
    fmt,
    write_texts,
)

#: |fx − fy| / fy below this is rounding noise, not a pixel aspect: <b1> is left out
#: (leaving it out moves no pixel by more than 1e-14·fy·|x'| < 1e-10 px)
_B1_NOISE = 1e-14


def metashape_calibration_values(interior: InteriorOrientation) -> dict[str, str | float]:
    """{element: value} of Metashape's calibration XML, in document order (see module doc)."""
    W, H = interior.image_size_px
    values: dict[str, str | float] = {"projection": "frame", "width": W, "height": H}
    values["f"] = interior.fy_px
    values["cx"] = interior.cx_px - W / 2
    values["cy"] = interior.cy_px - H / 2
    b1 = interior.fx_px - interior.fy_px
    if abs(b1) > _B1_NOISE * interior.fy_px:  # not just rounding of f·W/sw vs f·H/sh
        values["b1"] = b1
    d = interior.distortion
    if isinstance(d, FisheyeEquidistant):
        values["projection"] = "fisheye"
        values.update(k1=d.k1, k2=d.k2, k3=d.k3, k4=d.k4)
    elif isinstance(d, BrownConrady):
        # Metashape's P1/P2 are OpenCV's p2/p1.
        values.update(k1=d.k1, k2=d.k2, k3=d.k3, p1=d.p2, p2=d.p1)
    elif d is not None:
        raise ExportError(f"no Metashape camera model for distortion {type(d).__name__}")
    return values


def _calibration_element(interior: InteriorOrientation, parent=None) -> etree._Element:
    root = (etree.Element("calibration") if parent is None
            else etree.SubElement(parent, "calibration", type="frame", **{"class": "adjusted"}))
    for tag, value in metashape_calibration_values(interior).items():
        if parent is not None and tag in ("projection", "width", "height"):
            if tag == "width":
                W, H = interior.image_size_px
                etree.SubElement(root, "resolution", width=str(W), height=str(H))
            continue
        if isinstance(value, str):
            text = value
        elif tag in ("width", "height"):
            text = str(int(value))
        else:
            text = fmt(value)
        etree.SubElement(root, tag).text = text
    return root


def metashape_calibration_xml(interior: InteriorOrientation) -> str:
    """Metashape camera calibration XML (Tools → Camera Calibration → Load)."""
    root = _calibration_element(interior)
    # the declaration exactly as Metashape writes it (lxml would use single quotes)
    body = etree.tostring(root, pretty_print=True, encoding="unicode")
    return '<?xml version="1.0" encoding="UTF-8"?>\n' + body


def _accuracy_triple(value, what: str) -> np.ndarray:
    arr = np.broadcast_to(np.asarray(value, dtype=np.float64), (3,)).copy()
    if not (np.isfinite(arr).all() and (arr >= 0).all()):
        raise ExportError(f"{what} must be finite and >= 0, got {value!r}")
    return arr


def metashape_cameras_csv(
    poses: Sequence[CameraPose],
    crs: str,
    position_accuracy_m=None,
    rotation_accuracy_deg=None,
) -> str:
    """Camera reference CSV: Label, X/Easting, Y/Northing, Z/Altitude, Omega, Phi, Kappa.

    Accuracy columns (metres; degrees), scalar or per axis, are added when given.
    """
    crs = check_crs(crs)
    check_unique((p.image_name for p in poses), "image name")
    columns = ["Label", "X/Easting", "Y/Northing", "Z/Altitude", "Omega", "Phi", "Kappa"]
    pos_acc = rot_acc = None
    if position_accuracy_m is not None:
        pos_acc = _accuracy_triple(position_accuracy_m, "position_accuracy_m")
        columns += ["X_accuracy", "Y_accuracy", "Z_accuracy"]
    if rotation_accuracy_deg is not None:
        rot_acc = _accuracy_triple(rotation_accuracy_deg, "rotation_accuracy_deg")
        columns += ["Omega_accuracy", "Phi_accuracy", "Kappa_accuracy"]
    lines = [
        "# designer ground truth for Agisoft Metashape Import Reference: cameras",
        f"# CRS {crs}; X/Easting, Y/Northing, Z/Altitude = perspective centre in metres",
        "# Omega, Phi, Kappa in degrees (Reference Settings: Rotation angles = Omega, Phi, "
        "Kappa); R = Rx(omega)*Ry(phi)*Rz(kappa) maps camera axes (x right, y image top, "
        "z backwards) to the world",
        "#" + ",".join(columns),
    ]
    for pose in poses:
        opk = np.degrees(opk_from_rotation(pose.R_cam_to_world))
        fields = [pose.image_name, *(fmt(v) for v in (*pose.C_world, *opk))]
        for acc in (pos_acc, rot_acc):
            if acc is not None:
                fields += [fmt(v) for v in acc]
        lines.append(",".join(fields))
    return "\n".join(lines) + "\n"


def metashape_markers_csv(gcps: Sequence[GroundControlPoint], crs: str) -> str:
    """Marker reference CSV: Label, X/Easting, Y/Northing, Z/Altitude, accuracies, Role.

    Coordinates are the SURVEYED ones, accuracies the survey sigmas (m). Every GCP is
    listed; Metashape uses all imported markers as control, so a comment names the
    check points to untick in the Reference pane.
    """
    crs = check_crs(crs)
    check_unique((g.gcp_id for g in gcps), "GCP id")
    checks = [g.gcp_id for g in gcps if g.role == "check"]
    columns = ["Label", "X/Easting", "Y/Northing", "Z/Altitude",
               "X_accuracy", "Y_accuracy", "Z_accuracy", "Role"]
    lines = [
        "# designer ground truth for Agisoft Metashape Import Reference: markers",
        f"# CRS {crs}; surveyed coordinates and their standard deviations in metres",
        "# check points (untick them in the Reference pane): " + (" ".join(checks) or "none"),
        "#" + ",".join(columns),
    ]
    for g in gcps:
        lines.append(",".join(
            [g.gcp_id, *(fmt(v) for v in (*g.surveyed_xyz, *g.sigma_xyz)), g.role]
        ))
    return "\n".join(lines) + "\n"


def _crs_wkt(crs: str) -> str:
    """The CRS as WKT (Metashape's <reference>), or the label when pyproj cannot read it."""
    from pyproj import CRS
    from pyproj.enums import WktVersion
    from pyproj.exceptions import CRSError

    try:
        return CRS.from_user_input(crs).to_wkt(WktVersion.WKT1_GDAL)
    except CRSError:
        return crs


def metashape_markers_xml(
    poses: Sequence[CameraPose],
    gcps: Sequence[GroundControlPoint],
    observations: Sequence[GcpObservation],
    crs: str,
    cameras: CameraSet | None = None,
    interior: InteriorOrientation | None = None,
) -> str:
    """Markers XML: sensors, cameras, markers with reference and enabled flag (control =
    enabled, check = disabled), and every marker projection (see module doc); with
    ``cameras`` (a rig) one sensor per physical camera, else one sensor of ``interior``
    (without it, the cameras' sensor 0 is left to the project the file is imported
    into)."""
    crs = check_crs(crs)
    check_unique((p.image_name for p in poses), "image name")
    check_unique((g.gcp_id for g in gcps), "GCP id")
    camera_ids = {p.image_name: k for k, p in enumerate(poses)}
    marker_ids = {g.gcp_id: m for m, g in enumerate(gcps)}
    for o in observations:
        if o.image_name not in camera_ids or o.gcp_id not in marker_ids:
            raise ExportError(f"observation of {o.gcp_id!r} in {o.image_name!r}: unknown "
                              "GCP or image")
    doc = etree.Element("document", version="1.2.0")
    chunk = etree.SubElement(doc, "chunk", label="designer ground truth", enabled="true")
    sensor_ids: dict[str, int] = {}
    interiors: dict[str, InteriorOrientation] = {}
    if cameras is not None:
        cameras.covers(p.image_name for p in poses)
        interiors = dict(cameras.interiors)
    elif interior is not None:
        interiors = {SINGLE_SENSOR_LABEL: interior}
    if interiors:
        sensor_ids = {c: k for k, c in enumerate(interiors)}
        sensors = etree.SubElement(chunk, "sensors", next_id=str(len(sensor_ids)))
        for camera_id, k in sensor_ids.items():
            interior = interiors[camera_id]
            W, H = interior.image_size_px
            sensor = etree.SubElement(sensors, "sensor", id=str(k), label=camera_id,
                                      type="frame")
            etree.SubElement(sensor, "resolution", width=str(W), height=str(H))
            etree.SubElement(sensor, "property", name="fixed", value="true")
            _calibration_element(interior, sensor)
    camera_list = etree.SubElement(chunk, "cameras", next_id=str(len(poses)),
                                   next_group_id="0")
    for p in poses:
        sensor_id = 0 if cameras is None else sensor_ids[cameras.camera_of(p.image_name)]
        etree.SubElement(camera_list, "camera", id=str(camera_ids[p.image_name]),
                         sensor_id=str(sensor_id), label=camera_label(p.image_name))
    markers = etree.SubElement(chunk, "markers", next_id=str(len(gcps)), next_group_id="0")
    for g in gcps:
        marker = etree.SubElement(markers, "marker", id=str(marker_ids[g.gcp_id]),
                                  label=g.gcp_id)
        x, y, z = (fmt(v) for v in g.surveyed_xyz)
        sx, sy, sz = (fmt(v) for v in g.sigma_xyz)
        etree.SubElement(marker, "reference", x=x, y=y, z=z, sx=sx, sy=sy, sz=sz,
                         enabled="true" if g.role == "control" else "false")
    frames = etree.SubElement(chunk, "frames", next_id="1")
    frame_markers = etree.SubElement(etree.SubElement(frames, "frame", id="0"), "markers")
    for g in gcps:
        own = [o for o in observations if o.gcp_id == g.gcp_id]
        if not own:
            continue
        marker = etree.SubElement(frame_markers, "marker", marker_id=str(marker_ids[g.gcp_id]))
        for o in own:
            etree.SubElement(marker, "location", camera_id=str(camera_ids[o.image_name]),
                             pinned="true", x=fmt(o.uv_px[0]), y=fmt(o.uv_px[1]))
    etree.SubElement(chunk, "reference").text = _crs_wkt(crs)
    body = etree.tostring(doc, pretty_print=True, encoding="unicode")
    return '<?xml version="1.0" encoding="UTF-8"?>\n' + body


#: the label of the one sensor of a single-camera survey's markers XML
SINGLE_SENSOR_LABEL = "camera"


def camera_label(image_name: str) -> str:
    """The label Metashape gives the camera of an image: its file name without the
    extension (Metashape User Manual, "Adding photos": cameras are named after their
    files; the Reference pane and Import Markers match cameras by this label)."""
    return Path(image_name).stem


def write_metashape_markers_xml(
    path: str | os.PathLike,
    poses: Sequence[CameraPose],
    gcps: Sequence[GroundControlPoint],
    observations: Sequence[GcpObservation],
    crs: str,
) -> Path:
    """Write the markers XML atomically; returns the path."""
    write_texts({path: metashape_markers_xml(poses, gcps, observations, crs)})
    return Path(path)


def write_metashape_calibration(path: str | os.PathLike, interior: InteriorOrientation) -> Path:
    """Write the calibration XML atomically; returns the path."""
    write_texts({path: metashape_calibration_xml(interior)})
    return Path(path)


def write_metashape_cameras(
    path: str | os.PathLike,
    poses: Sequence[CameraPose],
    crs: str,
    position_accuracy_m=None,
    rotation_accuracy_deg=None,
) -> Path:
    """Write the camera reference CSV atomically; returns the path."""
    write_texts(
        {path: metashape_cameras_csv(poses, crs, position_accuracy_m, rotation_accuracy_deg)}
    )
    return Path(path)


def write_metashape_markers(
    path: str | os.PathLike, gcps: Sequence[GroundControlPoint], crs: str
) -> Path:
    """Write the marker reference CSV atomically; returns the path."""
    write_texts({path: metashape_markers_csv(gcps, crs)})
    return Path(path)
