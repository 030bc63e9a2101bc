import numpy as np
import pytest

from designer.errors import DesignerError
from designer.survey import area, gcp_layout
from tests.synthetic import ORIGIN_WORLD, hilly_terrain

L_SHAPE = np.array([[0, 0], [300, 0], [300, 100], [100, 100], [100, 300], [0, 300]], float)


def min_distance(xy):
    d = np.hypot(*(xy[:, None, :] - xy[None, :, :]).transpose(2, 0, 1))
    return d[np.triu_indices(len(xy), 1)].min()


# ------------------------------------------------------------------------- areas
def test_area_validation_and_containment():
    poly = area.as_polygon(L_SHAPE + ORIGIN_WORLD[:2])
    assert area.polygon_area_m2(poly) == pytest.approx(300 * 100 + 100 * 200)
    pts = ORIGIN_WORLD[:2] + np.array([[50, 50], [250, 50], [250, 250], [50, 250], [100, 100],
                                       [-1, 0]])
    assert list(area.contains(poly, pts)) == [True, True, False, True, True, False]
    assert area.as_polygon([[0, 0], [1, 0], [1, 1], [0, 1], [0, 0]]).shape == (4, 2)
    # on the boundary counts as inside: every vertex and edge midpoint, at UTM magnitudes
    edges = np.vstack([poly, (poly + np.roll(poly, -1, axis=0)) / 2])
    assert area.contains(poly, edges).all()
    rng = np.random.default_rng(3)
    xy = ORIGIN_WORLD[:2] + rng.uniform(-20, 320, (5000, 2))
    far = area.distance_to_boundary_m(poly, xy) > 1e-6
    crossings = np.array([area.contains(poly, q[None])[0] for q in xy[:200]])
    assert (area.contains(poly, xy)[:200] == crossings).all()
    assert area.contains(poly, xy)[~far].all()
    for bad, message in (([[0, 0], [1, 1]], "at least 3"),
                         ([[0, 0], [1, 0], [2, 0]], "zero size"),
                         ([[0, 0], [2, 2], [2, 0], [0, 2]], "edges cross"),
                         ([[0, 0], [1, np.nan], [0, 1]], "finite")):
        with pytest.raises(DesignerError, match=message):
            area.as_polygon(bad)


def test_inset_moves_every_edge_by_the_margin():
    inner = area.inset(L_SHAPE, 10.0)
    expected = [[10, 10], [290, 10], [290, 90], [90, 90], [90, 290], [10, 290]]
    assert np.allclose(np.sort(inner, axis=0), np.sort(np.array(expected, float), axis=0))
    with pytest.raises(DesignerError, match="smaller margin"):
        area.inset(L_SHAPE, 60.0)


# ----------------------------------------------------------------------- layouts
def test_grid_spans_the_inset_rectangle():
    xy = gcp_layout.grid(4, 3, area.rectangle(0, 0, 300, 200), margin_m=20.0)
    assert xy.shape == (12, 2)
    assert np.allclose(np.unique(xy[:, 0]), [20, 106.666666667, 193.333333333, 280])
    assert np.allclose(np.unique(xy[:, 1]), [20, 100, 180])
    one = gcp_layout.grid(1, 1, area.rectangle(0, 0, 300, 200))
    assert np.allclose(one, [[150, 100]])
    l_grid = gcp_layout.grid(5, 5, L_SHAPE, margin_m=5.0)
    assert 0 < len(l_grid) < 25
    assert np.all(area.distance_to_boundary_m(L_SHAPE, l_grid) >= 5.0 - 1e-9)


def test_perimeter_and_centre_puts_corners_first():
    rect = area.rectangle(0, 0, 400, 200)
    five = gcp_layout.perimeter_and_centre(5, rect, margin_m=10)
    assert np.allclose(five, [[10, 10], [390, 10], [390, 190], [10, 190], [200, 100]])
    nine = gcp_layout.perimeter_and_centre(9, area.rectangle(0, 0, 400, 400), margin_m=10)
    assert np.allclose(nine, [[10, 10], [200, 10], [390, 10], [390, 200], [390, 390],
                              [200, 390], [10, 390], [10, 200], [200, 200]])
    # extra points split the longest remaining piece: the 380 m edges get two each
    # (pieces of 126.7 m) before a 180 m edge gets one
    seven = gcp_layout.perimeter_and_centre(9, rect, margin_m=10)
    assert np.count_nonzero(np.isclose(seven[:, 1], 10)) == 4
    assert np.allclose(gcp_layout.perimeter_and_centre(1, rect), [[200, 100]])
    three = gcp_layout.perimeter_and_centre(3, L_SHAPE, margin_m=5)
    assert area.contains(L_SHAPE, three).all()


def test_random_stratified_is_seeded_spaced_stratified_and_inside():
    square = area.rectangle(0, 0, 400, 400) + ORIGIN_WORLD[:2]
    a = gcp_layout.random_stratified(16, square, min_spacing_m=30.0, seed=4)
    b = gcp_layout.random_stratified(16, square, min_spacing_m=30.0, seed=4)
    c = gcp_layout.random_stratified(16, square, min_spacing_m=30.0, seed=5)
    assert np.array_equal(a, b) and not np.array_equal(a, c)
    assert min_distance(a) >= 30.0
    assert area.contains(square, a).all()
    # one point in each 100 m × 100 m stratum
    cells = np.floor((a - ORIGIN_WORLD[:2]) / 100.0).astype(int)
    assert len({tuple(k) for k in cells}) == 16
    for seed in range(5):
        xy = gcp_layout.random_stratified(12, L_SHAPE, min_spacing_m=40.0, seed=seed)
        assert xy.shape == (12, 2)
        assert area.contains(L_SHAPE, xy).all()
        assert min_distance(xy) >= 40.0


def test_random_stratified_dense_request_still_honours_spacing():
    # about 70 % of the disc-packing bound: stratified attempts may fail, the fallback works
    xy = gcp_layout.random_stratified(40, area.rectangle(0, 0, 100, 100), 14.0, seed=2)
    assert len(xy) == 40 and min_distance(xy) >= 14.0


def test_too_many_gcps_for_the_spacing_is_a_clear_error():
    with pytest.raises(DesignerError, match="at most"):
        gcp_layout.random_stratified(200, area.rectangle(0, 0, 100, 100), 20.0, seed=1)
    with pytest.raises(DesignerError, match="could not place"):
        gcp_layout.random_stratified(60, area.rectangle(0, 0, 100, 100), 14.0, seed=1,
                                     max_attempts=2)
    with pytest.raises(DesignerError, match="whole number"):
        gcp_layout.random_stratified(0, L_SHAPE, 1.0, seed=1)


def test_manual_positions_are_checked_against_the_area():
    xy = gcp_layout.manual([[10, 10], [50, 250]], L_SHAPE)
    assert xy.dtype == float and xy.shape == (2, 2)
    with pytest.raises(DesignerError, match="outside the survey area"):
        gcp_layout.manual([[10, 10], [250, 250]], L_SHAPE)


# -------------------------------------------------------------------------- roles
def test_assign_roles():
    roles = gcp_layout.assign_roles(10, 3, seed=8)
    assert roles.shape == (10,) and list(roles).count("check") == 3
    assert np.array_equal(roles, gcp_layout.assign_roles(10, 3, seed=8))
    spread = gcp_layout.assign_roles(10, 3, pattern="interleaved")
    assert list(np.flatnonzero(spread == "check")) == [1, 5, 8]
    given = ["check", "control", "control", "check"]
    assert list(gcp_layout.assign_roles(4, 2, pattern=given)) == given
    with pytest.raises(DesignerError, match="not 3"):
        gcp_layout.assign_roles(4, 3, pattern=given)
    with pytest.raises(DesignerError, match="between 0"):
        gcp_layout.assign_roles(4, 5, seed=1)
    with pytest.raises(DesignerError, match="either a seed or a pattern"):
        gcp_layout.assign_roles(4, 1)


# ----------------------------------------------------------------- survey error
def test_true_positions_sit_on_the_terrain():
    hf = hilly_terrain(x0=ORIGIN_WORLD[:2][0], y0=ORIGIN_WORLD[:2][1])
    xy = gcp_layout.random_stratified(10, area.heightfield_area(hf), 20.0, seed=3)
    xyz = gcp_layout.true_gcp_xyz(xy, hf)
    assert np.allclose(xyz[:, 2], hf.height_at(xy[:, 0], xy[:, 1]), atol=0, rtol=0)
    with pytest.raises(DesignerError, match="outside the terrain"):
        gcp_layout.true_gcp_xyz([[0.0, 0.0]], hf)


def test_simulated_survey_error_statistics():
    true = np.tile([ORIGIN_WORLD[:2][0], ORIGIN_WORLD[:2][1], 300.0], (100_000, 1))
    surveyed = gcp_layout.simulate_survey_error(true, sigma_h_m=0.02, sigma_v_m=0.05, seed=9)
    err = surveyed - true
    assert np.allclose(err.std(axis=0), [0.02, 0.02, 0.05], rtol=0.02)
    assert np.all(np.abs(err.mean(axis=0)) < 4 * np.array([0.02, 0.02, 0.05]) / np.sqrt(1e5))
    assert np.array_equal(surveyed, gcp_layout.simulate_survey_error(true, 0.02, 0.05, seed=9))
    assert np.all(true[:, 2] == 300.0)
    with pytest.raises(DesignerError, match="sigma_v_m"):
        gcp_layout.simulate_survey_error(true, 0.02, -1.0, seed=9)
