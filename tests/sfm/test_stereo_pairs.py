"""Rectification, semi-global matching and COLMAP depth-map files on synthetic views.

The images are a random texture on a known plane, warped into each camera by the
plane's homography (OpenCV), so the true depth of every pixel is known.
"""

from __future__ import annotations

import dataclasses

import cv2
import numpy as np
import pytest

from designer.sfm.depth_maps import normals_from_depth, read_colmap_array, write_colmap_array
from designer.sfm.stereo_pairs import (
    View,
    choose_pairs,
    combine_depths,
    disparity_range,
    rectify,
    sgbm_depth,
)

W, H, F = 480, 360, 500.0
TEXTURE_M = 0.05  # metres per texture pixel on the ground plane
GROUND = 200.0  # texture side in metres... of a 4000 px texture at 5 cm


def nadir_view(name, C, kappa_deg=0.0, tilt_deg=(0.0, 0.0)):
    """A CV-frame camera looking down (z forward = −Z world), image top north at κ = 0."""
    k = np.radians(kappa_deg)
    Rz = np.array([[np.cos(k), -np.sin(k), 0], [np.sin(k), np.cos(k), 0], [0, 0, 1]])
    a, b = np.radians(tilt_deg)
    Rx = np.array([[1, 0, 0], [0, np.cos(a), -np.sin(a)], [0, np.sin(a), np.cos(a)]])
    Ry = np.array([[np.cos(b), 0, np.sin(b)], [0, 1, 0], [-np.sin(b), 0, np.cos(b)]])
    R_photo = Rx @ Ry @ Rz  # camera (photogrammetric) to world
    R = np.diag([1.0, -1.0, -1.0]) @ R_photo.T  # world to CV camera
    K = np.array([[F, 0, W / 2], [0, F, H / 2], [0, 0, 1.0]])
    return View(name, K, R, -R @ np.asarray(C, float), W, H)


def plane_height(x, y):
    return 0.02 * x - 0.01 * y  # a tilted ground plane, metres


def render_plane(view, texture):
    """The view's image of the texture lying on the plane z = plane_height(x, y)."""
    # texture pixel (continuous, corner origin) -> world point on the plane
    n = texture.shape[0]
    T = np.array([[TEXTURE_M, 0, -n * TEXTURE_M / 2], [0, -TEXTURE_M, n * TEXTURE_M / 2],
                  [0, 0, 1]])  # (u, v, 1) -> (x, y, 1)
    P = view.K @ np.column_stack([view.R, view.t])
    # world (x, y, 1) -> homogeneous (x, y, z(x, y), 1) is linear for a plane
    lift = np.array([[1, 0, 0], [0, 1, 0], [0.02, -0.01, 0], [0, 0, 1]])
    Hmat = P @ lift @ T
    shift = np.array([[1, 0, -0.5], [0, 1, -0.5], [0, 0, 1.0]])
    unshift = np.array([[1, 0, 0.5], [0, 1, 0.5], [0, 0, 1.0]])
    return cv2.warpPerspective(texture, shift @ Hmat @ unshift, (W, H),
                               flags=cv2.INTER_LINEAR)


@pytest.fixture(scope="module")
def texture():
    rng = np.random.default_rng(7)
    noise = rng.uniform(0, 255, (1000, 1000)).astype(np.float32)
    return cv2.GaussianBlur(cv2.resize(noise, (4000, 4000), interpolation=cv2.INTER_CUBIC),
                            (0, 0), 1.5).clip(0, 255).astype(np.uint8)


def true_depth(view):
    jj, ii = np.meshgrid(np.arange(W) + 0.5, np.arange(H) + 0.5)
    rays_cam = np.linalg.solve(view.K, np.stack([jj.ravel(), ii.ravel(), np.ones(W * H)]))
    rays = view.R.T @ rays_cam  # world directions for depth 1
    C = view.C_local
    # C + s·ray on the plane: C_z + s·r_z = 0.02 (C_x + s r_x) − 0.01 (C_y + s r_y)
    s = (plane_height(C[0], C[1]) - C[2]) / (rays[2] - 0.02 * rays[0] + 0.01 * rays[1])
    return s.reshape(H, W)


@pytest.mark.parametrize("baseline", [(12.0, 0.0, 0.0), (0.0, -10.0, 0.5), (7.0, 7.0, 0.0)])
def test_sgbm_depth_of_a_textured_plane_matches_its_true_depth(texture, baseline):
    ref = nadir_view("a", (0.0, 0.0, 60.0), kappa_deg=10.0, tilt_deg=(2.0, -1.5))
    src = nadir_view("b", np.add((0.0, 0.0, 60.0), baseline), kappa_deg=-5.0,
                     tilt_deg=(-1.0, 2.0))
    pair = rectify(ref, src)
    assert pair is not None
    # the two cameras lie on the rectified x axis: epipolar lines are rows
    c_rect = pair.R_rect @ (src.C_local - ref.C_local)
    assert np.allclose(c_rect, [np.linalg.norm(baseline), 0, 0], atol=1e-9)
    rng = np.random.default_rng(0)
    xy = rng.uniform(-20, 20, (200, 2))
    seen = np.column_stack([xy, plane_height(xy[:, 0], xy[:, 1])])
    depth = sgbm_depth(render_plane(ref, texture), render_plane(src, texture), ref, src, pair,
                       disparity_range(pair, seen, ref))
    truth = true_depth(ref)
    valid = depth > 0
    assert valid.mean() > 0.4  # the overlap, less borders
    rel = (depth[valid] - truth[valid]) / truth[valid]
    # fB/Z is 80-200 px here; SGBM's sub-pixel disparity is good to ~0.15 px (median),
    # i.e. ~0.15 % of the depth, and unbiased: a geometry error (a half-pixel shift, a
    # wrong rectification) would show as a bias of several 0.1 %
    assert abs(np.median(rel)) < 5e-4
    assert np.median(np.abs(rel)) < 2.5e-3
    assert np.quantile(np.abs(rel), 0.99) < 1e-2


def test_views_looking_along_their_baseline_are_not_rectified():
    ref = nadir_view("a", (0.0, 0.0, 60.0))
    src = nadir_view("b", (0.0, 0.0, 40.0))
    assert rectify(ref, src) is None


def test_a_disparity_search_wider_than_the_rectified_image_is_skipped():
    """Sparse points spread from near to far (an oblique view towards the horizon) ask
    for more disparities than the rectified image has columns: the pair is skipped (SGBM
    would fail allocating a negative size), a nadir pair of the same views is not."""
    ref = nadir_view("a", (0.0, 0.0, 60.0))
    src = nadir_view("b", (20.0, 0.0, 60.0))
    pair = rectify(ref, src)
    ground = np.column_stack([np.linspace(-10, 10, 50), np.zeros(50), np.zeros(50)])
    assert disparity_range(pair, ground, ref) is not None
    d_min, num = disparity_range(pair, ground, ref)
    assert pair.size_px[0] + min(d_min, 0) - max(d_min + num, 0) >= 16
    # the same pair over points from 31 m to 59 m below (within a factor of two of the
    # median depth, so none is dropped): fB/Z spans 170 to 330 px, then the 15 % margins
    near = np.column_stack([np.zeros(50), np.zeros(50), np.linspace(1.0, 29.0, 50)])
    wide = dataclasses.replace(pair, size_px=(200, pair.size_px[1]))
    assert disparity_range(wide, near, ref) is None


def test_pairs_prefer_different_epipolar_directions():
    grid = [(x, y) for y in (0.0, 15.0) for x in (0.0, 10.0, 20.0)]
    views = [nadir_view(str(k), (x, y, 60.0)) for k, (x, y) in enumerate(grid)]
    shared = np.full((6, 6), 500)
    shared[0, 1] = shared[1, 0] = 900
    shared[0, 2] = shared[2, 0] = 800
    depth = np.full(6, 60.0)
    # scores shared × sin(baseline angle) for view 0: 1 → 148, 2 → 253, 3 → 121,
    # 4 → 150, 5 → 224; view 2 is best; view 1 lies in the same direction, view 5 36.9°
    # away: the second choice
    assert choose_pairs(views, shared, depth, n_neighbours=2)[0] == [2, 5]
    # with only the strip left, the same direction is taken rather than nothing
    shared[0, 3:] = shared[3:, 0] = 0
    assert choose_pairs(views, shared, depth, n_neighbours=2)[0] == [2, 1]
    # too narrow (< 3°) or too wide (> 40°) baselines are not stereo pairs
    assert choose_pairs(views, shared, np.full(6, 300.0))[0] == [2]
    assert choose_pairs(views, shared, np.full(6, 15.0))[0] == [1]
    assert choose_pairs(views, np.zeros((6, 6), int), depth) == [[]] * 6


def test_combine_depths_keeps_agreement_and_drops_conflict():
    a = np.array([[10.0, 10.0, 0.0, 10.0]], np.float32)
    b = np.array([[10.05, 0.0, 12.0, 11.0]], np.float32)
    assert np.allclose(combine_depths([a, b]), [[10.025, 10.0, 12.0, 0.0]])


def test_colmap_map_files_round_trip_in_colmap_layout(tmp_path):
    rng = np.random.default_rng(1)
    normals = rng.normal(size=(5, 7, 3)).astype(np.float32)
    write_colmap_array(tmp_path / "n.bin", normals)
    raw = (tmp_path / "n.bin").read_bytes()
    assert raw.startswith(b"7&5&3&")
    # channel after channel, each row-major (COLMAP's Mat<float> layout)
    body = np.frombuffer(raw[len(b"7&5&3&"):], "<f4")
    assert body[1] == normals[0, 1, 0] and body[35] == normals[0, 0, 1]
    assert np.array_equal(read_colmap_array(tmp_path / "n.bin"), normals)
    depth = rng.uniform(1, 2, (4, 6)).astype(np.float32)
    write_colmap_array(tmp_path / "d.bin", depth)
    assert np.array_equal(read_colmap_array(tmp_path / "d.bin"), depth)


def test_normals_of_a_plane_face_the_camera():
    view = nadir_view("a", (0.0, 0.0, 60.0), tilt_deg=(3.0, 2.0))
    normals = normals_from_depth(true_depth(view).astype(np.float32), view.K)
    n_true_world = np.array([-0.02, 0.01, 1.0]) / np.linalg.norm([-0.02, 0.01, 1.0])
    n_true_cam = view.R @ n_true_world
    inner = normals[2:-2, 2:-2].reshape(-1, 3)
    assert np.abs(inner - n_true_cam).max() < 1e-3
    assert (inner[:, 2] < 0).all()  # towards the camera (which looks along +z)
