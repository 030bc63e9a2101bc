"""Exact area-sampled checkerboards: the detector baseline's 'perfect renderer'."""

from __future__ import annotations

import numpy as np
import pytest

from designer.experiments.synthetic import coverage, random_board, render


def supersampled(H, size, n=48):
    """White fraction by n × n point samples per pixel (the slow reference)."""
    W, Hh = size
    Hinv = np.linalg.inv(H)
    v, u = np.mgrid[0:Hh, 0:W].astype(float)
    off = (np.arange(n) + 0.5) / n
    acc = np.zeros((Hh, W))
    for oy in off:
        uu, vv = u[None] + off[:, None, None], v[None] + oy
        w = Hinv[2, 0] * uu + Hinv[2, 1] * vv + Hinv[2, 2]
        x = (Hinv[0, 0] * uu + Hinv[0, 1] * vv + Hinv[0, 2]) / w
        y = (Hinv[1, 0] * uu + Hinv[1, 1] * vv + Hinv[1, 2]) / w
        acc += ((np.floor(x) + np.floor(y)) % 2).mean(0)
    return acc / n


def test_axis_aligned_board_has_the_exact_pixel_areas():
    # squares of 4 px, board origin at (1.25, 2.5): column 1 is 0.75 in square -1 (x < 0)
    H = np.array([[4.0, 0, 1.25], [0, 4.0, 2.5], [0, 0, 1]])
    cov = coverage(H, (12, 12))
    # pixel (1, 3): x from 1 to 2 → board x from −0.0625 to 0.1875; y from 3 to 4 → 0.125..0.375
    # white where ⌊x⌋ + ⌊y⌋ odd: x < 0 part (0.25 of the pixel) is in square (−1, 0): white
    assert cov[3, 1] == pytest.approx(0.25, abs=1e-12)
    # pixel (0, 0): board x −0.3125..−0.0625, y −0.625..−0.375: square (−1, −1): black
    assert cov[0, 0] == 0.0
    # pixel (5, 6) straddles x = 1 (u = 5.25) and y = 1 (v = 6.5): 4 quarters
    # areas: left-top 0.25·0.5, right-top 0.75·0.5, left-bottom 0.25·0.5, right-bottom 0.75·0.5
    # squares (0,0) black, (1,0) white, (0,1) white, (1,1) black
    assert cov[6, 5] == pytest.approx(0.75 * 0.5 + 0.25 * 0.5, abs=1e-12)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_coverage_matches_supersampling_under_a_homography(seed):
    rng = np.random.default_rng(seed)
    board = random_board(rng, (40, 40), square_px=(5, 9))
    H = board.H_image_from_board.copy()
    H[2, :2] = rng.normal(0, 1e-3, 2)  # mild perspective
    exact = coverage(H, (40, 40))
    ref = supersampled(H, (40, 40))
    # 48 x 48 point samples resolve an edge's area to a fraction of 1/48
    assert np.abs(exact - ref).max() < 1 / 96
    assert np.abs(exact - ref).mean() < 3e-4
    assert ((exact == 0) | (exact == 1)).mean() > 0.3  # pure pixels stay pure


def test_two_parallel_edges_in_one_pixel_are_refused():
    c = np.cos(np.pi / 4) * 1.2
    H = np.array([[c, -c, 5.0], [c, c, 0.3], [0, 0, 1]])  # 1.2 px squares at 45°
    with pytest.raises(ValueError, match="wider than a pixel's diagonal"):
        coverage(H, (10, 10))
    # axis-parallel 1.2 px squares never put two parallel edges in a pixel: still exact
    H = np.array([[1.2, 0, 0.1], [0, 1.2, 0.7], [0, 0, 1]])
    assert np.abs(coverage(H, (10, 10)) - supersampled(H, (10, 10))).max() < 1 / 96


def test_render_is_srgb_encoded_8_bit():
    H = np.array([[4.0, 0, 1.5], [0, 4.0, 0.0], [0, 0, 1]])  # half a pixel of white at u = 1
    image = render(H, (8, 8))
    assert image.dtype == np.uint8
    assert set(np.unique(image)) <= {0, 188, 255}  # sRGB(0.5) = 0.735 → 188
    assert 188 in image
