"""True north in the grid and DJI gimbal angles, checked against independent computations."""

import math

import numpy as np
import pytest

from designer.core.rotation import rotation_from_heading_tilt_roll, rotation_from_opk
from designer.errors import DesignerError
from designer.flight.geodesy import Georef, north_azimuth_in
from designer.flight.gimbal import gimbal_from_rotation, rotation_from_gimbal
from tests.flight.helpers import dji_angles_deg, grid_azimuth_of_true_north_deg


@pytest.mark.parametrize(("crs", "X", "Y"), [
    ("EPSG:32632", 440_000.0, 5_400_000.0),   # west of the central meridian, north
    ("EPSG:32632", 560_000.0, 5_400_000.0),   # east of it
    ("EPSG:32732", 440_000.0, 6_000_000.0),   # southern hemisphere, west
    ("EPSG:32732", 560_000.0, 6_000_000.0),   # southern hemisphere, east
])
def test_true_north_matches_a_finite_difference_on_both_sides(crs, X, Y):
    got = float(Georef(crs).true_north_azimuth_deg(X, Y))
    expected = grid_azimuth_of_true_north_deg(crs, X, Y)
    assert abs(got - expected) < 1e-6
    assert abs(got) > 0.3  # far enough from the meridian for the sign to matter
    # east of the meridian in the north, true north points west of grid north
    north, east = crs == "EPSG:32632", X > 500_000
    assert (got < 0) == (north == east)


def test_north_of_another_crs_is_its_grid_north():
    g = Georef("EPSG:32632 (WGS 84 / UTM zone 32N)")
    X, Y = 700_000.0, 5_300_000.0
    assert float(north_azimuth_in("EPSG:32632", g, X, Y)) == 0.0
    assert float(north_azimuth_in("EPSG:4326", g, X, Y)) == pytest.approx(
        grid_azimuth_of_true_north_deg("EPSG:32632", X, Y), abs=1e-6)
    # zone 33's grid north seen from zone 32: the difference of the two convergences
    from pyproj import Transformer
    lon, lat = Transformer.from_crs("EPSG:32632", "EPSG:4326", always_xy=True).transform(X, Y)
    X33, Y33 = Transformer.from_crs("EPSG:4326", "EPSG:32633", always_xy=True).transform(lon, lat)
    expected = (grid_azimuth_of_true_north_deg("EPSG:32632", X, Y)
                - grid_azimuth_of_true_north_deg("EPSG:32633", X33, Y33))
    assert float(north_azimuth_in("EPSG:32633", g, X, Y)) == pytest.approx(expected, abs=1e-6)


def test_a_geographic_project_crs_is_refused():
    with pytest.raises(DesignerError, match="not a projected CRS"):
        Georef("EPSG:4326")


def test_nadir_north_up_is_the_identity():
    assert np.allclose(rotation_from_gimbal(0.0, -90.0, 0.0), np.eye(3), atol=1e-15)


@pytest.mark.parametrize(("yaw", "pitch"), [(90.0, -90.0), (30.0, -70.0), (-120.0, -45.0)])
def test_yaw_turns_the_image_top_and_pitch_lifts_the_view(yaw, pitch):
    R = rotation_from_gimbal(yaw, pitch, 0.0)
    # DJI yaw is the azimuth of the view (and of the image top at nadir), pitch its elevation
    expected = rotation_from_heading_tilt_roll(math.radians(yaw), math.radians(90 + pitch), 0)
    assert np.allclose(R, expected, atol=1e-14)
    view = -R[:, 2]
    assert math.degrees(math.asin(view[2])) == pytest.approx(pitch)


def test_angles_match_scipy_zyx_and_round_trip():
    rng = np.random.default_rng(3)
    for _ in range(500):
        R = rotation_from_opk(*rng.uniform(-math.pi, math.pi, 3))
        yaw, pitch, roll = gimbal_from_rotation(R)
        assert np.abs(rotation_from_gimbal(yaw, pitch, roll) - R).max() < 1e-12
        ref = dji_angles_deg(R, "EPSG:32632", 500_000.0, 5_000_000.0)  # on the meridian
        assert abs((yaw - ref[0] + 180) % 360 - 180) < 1e-7
        assert pitch == pytest.approx(ref[1], abs=1e-7)
        assert abs((roll - ref[2] + 180) % 360 - 180) < 1e-7


def test_exact_nadir_round_trips_at_the_gimbal_lock():
    for heading in (0.0, 37.0, 180.0, 271.5):
        R = rotation_from_heading_tilt_roll(math.radians(heading), 0.0, 0.0)
        yaw, pitch, roll = gimbal_from_rotation(R)
        assert (pitch, roll) == (-90.0, 0.0)
        assert yaw % 360 == pytest.approx(heading)
        assert np.abs(rotation_from_gimbal(yaw, pitch, roll) - R).max() < 1e-15
