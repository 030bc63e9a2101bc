"""The corner detector on exact synthetic checkerboards, and the matching rule."""

from __future__ import annotations

import numpy as np

from designer.experiments.corners import Detector, match
from designer.experiments.synthetic import random_board, render


def test_detector_is_unbiased_and_subpixel_on_exact_images():
    rng = np.random.default_rng(3)
    det = Detector()
    errors, expected = [], 0
    for _ in range(40):
        board = random_board(rng, (120, 120))
        found, uv = det.measure(render(board.H_image_from_board, board.size_px),
                                board.corners_uv_px)
        errors.append(uv[found] - board.corners_uv_px[found])
        expected += len(found)
    d = np.concatenate(errors)
    assert len(d) >= 0.95 * expected
    assert np.all(np.abs(d.mean(axis=0)) < 0.01)
    assert 0.02 < d.std() < 0.1


def test_detected_positions_use_designers_pixel_origin():
    # a corner at (20.5, 20.5) in designer's convention is OpenCV's (20, 20)
    H = np.array([[10.0, 0, 20.5], [0, 10.0, 20.5], [0, 0, 1]])
    found, uv = Detector().measure(render(H, (41, 41)), np.array([[20.5, 20.5]]))
    assert found[0]
    assert np.allclose(uv[0], [20.5, 20.5], atol=0.02)


def test_match_keeps_only_mutual_nearest_neighbours_within_the_radius():
    expected = np.array([[10.0, 10.0], [20.0, 10.0], [50.0, 50.0]])
    detected = np.array([[10.3, 10.0], [10.6, 10.0], [53.0, 50.0]])
    found, uv = match(detected, expected, 2.0)
    assert found.tolist() == [True, False, False]
    assert np.allclose(uv[0], [10.3, 10.0])
    assert np.isnan(uv[1:]).all()
    found, _ = match(np.empty((0, 2)), expected, 2.0)
    assert not found.any()
