import numpy as np
import pytest

from designer.core.projection import project_points
from designer.core.raycast import TerrainRaycaster
from designer.survey import area, coverage, gcp_layout
from designer.survey.flight import plan_flight
from designer.survey.visibility import visible_pairs
from tests.survey.scenes import refined, sight_clearance_deg
from tests.synthetic import ORIGIN_WORLD, flat_terrain, hilly_terrain, phantom4

SQUARE = area.rectangle(200, 200, 600, 600)


def flat_plan(**kw):
    hf = flat_terrain(size_m=800.0, spacing_m=5.0)
    params = dict(altitude_agl_m=100.0, front_overlap_fraction=0.8, side_overlap_fraction=0.7,
                  heightfield=hf)
    params.update(kw)
    return plan_flight(SQUARE, phantom4(), **params), hf


def brute_force_visible(P, C, R, cam, hf, tol_m):
    """(M, N) visibility from project_points and one Heightfield.intersect_rays per
    in-image pair (on the same surface refined 4×, so its marching steps a quarter cell):
    seen when the first hit from the camera is no closer than the point − tol."""
    proj = project_points(P, C, R, cam)
    m, n = np.nonzero(proj.in_image)
    ray = P[n] - C[m]
    hit = refined(hf, 4).intersect_rays(C[m], ray)
    hit_dist = np.linalg.norm(hit - C[m], axis=1)
    visible = np.zeros(proj.in_image.shape, dtype=bool)
    visible[m, n] = np.isnan(hit_dist) | (hit_dist >= np.linalg.norm(ray, axis=1) - tol_m)
    return visible


def assert_disagreements_only_graze(fast, brute, P, C, hf, tol_m, max_share):
    """Where the two visibility matrices differ, the sight line grazes the terrain
    (passes within 1° of it); such pairs are rare."""
    m, n = np.nonzero(fast != brute)
    assert len(m) <= max_share * brute.sum()
    if len(m):
        clearance = sight_clearance_deg(P[n], C[m], hf, tol_m)
        assert np.all(np.abs(clearance) < 1.0), clearance
        # and there the dense sampling sides with the fast search
        assert np.array_equal(clearance > 0, fast[m, n])


# --------------------------------------------------------------------- overlaps, GSD
@pytest.mark.parametrize(
    ("orientation", "grid_angle", "front", "side", "crosshatch"),
    [("landscape", 0.0, 0.8, 0.7, False), ("landscape", 30.0, 0.75, 0.6, True),
     ("portrait", 0.0, 0.8, 0.7, False), ("portrait", 63.0, 0.65, 0.8, False)],
)
def test_on_flat_ground_measured_overlap_equals_the_request(
        orientation, grid_angle, front, side, crosshatch):
    plan, hf = flat_plan(front_overlap_fraction=front, side_overlap_fraction=side,
                         orientation=orientation, grid_angle_deg=grid_angle,
                         crosshatch=crosshatch)
    result = coverage.analyse_plan(plan, phantom4(), hf, SQUARE, cell_m=10.0)
    inside = result.station_inside_area
    st = result.stations
    f = st.front_overlap[inside]
    s = np.concatenate([st.side_overlap_prev[inside], st.side_overlap_next[inside]])
    f, s = f[np.isfinite(f)], s[np.isfinite(s)]
    assert len(f) > 50 and len(s) > 50
    assert np.max(np.abs(f - front)) < 0.01
    assert np.max(np.abs(s - side)) < 0.01
    summary = result.summary()
    assert summary["front_overlap_median"] == pytest.approx(front, abs=0.01)
    assert summary["side_overlap_min"] == pytest.approx(side, abs=0.01)
    assert np.allclose(st.gsd_centre_m, plan.calc.gsd_m, rtol=1e-6)
    assert np.allclose(st.gsd_min_m, plan.calc.gsd_m, rtol=1e-6)
    assert np.allclose(st.gsd_max_m, plan.calc.gsd_m, rtol=1e-6)
    # every node of the area is seen by at least front-count × side-count images
    least = int(1 / (1 - front) + 1e-9) * int(1 / (1 - side) + 1e-9)
    assert result.coverage.count[result.coverage.grid.inside_area].min() >= least
    assert result.coverage.shares == {2: 1.0, 3: 1.0, 5: 1.0}


def test_a_concave_area_is_covered_to_its_edges():
    hf = flat_terrain(size_m=800.0, spacing_m=5.0)
    l_shape = np.array([[200, 200], [600, 200], [600, 330], [330, 330], [330, 600],
                        [200, 600]], float)
    plan = plan_flight(l_shape, phantom4(), altitude_agl_m=60.0, front_overlap_fraction=0.8,
                       side_overlap_fraction=0.7, heightfield=hf, grid_angle_deg=40.0)
    cover = coverage.coverage_map(coverage.ground_grid(hf, l_shape, cell_m=5.0),
                                  plan.C_world, plan.R_cam_to_world, phantom4(), None)
    assert cover.count[cover.grid.inside_area].min() >= 5 * 3
    assert cover.grid.inside_area.sum() > 0.9 * area.polygon_area_m2(l_shape) / 25


def test_overlap_drops_where_the_ground_rises_under_a_constant_altitude():
    hf = hilly_terrain(relief_m=40.0)
    poly = area.rectangle(60, 60, 340, 340)
    kw = dict(altitude_agl_m=60.0, front_overlap_fraction=0.8, side_overlap_fraction=0.7,
              heightfield=hf)
    const = plan_flight(poly, phantom4(), altitude_mode="constant", altitude_reference="min",
                        **kw)
    follow = plan_flight(poly, phantom4(), altitude_mode="terrain_following", **kw)
    rc = TerrainRaycaster(hf)
    a = coverage.analyse_stations(const.stations, phantom4(), rc)
    b = coverage.analyse_stations(follow.stations, phantom4(), rc)
    # above the lowest point every other station is lower above ground: finer GSD, less overlap
    assert np.nanmax(a.gsd_centre_m) <= const.calc.gsd_m * (1 + 1e-9)
    assert np.nanmedian(a.gsd_centre_m) < 0.8 * const.calc.gsd_m
    assert np.nanmedian(a.front_overlap) < 0.75
    # terrain following keeps the principal ray's GSD (the ground right below is hit)
    assert np.allclose(b.gsd_centre_m, follow.calc.gsd_m, rtol=1e-4)
    assert abs(np.nanmedian(b.front_overlap) - 0.8) < 0.03


# ------------------------------------------------------------------ ray casting
def test_first_hit_agrees_with_the_core_ray_marcher():
    rng = np.random.default_rng(21)
    for x0, y0 in ((0.0, 0.0), tuple(ORIGIN_WORLD[:2])):
        hf = hilly_terrain(x0=x0, y0=y0, relief_m=50.0)
        rc = TerrainRaycaster(hf)
        n = 3000
        origins = np.column_stack([x0 + rng.uniform(0, 400, n), y0 + rng.uniform(0, 400, n),
                                   rng.uniform(160, 250, n)])
        dirs = np.column_stack([rng.normal(0, 0.6, n), rng.normal(0, 0.6, n), -np.ones(n)])
        dirs[:100, 2] = 0.05  # rising rays: misses
        fast = rc.first_hit(origins, dirs, tol_m=1e-4)
        slow = refined(hf, 2).intersect_rays(origins, dirs, tol_m=1e-6)
        miss_fast, miss_slow = np.isnan(fast[:, 0]), np.isnan(slow[:, 0])
        # the core misses a crossing in its last step before a ray leaves the grid
        differ = miss_fast != miss_slow
        assert np.all(miss_slow[differ])
        near_edge = ~hf.contains(*(fast[differ, :2] + 2.0).T) | ~hf.contains(
            *(fast[differ, :2] - 2.0).T)
        assert near_edge.all() and differ.sum() < 10
        assert 100 <= miss_fast.sum() < n - 1000
        both = ~miss_fast & ~miss_slow
        assert np.max(np.abs(fast[both] - slow[both])) < 0.01


def test_a_ray_entering_the_grid_below_the_surface_is_blocked():
    hf = flat_terrain(size_m=100.0, spacing_m=10.0, height_m=100.0)
    rc = TerrainRaycaster(hf)
    hit = rc.first_hit([[-10.0, 50.0, 95.0], [-10.0, 50.0, 105.0]], [[1.0, 0.0, 0.0]] * 2)
    assert np.allclose(hit[0], [0.0, 50.0, 95.0]) and np.isnan(hit[1]).all()
    ground = np.array([[50.0, 50.0, 100.0]] * 3)
    cameras = np.array([[-10.0, 50.0, 95.0], [-10.0, 50.0, 120.0], [50.0, 50.0, 90.0]])
    assert list(rc.occluded(ground, cameras)) == [True, False, True]


def test_gcp_visibility_agrees_with_brute_force_ray_casting():
    # cameras stay over the terrain, so every sight line runs above the grid (see
    # test_a_ray_entering_the_grid_below_the_surface_is_blocked for the other case)
    hf = hilly_terrain(x0=ORIGIN_WORLD[:2][0], y0=ORIGIN_WORLD[:2][1], size_m=600.0, relief_m=60.0)
    rc = TerrainRaycaster(hf)
    cam = phantom4()
    survey = area.inset(area.heightfield_area(hf), 150.0)
    plan = plan_flight(survey, cam, altitude_agl_m=40.0,
                       front_overlap_fraction=0.6, side_overlap_fraction=0.5, heightfield=hf,
                       altitude_reference="mean", forward_tilt_deg=45.0, crosshatch=True)
    assert hf.contains(plan.C_world[:, 0], plan.C_world[:, 1]).all()
    xy = gcp_layout.random_stratified(40, survey, 10.0, seed=1)
    P = gcp_layout.true_gcp_xyz(xy, hf)
    C, R = plan.C_world, plan.R_cam_to_world
    tol = 0.01
    vis = coverage.gcp_visibility(P, C, R, cam, rc, tol_m=tol)
    fast = np.zeros((len(C), len(P)), dtype=bool)
    for g, images in enumerate(vis.images):
        fast[images, g] = True
    brute = brute_force_visible(P, C, R, cam, hf, tol)
    in_image = project_points(P, C, R, cam).in_image
    assert brute.sum() > 200 and (in_image & ~brute).sum() > 200  # seen and hidden both
    assert_disagreements_only_graze(fast, brute, P, C, hf, tol, max_share=0.01)
    assert np.array_equal(vis.counts, fast.sum(axis=0))
    # pixel positions are the projections
    g = int(np.argmax(vis.counts))
    uv = project_points(P[g:g + 1], C[vis.images[g]], R[vis.images[g]], cam).uv_px[:, 0]
    assert np.allclose(vis.uv_px[g], uv)


def test_coverage_counts_agree_with_brute_force_and_culling_changes_nothing():
    hf = hilly_terrain(relief_m=60.0)
    rc = TerrainRaycaster(hf)
    cam = phantom4()
    plan = plan_flight(area.rectangle(100, 100, 300, 300), cam, altitude_agl_m=50.0,
                       front_overlap_fraction=0.7, side_overlap_fraction=0.6, heightfield=hf,
                       altitude_mode="terrain_following", forward_tilt_deg=35.0,
                       grid_angle_deg=20.0)
    grid = coverage.ground_grid(hf, area.rectangle(80, 80, 320, 320), cell_m=12.0)
    C, R = plan.C_world, plan.R_cam_to_world
    cover = coverage.coverage_map(grid, C, R, cam, rc)
    P = grid.points_world()
    brute = brute_force_visible(P, C, R, cam, hf, 0.01)
    fast = np.zeros_like(brute)
    pairs = visible_pairs(P, C, R, cam, rc)
    fast[pairs.camera, pairs.point] = True
    assert np.array_equal(cover.count.ravel(), fast.sum(axis=0))
    assert_disagreements_only_graze(fast, brute, P, C, hf, 0.01, max_share=0.01)
    # without occlusion: exactly the in-image counts of project_points on every point
    no_occ = visible_pairs(P, C, R, cam, None).counts(len(P))
    assert np.array_equal(no_occ, project_points(P, C, R, cam).in_image.sum(axis=0))
    assert (no_occ > cover.count.ravel()).sum() > 20  # the terrain hides something


def test_analysis_of_a_utm_sized_plan_equals_its_local_twin():
    results = []
    for shift in (np.zeros(2), ORIGIN_WORLD[:2]):
        hf = hilly_terrain(x0=shift[0], y0=shift[1])
        poly = area.rectangle(50, 50, 350, 350) + shift
        plan = plan_flight(poly, phantom4(), altitude_agl_m=70.0, heightfield=hf,
                           altitude_mode="terrain_following", grid_angle_deg=10.0)
        gcps = gcp_layout.true_gcp_xyz(gcp_layout.grid(3, 3, poly, margin_m=20.0), hf)
        results.append(coverage.analyse_plan(plan, phantom4(), hf, poly, gcp_xyz=gcps))
    a, b = results
    assert np.array_equal(a.coverage.count, b.coverage.count)
    assert np.array_equal(a.gcps.counts, b.gcps.counts)
    assert np.allclose(a.stations.front_overlap, b.stations.front_overlap, atol=1e-6,
                       equal_nan=True)
    assert np.allclose(a.stations.gsd_mean_m, b.stations.gsd_mean_m, rtol=1e-6)
    summary = b.summary()
    assert summary["gcps_in_fewer_than_3_images"] == 0
    assert summary["gcp_views_min"] >= 3
    assert summary["render_time_s"] is None


def test_rays_past_the_edge_see_void_not_the_side_of_the_ground():
    """A line flown along the terrain's east edge, just outside it: rays that pass the
    edge going down would enter the solid ground's side tens of metres below the surface;
    they see void, and each station's GSD and front overlap are those of the ground it
    does see."""
    hf = hilly_terrain(relief_m=8.0)  # x, y in 0..400 m, ground 92..108 m
    strip = area.rectangle(380, 100, 460, 300)
    plan = plan_flight(strip, phantom4(), altitude_agl_m=60.0, front_overlap_fraction=0.8,
                       side_overlap_fraction=0.7, heightfield=hf, grid_angle_deg=0.0)
    rc = TerrainRaycaster(hf)
    st = coverage.analyse_stations(plan.stations, phantom4(), rc)
    C = plan.C_world
    past = C[:, 0] > 400.0
    assert past.sum() >= 5
    # a station 10 m out sees the ground beside it at 50–70 m: nothing farther
    near = past & (C[:, 0] < 430.0)
    assert near.any()
    depth_max = C[:, 2] - 92.0
    nominal = plan.calc.gsd_m / plan.calc.altitude_agl_m
    assert np.all(st.gsd_max_m[near] <= 1.05 * nominal * depth_max[near]), st.gsd_max_m[near]
    assert np.all(np.isnan(st.centre_ground_xyz[past]))
    f = st.front_overlap[near]
    assert np.isfinite(f).sum() >= 3
    assert np.nanmin(f) == pytest.approx(0.8, abs=0.03)
    # the raycaster's solid ground still stops the ray at the side (occlusion needs it)
    c = np.array([[410.0, 200.0, 160.0]])
    down = np.array([[-0.05, 0.0, -1.0]])
    assert rc.first_hit(c, down)[0, 2] < 0.0
    assert np.isnan(rc.surface_hit(c, down)).all()


def test_triangle_shares_skip_borders_that_cross_no_triangle_and_agree_exactly():
    """Borders whose samples lie all on one side give 1 or 0 without the triangles (the
    plan figures of a 5,000-image block); the shares are the same numbers as every
    triangle measured."""
    rng = np.random.default_rng(5)
    k = 9
    margins = rng.normal(0.0, 50.0, (40, 4, k, k))
    margins[:10] = np.abs(margins[:10])          # the other image holds every sample
    margins[10:20, 1] = -np.abs(margins[10:20, 1])  # one border leaves it out
    margins[20:25, :, :, 0] = 0.0               # samples on the border count inside
    a, b, c = coverage._triangles(margins)
    every_triangle = np.prod(_every_triangle_share(a, b, c), axis=1)
    assert np.array_equal(coverage._triangle_shares(margins), every_triangle, equal_nan=True)


def _every_triangle_share(p, q, r):
    """The share of every triangle, each measured (the formula before the skips)."""
    n_pos = (p >= 0).astype(int) + (q >= 0) + (r >= 0)
    lone_is_p = ((p >= 0) != (q >= 0)) & ((p >= 0) != (r >= 0))
    lone_is_q = ~lone_is_p & ((q >= 0) != (p >= 0))
    x = np.where(lone_is_p, p, np.where(lone_is_q, q, r))
    y = np.where(lone_is_p, q, p)
    z = np.where(lone_is_p | lone_is_q, r, q)
    with np.errstate(invalid="ignore", divide="ignore"):
        corner = x * x / ((x - y) * (x - z))
    return np.select([n_pos == 3, n_pos == 0, n_pos == 1], [1.0, 0.0, corner], 1.0 - corner)


def test_visible_pairs_are_the_same_whatever_the_projection_batches(monkeypatch):
    """Cameras are taken in batches of about PROJECTION_BATCH candidates (a camera's run
    is never split); small batches, one camera per batch at the extreme, give the same
    pairs in the same order; the candidates found strip by strip (_BoxIndex) are every
    point each camera sees, also for a camera whose footprint box is infinite."""
    from designer.core.rotation import rotation_from_opk
    from designer.survey import visibility

    hf = hilly_terrain(relief_m=60.0)
    rc = TerrainRaycaster(hf)
    cam = phantom4()
    plan = plan_flight(area.rectangle(100, 100, 300, 300), cam, altitude_agl_m=50.0,
                       front_overlap_fraction=0.7, side_overlap_fraction=0.6, heightfield=hf,
                       forward_tilt_deg=35.0, grid_angle_deg=20.0)
    P = coverage.ground_grid(hf, area.rectangle(80, 80, 320, 320), cell_m=12.0).points_world()
    # and a camera looking at the horizon (its footprint box is infinite)
    C = np.vstack([plan.C_world, plan.C_world[:1]])
    R = np.concatenate([plan.R_cam_to_world, rotation_from_opk(0.0, np.radians(-80.0), 0.0)[None]])
    boxes = visibility.footprint_boxes(C, R, cam, 0.0, 100.0)
    assert np.isinf(boxes[-1]).all() and np.isfinite(boxes[:-1]).all()
    whole = visible_pairs(P, C, R, cam, rc, border_px=10.0)
    assert whole.camera.size > 1000 and (whole.camera == len(C) - 1).sum() > 10
    for m in range(len(C)):  # each camera's points in the order of their x (ties: index)
        mine = whole.point[whole.camera == m]
        assert np.array_equal(mine, np.sort(mine)[np.argsort(P[np.sort(mine), 0],
                                                             kind="stable")])
    for batch in (5000, 1):
        monkeypatch.setattr(visibility, "PROJECTION_BATCH", batch)
        part = visible_pairs(P, C, R, cam, rc, border_px=10.0)
        for name in ("camera", "point", "uv_px", "depth_m"):
            assert np.array_equal(getattr(part, name), getattr(whole, name)), name
    # without occlusion: every point in the image (past the border), none more
    bare = visible_pairs(P, C, R, cam, None, border_px=10.0)
    in_image = project_points(P, C, R, cam)
    W, H = cam.image_size_px
    for m in range(len(C)):
        uv = in_image.uv_px[m]
        with np.errstate(invalid="ignore"):
            seen = (in_image.in_image[m] & (uv[:, 0] >= 10.0) & (uv[:, 0] <= W - 10.0)
                    & (uv[:, 1] >= 10.0) & (uv[:, 1] <= H - 10.0))
        assert np.array_equal(np.sort(bare.point[bare.camera == m]), np.flatnonzero(seen))
