import math
from dataclasses import replace

import numpy as np
import pytest

from designer.core.rotation import (
    heading_tilt_roll_from_rotation,
    opk_from_rotation,
    rotation_from_heading_tilt_roll,
    rotvec_from_rotation,
)
from designer.errors import DesignerError
from designer.survey import area
from designer.survey.flight import Station, apply_pose_noise, camera_calc, plan_flight
from tests.synthetic import ORIGIN_WORLD, hilly_terrain, phantom4

# --------------------------------------------------------------------- CameraCalc


def test_camera_calc_phantom4_at_100_m_matches_hand_computation():
    calc = camera_calc(phantom4(), altitude_agl_m=100.0, front_overlap_fraction=0.8,
                       side_overlap_fraction=0.7)
    # GSD = 100 m · (13.2 mm / 5472) / 8.8 mm = 2.7412 cm
    assert calc.gsd_m == pytest.approx(0.0274123, rel=1e-5)
    assert round(calc.gsd_m * 100, 3) == 2.741
    assert calc.footprint_across_m == pytest.approx(150.0, rel=1e-12)  # 5472 px · GSD
    assert calc.footprint_along_m == pytest.approx(100.0, rel=1e-12)  # 3648 px · GSD
    assert calc.line_spacing_m == pytest.approx(45.0, rel=1e-12)  # 150 · (1 − 0.7)
    assert calc.trigger_distance_m == pytest.approx(20.0, rel=1e-12)  # 100 · (1 − 0.8)


def test_camera_calc_from_target_gsd_and_portrait():
    # Sony a6000: 23.5 mm / 6000 px, f = 16 mm; GSD 2 cm → H = 0.02 · 16 / 0.0039167 = 81.70 m
    cam = phantom4(focal_length_mm=16.0, sensor_width_mm=23.5, sensor_height_mm=15.6666666667,
                   image_width_px=6000, image_height_px=4000)
    calc = camera_calc(cam, gsd_m=0.02, front_overlap_fraction=0.75,
                       side_overlap_fraction=0.6, orientation="portrait")
    assert calc.altitude_agl_m == pytest.approx(0.02 * 16.0 / (23.5 / 6000), rel=1e-9)
    assert calc.altitude_agl_m == pytest.approx(81.702, abs=1e-3)
    # portrait: the short side (4000 px) lies across track
    assert calc.footprint_across_m == pytest.approx(4000 * 0.02, rel=1e-6)
    assert calc.footprint_along_m == pytest.approx(6000 * 0.02, rel=1e-9)
    assert calc.line_spacing_m == pytest.approx(80.0 * 0.4, rel=1e-6)
    assert calc.trigger_distance_m == pytest.approx(120.0 * 0.25, rel=1e-9)


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        (dict(altitude_agl_m=100.0, front_overlap_fraction=1.0), "100 %"),
        (dict(altitude_agl_m=100.0, front_overlap_fraction=80.0), "0.8"),
        (dict(altitude_agl_m=100.0, side_overlap_fraction=1.2), "1.2 % is written 0.012"),
        (dict(altitude_agl_m=100.0, side_overlap_fraction=100.0), "100 %"),
        (dict(altitude_agl_m=100.0, side_overlap_fraction=-0.1), "[0, 1)"),
        (dict(altitude_agl_m=0.0), "must be > 0"),
        (dict(altitude_agl_m=-20.0), "must be > 0"),
        (dict(gsd_m=0.0), "GSD"),
        (dict(), "either"),
        (dict(altitude_agl_m=100.0, gsd_m=0.02), "either"),
    ],
)
def test_impossible_camera_calc_requests_raise_clear_errors(kwargs, message):
    params = dict(front_overlap_fraction=0.8, side_overlap_fraction=0.7)
    params.update(kwargs)
    with pytest.raises(DesignerError, match=None) as info:
        camera_calc(phantom4(), **params)
    assert message in str(info.value)


def test_impossible_plans_raise_clear_errors():
    square = area.rectangle(0, 0, 500, 500)
    with pytest.raises(DesignerError, match="forward tilt"):
        plan_flight(square, phantom4(), altitude_agl_m=100, forward_tilt_deg=85,
                    altitude_reference=0.0)
    with pytest.raises(DesignerError, match="needs the terrain"):
        plan_flight(square, phantom4(), altitude_agl_m=100, altitude_mode="terrain_following")
    with pytest.raises(DesignerError, match="more than the limit"):
        plan_flight(square, phantom4(), altitude_agl_m=5, altitude_reference=0.0,
                    max_stations=1000)
    with pytest.raises(DesignerError, match="start corner"):
        plan_flight(square, phantom4(), altitude_agl_m=100, altitude_reference=0.0,
                    start_corner="north")
    with pytest.raises(DesignerError, match="must contain"):
        plan_flight(square, phantom4(), altitude_agl_m=100, altitude_reference=0.0,
                    image_name_format="photo.png")
    with pytest.raises(DesignerError, match="edges cross"):
        plan_flight([[0, 0], [100, 100], [100, 0], [0, 100]], phantom4(),
                    altitude_agl_m=100, altitude_reference=0.0)


# ------------------------------------------------------------------ line geometry
def plan_square(poly=None, **kw):
    params = dict(altitude_agl_m=100.0, front_overlap_fraction=0.8,
                  side_overlap_fraction=0.7, altitude_reference=0.0)
    params.update(kw)
    poly = area.rectangle(0, 0, 400, 300) if poly is None else poly
    return plan_flight(poly, phantom4(), **params)


def test_lines_are_spaced_and_extended_by_the_documented_rule():
    plan = plan_square()
    C = plan.C_world
    # north-flying lines, x across, w = 400 m, A = 150 m, s = 45 m, N = ⌊150/45⌋ = 3:
    # n = ⌊(400 − 150)/45 + 4⌋ + 2 = 11 lines spanning 450 m, centred on x = 200 m
    xs = np.unique(np.round(C[:, 0], 9))
    assert plan.n_lines == len(xs) == 11
    assert np.allclose(np.diff(xs), 45.0)
    assert xs[0] == pytest.approx(-25.0) and xs[-1] == pytest.approx(425.0)
    # along track: w = 300 m, A = 100 m, s = 20 m, N = 5: n = ⌊10 + 8⌋ + 2 = 20 stations
    for k in range(plan.n_lines):
        y = np.sort(C[plan.line_index == k, 1])
        assert len(y) == 20
        assert np.allclose(np.diff(y), 20.0)
        assert y[0] == pytest.approx(-40.0) and y[-1] == pytest.approx(340.0)
    assert np.all(C[:, 2] == 100.0)  # constant altitude above the reference height 0
    # the edge x = 0 lies inside 3 lines' footprints (|x − line| < 75 m), as the middle does
    assert np.count_nonzero(np.abs(xs) < 75.0) == 3
    # y = 0 lies inside 5 images of a line (|y − station| < 50 m)
    assert np.count_nonzero(np.abs(y) < 50.0) == 5
    # a small area without overlap gets one image
    tiny = plan_square(poly=area.rectangle(0, 0, 1, 1), front_overlap_fraction=0.0,
                       side_overlap_fraction=0.0)
    assert len(tiny.stations) == 1 and np.allclose(tiny.C_world[0], [0.5, 0.5, 100.0])


def test_serpentine_order_from_the_start_corner_and_camera_orientation():
    plan = plan_square(start_corner="SW")
    first, last_of_line0 = plan.stations[0], plan.stations[19]
    assert first.C_world[0] < 0 and first.C_world[1] < 0  # starts at the south-west
    assert last_of_line0.C_world[1] > first.C_world[1]  # first line flies north
    az = np.array([s.flight_azimuth_deg for s in plan.stations])
    assert set(az[plan.line_index % 2 == 0]) == {0.0}
    assert set(az[plan.line_index % 2 == 1]) == {180.0}
    # landscape nadir, flying north: identity (image top north, image right east)
    assert np.allclose(first.R_cam_to_world, np.eye(3), atol=1e-12)
    # flying south: image top south (κ = 180°), still nadir
    back = plan.stations[20].R_cam_to_world
    assert np.allclose(back @ [0, 1, 0], [0, -1, 0], atol=1e-12)
    assert np.allclose(back @ [0, 0, -1], [0, 0, -1], atol=1e-12)
    ne = plan_square(start_corner="NE")
    assert ne.stations[0].C_world[0] > 400 and ne.stations[0].C_world[1] > 300
    assert ne.stations[0].flight_azimuth_deg == 180.0


@pytest.mark.parametrize("grid_angle", [0.0, 30.0, 117.0])
def test_image_axes_follow_the_flight_direction(grid_angle):
    for orientation, axis in (("landscape", [0, 1, 0]), ("portrait", [1, 0, 0])):
        plan = plan_square(grid_angle_deg=grid_angle, orientation=orientation)
        for s in plan.stations[:: 7]:
            a = math.radians(s.flight_azimuth_deg)
            forward = np.array([math.sin(a), math.cos(a), 0.0])
            assert np.allclose(s.R_cam_to_world @ axis, forward, atol=1e-12)
            assert np.allclose(s.R_cam_to_world @ [0, 0, -1], [0, 0, -1], atol=1e-12)


@pytest.mark.parametrize("orientation", ["landscape", "portrait"])
def test_forward_tilt_looks_ahead_by_the_tilt_angle(orientation):
    plan = plan_square(forward_tilt_deg=30.0, orientation=orientation, grid_angle_deg=20.0)
    for s in plan.stations[::11]:
        a = math.radians(s.flight_azimuth_deg)
        view = s.R_cam_to_world @ [0, 0, -1]
        assert math.degrees(math.acos(-view[2])) == pytest.approx(30.0, abs=1e-9)
        horizontal = view[:2] / np.hypot(*view[:2])
        assert np.allclose(horizontal, [math.sin(a), math.cos(a)], atol=1e-9)
    # the tilted footprint is pushed forward: the lines are longer by H · tan(tilt) each end
    nadir = plan_square(orientation=orientation, grid_angle_deg=20.0)
    assert len(plan.stations) > len(nadir.stations)


def test_crosshatch_doubles_the_lines_at_plus_90_degrees():
    square = area.rectangle(0, 0, 400, 400)
    single = plan_square(poly=square, grid_angle_deg=25.0)
    double = plan_square(poly=square, grid_angle_deg=25.0, crosshatch=True)
    assert double.n_lines == 2 * single.n_lines
    grid = np.array([s.grid_index for s in double.stations])
    az = np.array([s.flight_azimuth_deg for s in double.stations])
    assert set(az[grid == 0] % 180) == {25.0}
    assert set(az[grid == 1] % 180) == {115.0}
    assert np.count_nonzero(grid == 1) == len(single.stations)
    # on a square flown north, the second grid starts where the first one ended
    square_plan = plan_square(poly=square, crosshatch=True)
    grid = np.array([s.grid_index for s in square_plan.stations])
    end = square_plan.stations[np.flatnonzero(grid == 0)[-1]].C_world
    start = square_plan.stations[np.flatnonzero(grid == 1)[0]].C_world
    assert np.hypot(*(end[:2] - start[:2])) < 100.0
    names = double.image_names
    assert len(set(names)) == len(names) and names[0] == "IMG_00001.png"


def test_utm_sized_area_gives_the_plan_of_its_local_twin_shifted():
    local_hf = hilly_terrain()
    utm_hf = hilly_terrain(x0=ORIGIN_WORLD[:2][0], y0=ORIGIN_WORLD[:2][1])
    poly = np.array([[20.0, 30.0], [380.0, 10.0], [360.0, 370.0], [150.0, 250.0], [40, 390]])
    for mode in ("terrain_following", "constant"):
        kw = dict(altitude_agl_m=60.0, front_overlap_fraction=0.8, side_overlap_fraction=0.65,
                  grid_angle_deg=33.0, crosshatch=True, altitude_mode=mode,
                  forward_tilt_deg=10.0)
        a = plan_flight(poly, phantom4(), heightfield=local_hf, **kw)
        b = plan_flight(poly + ORIGIN_WORLD[:2], phantom4(), heightfield=utm_hf, **kw)
        assert len(a.stations) == len(b.stations)
        shift = np.array([*ORIGIN_WORLD[:2], 0.0])
        assert np.max(np.abs(b.C_world - shift - a.C_world)) < 1e-6
        assert np.max(np.abs(b.R_cam_to_world - a.R_cam_to_world)) < 1e-12
        assert np.array_equal(a.line_index, b.line_index)


def test_terrain_following_holds_the_height_above_ground():
    hf = hilly_terrain()
    poly = area.rectangle(50, 50, 350, 350)
    plan = plan_flight(poly, phantom4(), altitude_agl_m=80.0, front_overlap_fraction=0.75,
                       side_overlap_fraction=0.6, heightfield=hf,
                       altitude_mode="terrain_following", grid_angle_deg=12.0)
    C = plan.C_world
    ground = hf.height_at(C[:, 0], C[:, 1])
    over = np.isfinite(ground)
    assert over.sum() > len(C) / 2
    assert np.max(np.abs(C[over, 2] - ground[over] - 80.0)) < 1e-9
    assert np.ptp(C[:, 2]) > 30.0  # it really follows the hills
    x0, x1, y0, y1 = hf.extent_m  # stations past the edge use the nearest edge height
    edge = hf.height_at(np.clip(C[~over, 0], x0, x1), np.clip(C[~over, 1], y0, y1))
    assert np.allclose(C[~over, 2], edge + 80.0)


@pytest.mark.parametrize("reference", ["mean", "max", "min", 123.5])
def test_constant_altitude_references(reference):
    hf = hilly_terrain()
    poly = area.rectangle(0, 0, 200, 400)
    plan = plan_flight(poly, phantom4(), altitude_agl_m=90.0, heightfield=hf,
                       altitude_mode="constant", altitude_reference=reference)
    z = hf.heights_m[:, : 101]  # nodes with x ≤ 200 m (2 m spacing): the area's nodes
    expected = {"mean": z.mean(), "max": z.max(), "min": z.min()}.get(reference, reference)
    assert plan.reference_height_m == pytest.approx(expected, rel=1e-12)
    assert np.allclose(plan.C_world[:, 2], expected + 90.0)


# --------------------------------------------------------------------- pose noise
def _random_stations(rng, n):
    R = rotation_from_heading_tilt_roll(rng.uniform(0, 2 * np.pi, n),
                                        rng.uniform(0, 0.6, n), rng.uniform(-0.2, 0.2, n))
    C = np.array([*ORIGIN_WORLD[:2], 300.0]) + rng.uniform(-500, 500, (n, 3))
    return [Station(f"IMG_{k}", C[k], R[k], 0, 0, 0.0) for k in range(n)]


def test_pose_noise_statistics_match_the_requested_sigmas():
    stations = _random_stations(np.random.default_rng(3), 20000)
    sigma_xyz = np.array([0.05, 0.10, 0.20])
    sigma_deg = np.array([0.5, 1.0, 2.0])
    C_before = np.array([s.C_world for s in stations])
    noisy = apply_pose_noise(stations, sigma_xyz, sigma_deg, seed=11)
    dC = np.array([n.C_world - s.C_world for n, s in zip(noisy, stations, strict=True)])
    assert np.allclose(dC.std(axis=0), sigma_xyz, rtol=0.03)
    assert np.all(np.abs(dC.mean(axis=0)) < 4 * sigma_xyz / np.sqrt(len(dC)))
    R = np.array([s.R_cam_to_world for s in stations])
    Rn = np.array([n.R_cam_to_world for n in noisy])
    delta = np.degrees(rotvec_from_rotation(np.swapaxes(R, 1, 2) @ Rn))  # camera frame
    assert np.allclose(delta.std(axis=0), sigma_deg, rtol=0.03)
    assert abs(np.corrcoef(delta.T)[0, 2]) < 0.03
    # the input is untouched, and the same seed gives the same noise
    assert np.array_equal(np.array([s.C_world for s in stations]), C_before)
    again = apply_pose_noise(stations[:50], sigma_xyz, sigma_deg, seed=11)
    assert all(np.array_equal(a.R_cam_to_world, b.R_cam_to_world)
               and np.array_equal(a.C_world, b.C_world)
               for a, b in zip(again, apply_pose_noise(stations[:50], sigma_xyz, sigma_deg,
                                                       seed=11), strict=True))
    other = apply_pose_noise(stations[:50], sigma_xyz, sigma_deg, seed=12)
    assert not np.array_equal(other[0].C_world, again[0].C_world)


def test_pose_noise_on_a_nadir_north_camera_is_omega_phi_kappa_noise():
    s = Station("a", [0, 0, 100], np.eye(3), 0, 0, 0.0)
    noisy = apply_pose_noise([s] * 20000, [0, 0, 0], [0.3, 0.6, 1.2], seed=5)
    opk = np.degrees(np.array([opk_from_rotation(n.R_cam_to_world) for n in noisy]))
    assert np.allclose(opk.std(axis=0), [0.3, 0.6, 1.2], rtol=0.03)
    assert all(np.array_equal(n.C_world, s.C_world) for n in noisy[:10])


def test_pose_noise_keeps_everything_else_and_validates_sigmas():
    plan = plan_square()
    noisy = apply_pose_noise(plan.stations, 0.1, 0.5, seed=1)
    assert [n.image_name for n in noisy] == plan.image_names
    assert [n.line_index for n in noisy] == list(plan.line_index)
    moved = replace(plan, stations=tuple(noisy))
    assert np.all(moved.C_world != plan.C_world)
    _, tilt, _ = heading_tilt_roll_from_rotation(moved.R_cam_to_world)
    assert np.degrees(tilt).max() < 5
    with pytest.raises(DesignerError, match="sigma_opk_deg"):
        apply_pose_noise(plan.stations, 0.1, [-1, 0, 0], seed=1)
    with pytest.raises(ValueError, match="read-only"):
        noisy[0].C_world[0] = 1.0


def test_the_kept_reference_height_is_the_terrains_own():
    """The mean height under the area is kept per height grid and area (an edit of the
    flight's height plans twice over the same terrain); another grid, or the same grid's
    heights raised in a new height field, gives its own."""
    from designer.core.heightfield import Heightfield

    hf = hilly_terrain()
    x0, x1, y0, y1 = hf.extent_m
    square = np.array([[x0 + 50, y0 + 50], [x1 - 50, y0 + 50], [x1 - 50, y1 - 50],
                       [x0 + 50, y1 - 50]])
    first = plan_flight(square, phantom4(), altitude_agl_m=80, heightfield=hf)
    again = plan_flight(square, phantom4(), altitude_agl_m=80, heightfield=hf)
    assert np.array_equal(first.C_world, again.C_world)
    raised = Heightfield(hf.x0_m, hf.y0_m, hf.dx_m, hf.dy_m, hf.heights_m + 10.0)
    up = plan_flight(square, phantom4(), altitude_agl_m=80, heightfield=raised)
    assert np.allclose(up.C_world[:, 2] - 10.0, first.C_world[:, 2])


def test_contains_grid_is_contains_of_every_node():
    """area.contains_grid (the reference height's nodes inside the area, crossings found
    once per row) answers as contains node by node: concave and rotated areas, nodes on
    edges and vertices, UTM-sized coordinates."""
    rng = np.random.default_rng(4)
    E0, N0 = ORIGIN_WORLD[:2]
    polygons = [
        area.rectangle(E0 + 10.0, N0 + 10.0, E0 + 90.0, N0 + 70.0),
        np.array([[0, 0], [80, 0], [80, 80], [40, 30], [0, 80]], float) + [E0, N0],
        np.array([[50, 0], [100, 50], [50, 100], [0, 50]], float) + [E0, N0],
    ]
    x = E0 - 5.0 + np.arange(111) * 1.0
    y = N0 - 5.0 + np.arange(97) * 1.0 + rng.uniform(0, 1e-3)
    for poly in polygons:
        X, Y = np.meshgrid(x, y)
        one_by_one = area.contains(poly, np.column_stack([X.ravel(), Y.ravel()]))
        grid = area.contains_grid(poly, x, y)
        assert grid.shape == (len(y), len(x))
        assert np.array_equal(grid.ravel(), one_by_one)
        assert 0.2 < grid.mean() < 0.9
    # nodes exactly on the edges and vertices count inside
    square = area.rectangle(E0, N0, E0 + 10.0, N0 + 10.0)
    on = area.contains_grid(square, E0 + np.arange(11.0), N0 + np.arange(11.0))
    assert on.all()
