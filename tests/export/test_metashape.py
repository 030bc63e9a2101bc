from pathlib import Path

import numpy as np
import pytest
from lxml import etree

from designer.core.distortion import BrownConrady
from designer.core.interior import InteriorOrientation
from designer.core.projection import R_cv_from_world
from designer.core.rotation import rotation_from_opk
from designer.export.metashape import (
    metashape_calibration_xml,
    metashape_cameras_csv,
    metashape_markers_csv,
)
from tests.synthetic import LENSES, interior_for, survey


def parse_calibration(xml: str) -> dict[str, str]:
    root = etree.fromstring(xml.encode("utf-8"))
    assert root.tag == "calibration"
    return {child.tag: child.text for child in root}


def metashape_project(calib: dict[str, str], x_cv: np.ndarray) -> np.ndarray:
    """Pixel coordinates of CV-frame points (N, 3) by Metashape's Appendix C camera model.

    Written from the manual's formulas, independently of designer's distortion code.
    """
    get = {k: float(calib.get(k, 0.0)) for k in
           ("f", "cx", "cy", "b1", "b2", "k1", "k2", "k3", "k4", "p1", "p2")}
    W, H = int(calib["width"]), int(calib["height"])
    x = x_cv[:, 0] / x_cv[:, 2]
    y = x_cv[:, 1] / x_cv[:, 2]
    if calib["projection"] == "fisheye":
        r = np.hypot(x, y)
        scale = np.arctan(r) / r
        x, y = x * scale, y * scale
    else:
        assert calib["projection"] == "frame"
    r2 = x * x + y * y
    radial = 1 + get["k1"] * r2 + get["k2"] * r2**2 + get["k3"] * r2**3 + get["k4"] * r2**4
    xd = x * radial + get["p1"] * (r2 + 2 * x * x) + 2 * get["p2"] * x * y
    yd = y * radial + get["p2"] * (r2 + 2 * y * y) + 2 * get["p1"] * x * y
    u = W * 0.5 + get["cx"] + xd * (get["f"] + get["b1"]) + yd * get["b2"]
    v = H * 0.5 + get["cy"] + yd * get["f"]
    return np.column_stack([u, v])


def test_p1_p2_are_swapped_against_opencv():
    interior = InteriorOrientation(8.8, 13.2, 8.8, 5472, 3648,
                                   distortion=BrownConrady(k1=-0.1, p1=1e-3, p2=-2e-4))
    calib = parse_calibration(metashape_calibration_xml(interior))
    assert float(calib["p1"]) == -2e-4  # OpenCV p2
    assert float(calib["p2"]) == 1e-3  # OpenCV p1
    assert float(calib["k1"]) == -0.1


def test_principal_point_is_an_offset_from_the_image_centre_in_pixels():
    interior = interior_for("opencv")
    calib = parse_calibration(metashape_calibration_xml(interior))
    W, H = interior.image_size_px
    assert (int(calib["width"]), int(calib["height"])) == (W, H)
    assert float(calib["cx"]) == interior.cx_px - W / 2
    assert float(calib["cy"]) == interior.cy_px - H / 2
    # x0 = +0.0513 mm right, y0 = -0.0371 mm (down) → cx > 0, cy > 0 (v grows down)
    assert float(calib["cx"]) == pytest.approx(0.0513 / interior.pixel_pitch_x_mm)
    assert float(calib["cy"]) == pytest.approx(0.0371 / interior.pixel_pitch_y_mm)
    assert float(calib["f"]) == interior.fy_px and "b1" not in calib


@pytest.mark.parametrize("lens", LENSES)
def test_appendix_c_projection_of_the_xml_equals_designers(lens):
    interior, poses, gcps, obs = survey(30, lens)
    calib = parse_calibration(metashape_calibration_xml(interior))
    assert calib["projection"] == ("fisheye" if lens == "fisheye" else "frame")
    if lens == "nonsquare":
        assert float(calib["b1"]) == pytest.approx(interior.fx_px - interior.fy_px)
    by_image = {p.image_name: p for p in poses}
    true_xyz = {g.gcp_id: g.true_xyz for g in gcps}
    for o in obs:
        pose = by_image[o.image_name]
        x_cv = R_cv_from_world(pose.R_cam_to_world) @ (true_xyz[o.gcp_id] - pose.C_world)
        uv = metashape_project(calib, x_cv[None])[0]
        np.testing.assert_allclose(uv, o.uv_px, rtol=0, atol=1e-8)


def test_cameras_csv_says_opk_degrees_and_round_trips():
    _interior, poses, _gcps, _obs = survey(31)
    text = metashape_cameras_csv(poses, "EPSG:32632", position_accuracy_m=[0.02, 0.02, 0.05],
                                 rotation_accuracy_deg=0.1)
    comments = [ln for ln in text.splitlines() if ln.startswith("#")]
    assert any("Omega, Phi, Kappa" in c and "degrees" in c for c in comments)
    assert any("EPSG:32632" in c for c in comments)
    assert comments[-1] == ("#Label,X/Easting,Y/Northing,Z/Altitude,Omega,Phi,Kappa,"
                            "X_accuracy,Y_accuracy,Z_accuracy,"
                            "Omega_accuracy,Phi_accuracy,Kappa_accuracy")
    rows = [ln.split(",") for ln in text.splitlines() if not ln.startswith("#")]
    assert [r[0] for r in rows] == [p.image_name for p in poses]
    for r, pose in zip(rows, poses, strict=True):
        np.testing.assert_array_equal([float(v) for v in r[1:4]], pose.C_world)
        R = rotation_from_opk(*np.radians([float(v) for v in r[4:7]]))
        np.testing.assert_allclose(R, pose.R_cam_to_world, rtol=0, atol=1e-12)
        assert r[7:] == ["0.02", "0.02", "0.05", "0.1", "0.1", "0.1"]


def test_markers_csv_has_surveyed_coordinates_sigmas_and_names_check_points():
    _interior, _poses, gcps, _obs = survey(32)
    text = metashape_markers_csv(gcps, "EPSG:32632")
    checks = [g.gcp_id for g in gcps if g.role == "check"]
    assert any(ln.startswith("# check points") and ln.endswith(" ".join(checks))
               for ln in text.splitlines())
    rows = [ln.split(",") for ln in text.splitlines() if not ln.startswith("#")]
    for r, g in zip(rows, gcps, strict=True):
        assert r[0] == g.gcp_id and r[7] == g.role
        np.testing.assert_array_equal([float(v) for v in r[1:4]], g.surveyed_xyz)
        np.testing.assert_array_equal([float(v) for v in r[4:7]], g.sigma_xyz)


def test_markers_xml_has_projections_and_control_check_flags():
    """Metashape's markers XML: a check point is an unticked (enabled="false") marker;
    every image point is a pinned <location> in Metashape pixels (corner origin)."""
    from pyproj import CRS

    from designer.export.metashape import metashape_markers_xml

    interior, poses, gcps, obs = survey(33)
    roles = {g.role for g in gcps}
    assert roles == {"control", "check"}
    root = etree.fromstring(metashape_markers_xml(poses, gcps, obs, "EPSG:32632",
                                                  interior=interior).encode())
    assert root.tag == "document"
    chunk = root.find("chunk")
    # every camera's sensor_id refers to a sensor of the file: the one camera's
    sensors = {s.get("id"): s for s in chunk.find("sensors")}
    assert list(sensors) == ["0"] and sensors["0"].get("type") == "frame"
    W, H = interior.image_size_px
    resolution = sensors["0"].find("resolution")
    assert (int(resolution.get("width")), int(resolution.get("height"))) == (W, H)
    assert {c.get("sensor_id") for c in chunk.find("cameras")} == {"0"}
    # labels as Metashape names cameras: the file name without its extension
    by_stem = {Path(p.image_name).stem: p.image_name for p in poses}
    cameras = {c.get("id"): by_stem[c.get("label")] for c in chunk.find("cameras")}
    assert sorted(cameras.values()) == sorted(p.image_name for p in poses)
    markers = {m.get("id"): m for m in chunk.find("markers")}
    by_label = {m.get("label"): m for m in markers.values()}
    for g in gcps:
        ref = by_label[g.gcp_id].find("reference")
        assert [float(ref.get(a)) for a in "xyz"] == g.surveyed_xyz.tolist()
        assert [float(ref.get(a)) for a in ("sx", "sy", "sz")] == g.sigma_xyz.tolist()
        assert ref.get("enabled") == ("true" if g.role == "control" else "false")
    seen = []
    for marker in chunk.find("frames").find("frame").find("markers"):
        label = markers[marker.get("marker_id")].get("label")
        for loc in marker.iter("location"):
            assert loc.get("pinned") == "true"
            seen.append((label, cameras[loc.get("camera_id")],
                         float(loc.get("x")), float(loc.get("y"))))
    assert sorted(seen) == sorted((o.gcp_id, o.image_name, *o.uv_px.tolist()) for o in obs)
    assert CRS.from_wkt(chunk.find("reference").text).to_epsg() == 32632


def test_markers_xml_refuses_observations_of_unknown_images():
    from designer.core.truth import GcpObservation
    from designer.export import ExportError
    from designer.export.metashape import metashape_markers_xml

    _interior, poses, gcps, _obs = survey(34)
    with pytest.raises(ExportError, match="unknown"):
        metashape_markers_xml(poses, gcps, [GcpObservation(gcps[0].gcp_id, "x.png", [1, 2])],
                              "EPSG:32632")
