"""The light map folded into a detail bake over part of the terrain reads it as Blender
and the single bake's resize do."""

from __future__ import annotations

import cv2
import numpy as np

from designer.render.terrain_bake import sample_light_rect


def test_the_whole_square_matches_the_single_bakes_resize():
    light = np.random.default_rng(3).random((37, 53)).astype(np.float32)
    out = sample_light_rect(light, (211, 149), (0.0, 1.0, 0.0, 1.0))
    ref = cv2.resize(light, (149, 211), interpolation=cv2.INTER_LINEAR)
    np.testing.assert_allclose(out, ref, atol=2e-3)


def test_a_sub_rectangle_is_the_same_surface_as_the_whole():
    y, x = np.mgrid[0:64, 0:80].astype(np.float32)
    light = 0.3 + 0.002 * x + 0.003 * y  # a plane: bilinear reads it exactly inside
    out = sample_light_rect(light, (40, 50), (0.25, 0.75, 0.2, 0.6))
    # texel centre (row r, column c) of the rectangle, in light-map pixels
    u = 0.25 + (np.arange(50) + 0.5) / 50 * 0.5
    v = 0.6 - (np.arange(40) + 0.5) / 40 * 0.4
    px, py = u * 80 - 0.5, (1 - v) * 64 - 0.5
    np.testing.assert_allclose(out, 0.3 + 0.002 * px[None, :] + 0.003 * py[:, None],
                               atol=1e-5)
