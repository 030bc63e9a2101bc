"""The terrain's compiled loops (designer/core/csrc/terrain.c) give, to the last bit, what
the same steps written in numpy give: the ray caster's sphere-tracing march and the world
noise's octaves. The numpy steps here are the oracle (they were the implementation)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from designer.core.heightfield import Heightfield
from designer.scene.world_noise import _splitmix64, octave_sum
from designer.survey.raycast import TerrainRaycaster


# ------------------------------------------------------------------ the numpy oracles
def _unit(h):
    return (h >> np.uint64(11)).astype(np.float64) * (2.0 / 2.0**53) - 1.0


def _quintic(t):
    return t * t * t * (t * (t * 6.0 - 15.0) + 10.0)


def numpy_octave_sum(seed, stream, wavelength_m, octaves, x, y, persistence, rotate):
    total = np.zeros(np.broadcast(x, y).shape)
    one = np.uint64(1)
    for k in range(octaves):
        spacing = wavelength_m / 2**k
        draw = np.random.default_rng([seed, stream, k])
        offset = draw.uniform(0.0, spacing, 2)
        if rotate:
            angle = draw.uniform(0.0, 2.0 * math.pi)
            c, s = math.cos(angle), math.sin(angle)
            u, v = c * x - s * y, s * x + c * y
        else:
            u, v = x, y
        gx, gy = (u + offset[0]) / spacing, (v + offset[1]) / spacing
        ix, iy = np.floor(gx), np.floor(gy)
        fx, fy = _quintic(gx - ix), _quintic(gy - iy)
        key = _splitmix64(np.uint64(seed) * np.uint64(1 << 8) + np.uint64(16 * stream + k))
        ix, iy = ix.astype(np.int64).view(np.uint64), iy.astype(np.int64).view(np.uint64)

        def lattice(i, j, key=key):
            with np.errstate(over="ignore"):
                return _unit(_splitmix64(_splitmix64(key + i) + j))

        with np.errstate(over="ignore"):
            v00, v10 = lattice(ix, iy), lattice(ix + one, iy)
            v01, v11 = lattice(ix, iy + one), lattice(ix + one, iy + one)
        top = v00 + (v10 - v00) * fx
        bottom = v01 + (v11 - v01) * fx
        total += persistence**k * (top + (bottom - top) * fy)
    return total


def numpy_march(rc, org, d, t, rate, t1, touch_m, min_step_m, max_iter):
    """(hit, t of the rays still going, their indices) after max_iter steps."""
    hit = np.full(len(org), np.nan)
    idx = np.arange(len(org))
    for _ in range(max_iter):
        if idx.size == 0:
            break
        p = org[idx] + t[:, None] * d[idx]
        gap = p[:, 2] - rc.height(p[:, 0], p[:, 1])
        touched = gap <= touch_m
        hit[idx[touched]] = t[touched]
        r, end = rate[idx], t1[idx]
        with np.errstate(divide="ignore", invalid="ignore"):
            t_next = np.minimum(t + np.maximum(gap / r, min_step_m), end)
        going = ~touched & (r > 0) & (t < end)
        idx, t = idx[going], t_next[going]
    return hit, t, idx


# ----------------------------------------------------------------------------- tests
@pytest.mark.parametrize("rotate", [False, True])
def test_octave_sum_is_the_numpy_octaves_to_the_bit(rotate):
    rng = np.random.default_rng(5)
    # UTM-sized and negative coordinates, and points on lattice lines
    x = np.concatenate([rng.uniform(4.9e5, 5.1e5, 3000), rng.uniform(-300, 300, 3000),
                        np.arange(-8.0, 8.0, 0.5)])
    y = np.concatenate([rng.uniform(5.2e6, 5.3e6, 3000), rng.uniform(-300, 300, 3000),
                        np.arange(-8.0, 8.0, 0.5)])
    total, std = octave_sum(11, 3, 120.0, 7, x, y, persistence=0.6, rotate=rotate)
    expected = numpy_octave_sum(11, 3, 120.0, 7, x, y, 0.6, rotate)
    np.testing.assert_array_equal(total, expected)
    assert std > 0 and total.std() > 0.3 * std


def test_octave_sum_broadcasts_a_grid_and_keeps_its_shape():
    x = np.linspace(0, 50, 7)[None, :]
    y = np.linspace(0, 30, 5)[:, None]
    total, _ = octave_sum(2, 0, 40.0, 3, x, y)
    assert total.shape == (5, 7)
    np.testing.assert_array_equal(total, numpy_octave_sum(2, 0, 40.0, 3, x, y, 0.5, False))
    empty, _ = octave_sum(2, 0, 40.0, 3, np.zeros(0), np.zeros(0))
    assert empty.shape == (0,)


@pytest.mark.parametrize("touch_m,min_step_m,max_iter", [(1e-3, 0.0, 64), (0.0, 0.02, 256),
                                                         (1e-3, 0.0, 3)])
def test_the_march_is_the_numpy_steps_to_the_bit(touch_m, min_step_m, max_iter):
    rng = np.random.default_rng(8)
    ny, nx = 61, 83
    z = rng.normal(100.0, 3.0, (ny, nx)).cumsum(axis=1) * 0.05 + 100.0
    hf = Heightfield(5.0e5, 5.2e6, 0.5, 0.5, z)
    rc = TerrainRaycaster(hf)
    n = 4000
    org = np.column_stack([rng.uniform(5.0e5, 5.0e5 + 41, n),
                           rng.uniform(5.2e6, 5.2e6 + 30, n), rng.uniform(150, 200, n)])
    d = rng.normal(size=(n, 3))
    d[:, 2] = -np.abs(d[:, 2]) * rng.uniform(0.05, 2.0, n)  # grazing to steep
    d[::17, 2] = 0.0  # level rays: rate 0 ends them
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    t0 = np.zeros(n)
    t1 = np.where(rng.random(n) < 0.2, rng.uniform(1, 60, n), np.inf)
    rate = -d[:, 2] + 2.5 * np.hypot(d[:, 0], d[:, 1])
    hit, t_left, idx_left = numpy_march(rc, org, d, t0.copy(), rate, t1, touch_m,
                                        min_step_m, max_iter)
    from designer.core.compiled import cterrain

    t = t0.copy()
    found = np.full(n, np.nan)
    going = np.zeros(n, dtype=np.uint8)
    cterrain().march(rc._zf, rc._nx, rc._ny, rc._x0, rc._y0, rc._dx, rc._dy, org, d, t,
                     rate, t1, touch_m, min_step_m, max_iter, found, going)
    np.testing.assert_array_equal(found, hit)
    np.testing.assert_array_equal(np.flatnonzero(going), idx_left)
    np.testing.assert_array_equal(t[going.view(bool)], t_left)
    assert np.isfinite(hit).sum() > n // 4  # the rays do meet the terrain


def test_the_march_refuses_arrays_of_the_wrong_size():
    from designer.core.compiled import cterrain

    z = np.zeros((4, 4))
    with pytest.raises(ValueError, match="origins"):
        cterrain().march(z, 4, 4, 0.0, 0.0, 1.0, 1.0, np.zeros(5), np.zeros(6), np.zeros(2),
                         np.zeros(2), np.zeros(2), 0.0, 0.0, 8, np.zeros(2),
                         np.zeros(2, dtype=np.uint8))
