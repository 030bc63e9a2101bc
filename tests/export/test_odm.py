import math

import numpy as np
import pytest

from designer.core.rotation import rotation_from_heading_tilt_roll, rotation_from_opk
from designer.core.truth import CameraPose, GroundControlPoint
from designer.export import ExportError
from designer.export.odm import (
    odm_gcp_list_text,
    odm_geo_text,
    odm_ypr_deg_from_rotation,
    write_odm_gcp_list,
)
from tests.synthetic import ORIGIN_WORLD, survey


def odm_rotation(yaw_deg, pitch_deg, roll_deg):
    """R_cam_to_world (ENU) as OpenDroneMap builds it in opendm/photo.py compute_opk.

    cnb: body (x forward, y right, z down) → NED, Rz(yaw)·Ry(pitch)·Rx(roll) (Bäumker);
    cbb: image (x right, y top, z back) → body; then NED → ENU.
    """
    y, p, r = (math.radians(a) for a in (yaw_deg, pitch_deg, roll_deg))
    cy, sy, cp, sp, cr, sr = math.cos(y), math.sin(y), math.cos(p), math.sin(p), \
        math.cos(r), math.sin(r)
    cnb = np.array([
        [cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
        [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
        [-sp, cp * sr, cp * cr],
    ])
    cbb = np.array([[0, 1, 0], [1, 0, 0], [0, 0, -1.0]])
    enu_from_ned = np.array([[0, 1, 0], [1, 0, 0], [0, 0, -1.0]])
    return enu_from_ned @ cnb @ cbb


def test_gcp_list_header_rows_and_half_pixel_shift():
    _interior, _poses, gcps, obs = survey(20)
    text = odm_gcp_list_text(gcps, obs, "EPSG:32632")
    lines = text.splitlines()
    assert lines[0] == "EPSG:32632"
    by_id = {g.gcp_id: g for g in gcps}
    control = [o for o in obs if by_id[o.gcp_id].role == "control"]
    assert len(lines) - 1 == len(control) > 0
    for line, o in zip(lines[1:], control, strict=True):
        x, y, z, im_x, im_y, image, gcp_id = line.split()
        assert (image, gcp_id) == (o.image_name, o.gcp_id)
        assert [float(x), float(y), float(z)] == by_id[gcp_id].surveyed_xyz.tolist()
        assert float(im_x) == o.uv_px[0] - 0.5 and float(im_y) == o.uv_px[1] - 0.5


def test_gcp_list_pixels_mean_what_opensfm_reads():
    """OpenSfM normalises gcp_list pixels as (px + 0.5 - W/2) / max(W, H) (features.py)."""
    interior, _poses, gcps, obs = survey(21)
    W, H = interior.image_size_px
    size = max(W, H)
    rows = odm_gcp_list_text(gcps, obs, "WGS84 UTM 32N", roles=("control", "check"))
    for line, o in zip(rows.splitlines()[1:], obs, strict=True):
        px, py = (float(v) for v in line.split()[3:5])
        opensfm = np.array([(px + 0.5 - W / 2) / size, (py + 0.5 - H / 2) / size])
        designer = np.array([(o.uv_px[0] - W / 2) / size, (o.uv_px[1] - H / 2) / size])
        np.testing.assert_allclose(opensfm, designer, rtol=0, atol=1e-13)


def test_check_points_are_left_out_unless_asked():
    _interior, _poses, gcps, obs = survey(22)
    checks = {g.gcp_id for g in gcps if g.role == "check"}
    default = odm_gcp_list_text(gcps, obs, "EPSG:32632")
    assert not {ln.split()[6] for ln in default.splitlines()[1:]} & checks
    both = odm_gcp_list_text(gcps, obs, "EPSG:32632", roles=("control", "check"))
    assert len(both.splitlines()) - 1 == len(obs)
    with pytest.raises(ExportError, match="role"):
        odm_gcp_list_text(gcps, obs, "EPSG:32632", roles=("tie",))


@pytest.mark.parametrize("crs", ["epsg:32632", "WGS84 UTM 16N", "WGS84 UTM 5S",
                                 "+proj=utm +zone=10 +ellps=WGS84 +datum=WGS84 +units=m"])
def test_crs_lines_odm_parses_are_accepted(crs):
    _interior, poses, gcps, obs = survey(23)
    assert odm_gcp_list_text(gcps, obs, crs).splitlines()[0] == crs
    assert odm_geo_text(poses, crs).splitlines()[0] == crs


@pytest.mark.parametrize("crs", [
    "", "UTM 32N", "ETRS89 / UTM zone 32N", "EPSG:32632\nx",
    # ODM compares 'WGS84' and 'UTM' case-sensitively; PROJ has zones 1-60 only
    "wgs84 utm 32N", "WGS84 utm 32N", "WGS84 UTM 0N", "WGS84 UTM 61N", "WGS84 UTM 32",
    # ODM parses these, but the coordinates are metres: geographic or foot CRSs misread them
    "EPSG:4326", "+proj=longlat +datum=WGS84", "EPSG:2263",
])
def test_crs_lines_odm_cannot_parse_are_rejected(crs):
    _interior, _poses, gcps, obs = survey(24)
    with pytest.raises(ExportError):
        odm_gcp_list_text(gcps, obs, crs)


def true_north_grid_azimuth_rad(crs: str, E: float, N: float) -> float:
    """Grid azimuth (clockwise from the CRS's Y axis) of true north at (E, N): the
    direction from the point 1 km south to the point 1 km north on the same meridian
    (central difference), by pyproj.Transformer — independent of PROJ's
    meridian_convergence factor."""
    from pyproj import CRS, Transformer

    if crs.startswith("WGS84 UTM "):  # as OpenDroneMap builds it (opendm/location.py)
        zone = crs.split()[2]
        south = " +south" if zone.endswith("S") else ""
        projected = CRS.from_proj4(f"+proj=utm +zone={int(zone[:-1])} +datum=WGS84 "
                                   f"+units=m{south}")
    else:
        projected = CRS.from_user_input(crs)
    to_geo = Transformer.from_crs(projected, CRS.from_epsg(4326), always_xy=True)
    to_grid = Transformer.from_crs(CRS.from_epsg(4326), projected, always_xy=True)
    lon, lat = to_geo.transform(E, N)
    E1, N1 = to_grid.transform(lon, lat - 1000.0 / 111_320.0)
    E2, N2 = to_grid.transform(lon, lat + 1000.0 / 111_320.0)
    return math.atan2(E2 - E1, N2 - N1)


def Rz(angle_rad: float) -> np.ndarray:
    c, s = math.cos(angle_rad), math.sin(angle_rad)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def test_geo_txt_angles_rebuild_the_rotation_with_odms_formula():
    """ODM's angles refer to TRUE north (compute_opk: north = d(ECEF)/d(latitude)):
    turning ODM's matrix from true-north axes to grid axes gives the true rotation."""
    _interior, poses, _gcps, _obs = survey(25)
    lines = odm_geo_text(poses, "EPSG:32632").splitlines()
    assert lines[0] == "EPSG:32632" and len(lines) == len(poses) + 1
    for line, pose in zip(lines[1:], poses, strict=True):
        parts = line.split()
        assert parts[0] == pose.image_name and len(parts) == 7
        xyz = np.array([float(v) for v in parts[1:4]])
        np.testing.assert_array_equal(xyz, pose.C_world)
        yaw, pitch, roll = (float(v) for v in parts[4:7])
        # a vector at true azimuth a has grid azimuth a + theta: grid = Rz(-theta) · true
        theta = true_north_grid_azimuth_rad("EPSG:32632", *pose.C_world[:2])
        np.testing.assert_allclose(Rz(-theta) @ odm_rotation(yaw, pitch, roll),
                                   pose.R_cam_to_world, rtol=0, atol=1e-7)


@pytest.mark.parametrize(("crs", "E", "N", "west_of_cm"), [
    ("EPSG:32632", 300_000.0, 5_000_000.0, True),    # zone 32N, ~2.5° west of 9° E
    ("EPSG:32632", 700_000.0, 5_000_000.0, False),   # ~2.5° east
    ("WGS84 UTM 33S", 320_000.0, 6_000_000.0, True),  # southern hemisphere, west
    ("WGS84 UTM 33S", 680_000.0, 6_000_000.0, False),  # southern hemisphere, east
])
def test_geo_txt_yaw_is_referred_to_true_north_on_both_sides_of_the_central_meridian(
        crs, E, N, west_of_cm):
    """A camera whose image top points to grid north: its true yaw is minus the grid
    azimuth of true north (θ), which changes sign across the central meridian and
    between hemispheres; ~1.8° here, so a grid-north yaw would be far off."""
    pose = CameraPose("a.png", [E, N, 300.0], np.eye(3))
    yaw = float(odm_geo_text([pose], crs).splitlines()[1].split()[4])
    theta_deg = math.degrees(true_north_grid_azimuth_rad(crs, E, N))
    # northern hemisphere: meridians converge to the north pole, so west of the
    # central meridian true north leans east (θ > 0); south of the equator the reverse
    north = not crs.endswith("S")
    assert (theta_deg > 0) == (west_of_cm == north) and abs(theta_deg) > 1.0
    assert ((yaw + theta_deg + 180.0) % 360.0) - 180.0 == pytest.approx(0.0, abs=1e-6)


@pytest.mark.parametrize(
    ("heading", "tilt", "roll", "expected"),
    [
        (0, 0, 0, (0, 0, 0)),       # nadir, image top north
        (90, 0, 0, (90, 0, 0)),     # image top east
        (270, 0, 0, (270, 0, 0)),   # image top west
        (0, 30, 0, (0, 30, 0)),     # forward oblique: pitch 90 would look ahead
        (0, 0, 10, (0, 0, -10)),    # designer roll right = ODM roll left (aerospace sign)
    ],
)
def test_odm_angle_conventions(heading, tilt, roll, expected):
    R = rotation_from_heading_tilt_roll(*np.radians([heading, tilt, roll]))
    np.testing.assert_allclose(odm_ypr_deg_from_rotation(R), expected, atol=1e-12)


def test_yaw_follows_the_image_top_and_pitch_the_view():
    # forward oblique to the north: the viewing axis (−z) tips from nadir towards north
    R = rotation_from_opk(np.radians(30.0), 0.0, 0.0)
    view = R @ [0, 0, -1]
    assert view[1] > 0  # looks north
    yaw, pitch, _roll = odm_ypr_deg_from_rotation(R)
    assert yaw == pytest.approx(0, abs=1e-12) and pitch == pytest.approx(30)


def test_geo_txt_accuracies_are_written_as_a_pair():
    pose = CameraPose("a.png", ORIGIN_WORLD, np.eye(3))
    line = odm_geo_text([pose], "EPSG:32632", 0.02, 0.05).splitlines()[1]
    assert line.split()[-2:] == ["0.02", "0.05"]
    with pytest.raises(ExportError, match="both"):
        odm_geo_text([pose], "EPSG:32632", horizontal_accuracy_m=0.02)


def test_observation_of_an_unknown_gcp_is_rejected(tmp_path):
    _interior, _poses, gcps, obs = survey(26)
    with pytest.raises(ExportError, match="unknown GCP"):
        write_odm_gcp_list(tmp_path / "gcp_list.txt", gcps[1:], obs, "EPSG:32632")
    assert list(tmp_path.iterdir()) == []


def test_gcps_at_identical_surveyed_coordinates_are_rejected():
    _interior, _poses, gcps, obs = survey(27)
    twin = GroundControlPoint("TWIN", "control", gcps[0].true_xyz, gcps[0].surveyed_xyz,
                              gcps[0].sigma_xyz)
    with pytest.raises(ExportError, match="merge"):
        odm_gcp_list_text([*gcps, twin], obs, "EPSG:32632")
    # a check point at the same spot is not written by default, so it is harmless
    twin_check = GroundControlPoint("TWIN", "check", twin.true_xyz, twin.surveyed_xyz,
                                    twin.sigma_xyz)
    assert odm_gcp_list_text([*gcps, twin_check], obs, "EPSG:32632")
