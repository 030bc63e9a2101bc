"""The rolling-shutter projection against brute force: every row projected with the
camera where it is when that row is exposed."""

import numpy as np
import pytest

from designer.core.projection import pixel_rays_world, project_points
from designer.core.rolling_shutter import (
    RollingShutterError,
    rolling_shutter_projection,
    row_delay_s,
    row_time_s,
)
from designer.core.rotation import rotation_from_opk
from tests.synthetic import ORIGIN_WORLD, interior_for, phantom4


def scene(rng, interior, n=300):
    C = ORIGIN_WORLD + np.array([10.0, -20.0, 100.0])
    R = rotation_from_opk(*np.radians(rng.uniform(-10, 10, 3)))
    uv = rng.uniform([0, 0], interior.image_size_px, size=(n, 2))
    P = C + pixel_rays_world(uv, R, interior) * rng.uniform(80, 120, n)[:, None]
    return C, R, P


def brute_force_rows(P, C, R, velocity, readout_s, interior, direction):
    """Per point: the continuous row v where the row function crosses v, found by
    projecting with the camera of every row centre and interpolating between the two
    rows the crossing lies between; NaN if the point is seen in no row."""
    H = interior.image_height_px
    rows = np.arange(H)
    v_rows = np.empty((H, len(P)))
    for r in rows:
        delay = row_time_s(int(r), H, readout_s, direction)
        v_rows[r] = project_points(P, C + velocity * delay, R, interior).uv_px[0, :, 1]
    f = v_rows - (rows[:, None] + 0.5)  # f(v) = proj_v(camera at v) − v at row centres
    out = np.full(len(P), np.nan)
    for k in range(len(P)):
        s = np.flatnonzero(np.sign(f[:-1, k]) != np.sign(f[1:, k]))
        if len(s) == 1:
            r = s[0]
            w = f[r, k] / (f[r, k] - f[r + 1, k])
            out[k] = r + 0.5 + w
    return out, v_rows


@pytest.mark.parametrize("direction", ["top-to-bottom", "bottom-to-top"])
@pytest.mark.parametrize("lens", ["pinhole", "opencv"])
def test_projection_matches_the_row_by_row_brute_force(direction, lens):
    rng = np.random.default_rng(3)
    interior = interior_for(lens)
    C, R, P = scene(rng, interior)
    velocity = np.array([12.0, -5.0, 0.8])  # m/s, world
    readout_s = 0.04
    uv = rolling_shutter_projection(P, C, R, velocity, readout_s, interior, direction)
    v_bf, v_rows = brute_force_rows(P, C, R, velocity, readout_s, interior, direction)
    seen = np.isfinite(v_bf)
    assert seen.mean() > 0.9
    # the row function is linear in the delay, so the interpolated crossing is exact
    np.testing.assert_allclose(uv[seen, 1], v_bf[seen], atol=1e-6)
    # the row the point is drawn in: projecting with that row's camera puts it there
    r = np.floor(uv[seen, 1]).astype(int)
    inside = (r >= 0) & (r < interior.image_height_px)
    idx = np.flatnonzero(seen)[inside]
    v_own = v_rows[r[inside], idx]
    per_row_px = np.abs(np.diff(v_rows, axis=0)).max()
    assert np.all(np.abs(v_own - uv[idx, 1]) <= per_row_px + 1e-9)
    # u is the projection with the camera at the solved instant
    delay = row_delay_s(uv[:, 1], interior.image_height_px, readout_s, direction)
    direct = np.array([project_points(p, C + velocity * d, R, interior).uv_px[0, 0]
                       for p, d in zip(P, delay, strict=True)])
    np.testing.assert_allclose(uv, direct, atol=1e-6)
    # and the global-shutter projection is far off: the test can fail
    global_uv = project_points(P, C, R, interior).uv_px[0]
    assert np.nanmax(np.abs(global_uv - uv)) > 10


def test_first_row_time_is_the_image_time_and_rows_follow_at_readout_over_height():
    assert row_time_s(0, 3000, 0.03) == 0.0
    assert row_time_s(1500, 3000, 0.03) == pytest.approx(0.015)
    assert row_time_s(2999, 3000, 0.03, "bottom-to-top") == 0.0
    assert row_time_s(0, 3000, 0.03, "bottom-to-top") == pytest.approx(0.03 * 2999 / 3000)


def test_no_readout_or_no_motion_is_the_global_shutter_projection():
    rng = np.random.default_rng(5)
    interior = phantom4()
    C, R, P = scene(rng, interior, 50)
    expect = project_points(P, C, R, interior).uv_px[0]
    for readout, vel in ((0.0, [10.0, 0, 0]), (0.03, [0.0, 0, 0])):
        np.testing.assert_array_equal(
            rolling_shutter_projection(P, C, R, np.array(vel), readout, interior), expect)


def test_points_behind_the_camera_are_nan():
    interior = phantom4()
    C = ORIGIN_WORLD + np.array([0.0, 0.0, 100.0])
    P = np.array([C + [0.0, 0.0, -100.0], C + [0.0, 0.0, 50.0]])
    uv = rolling_shutter_projection(P, C, np.eye(3), np.array([10.0, 0, 0]), 0.03, interior)
    assert np.isfinite(uv[0]).all() and np.isnan(uv[1]).all()


def test_a_camera_faster_than_the_readout_raises():
    interior = phantom4()
    C = ORIGIN_WORLD + np.array([0.0, 0.0, 10.0])
    P = np.array([C + [0.0, 0.0, -10.0]])
    # 10 m above ground the image is 10 m tall; flying north at 1000 m/s the ground
    # moves down the image 50 m during the 0.05 s readout, five times as fast as the
    # readout sweeps it
    with pytest.raises(RollingShutterError, match="did not converge"):
        rolling_shutter_projection(P, C, np.eye(3), np.array([0.0, 1000.0, 0.0]), 0.05,
                                   interior)


def test_a_point_far_outside_the_image_that_breaks_down_is_dropped_not_fatal():
    """A scene vertex beside the camera (a mask's far-away plant seen from an oblique
    view) may pass behind the camera during the readout: it is NaN, and the points in the
    image are projected as ever."""
    interior = phantom4()
    C = ORIGIN_WORLD + np.array([0.0, 0.0, 30.0])
    # looking north, level: x = east (image right), y = up (image top), z = south
    R = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]])
    velocity = np.array([0.0, 10.0, 0.0])  # flying north, towards what it sees
    beside = C + [100.0, 0.01, 0.0]  # 1 cm in front of the camera, 100 m to the right
    ahead = C + [2.0, 50.0, -3.0]
    uv = rolling_shutter_projection(np.array([beside, ahead]), C, R, velocity, 0.03, interior)
    assert np.isnan(uv[0]).all()
    alone = rolling_shutter_projection(ahead[None], C, R, velocity, 0.03, interior)
    np.testing.assert_allclose(uv[1], alone[0], atol=1e-9)
    assert np.isfinite(alone).all()
