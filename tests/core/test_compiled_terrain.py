"""The terrain's compiled loops (designer/core/csrc/terrain.c) give, to the last bit, what
the same steps written in numpy give: the ray caster's sphere-tracing march and the world
noise's octaves. The numpy steps here are the oracle (they were the implementation)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from designer.core.heightfield import Heightfield
from designer.core.raycast import TerrainRaycaster
from designer.scene.world_noise import _splitmix64, octave_sum


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


def numpy_clip(rc, org, d, t0, t1):
    """[t0, t1] narrowed to where the ray is over the grid and not above its top."""
    x0, x1, y0, y1 = rc._box
    for axis, lo, hi in ((0, x0, x1), (1, y0, y1), (2, -np.inf, rc.z_max_m)):
        o, v = org[:, axis], d[:, axis]
        with np.errstate(divide="ignore", invalid="ignore"):
            ta, tb = (lo - o) / v, (hi - o) / v
        flat = v == 0
        inside = (o >= lo) & (o <= hi)
        t0 = np.where(flat, np.where(inside, t0, np.inf), np.maximum(t0, np.minimum(ta, tb)))
        t1 = np.where(flat, np.where(inside, t1, -np.inf), np.minimum(t1, np.maximum(ta, tb)))
    return t0, t1


def numpy_range_max(tables, i0, i1, j0, j1):
    ky = np.frexp((i1 - i0 + 1).astype(float))[1] - 1
    kx = np.frexp((j1 - j0 + 1).astype(float))[1] - 1
    out = np.empty(len(i0))
    for r in range(len(i0)):
        T = tables[(int(kx[r]), int(ky[r]))]
        a, b = i0[r], i1[r] - (1 << int(ky[r])) + 1
        c, e = j0[r], j1[r] - (1 << int(kx[r])) + 1
        out[r] = max(max(T[a, c], T[a, e]), max(T[b, c], T[b, e]))
    return out


def numpy_bounds(rc, tables, org, d, t0, t1):
    """The highest terrain and steepest slope over the box each ray's stretch spans."""
    a = org + t0[:, None] * d
    b = org + np.where(np.isfinite(t1), t1, t0)[:, None] * d
    lo, hi = np.minimum(a, b), np.maximum(a, b)

    def cell(x, x0, dx, n):
        return np.clip(np.floor((x - x0) / dx), 0, n - 2).astype(np.intp) // rc._block

    pad_x, pad_y = 1e-6 * rc._dx, 1e-6 * rc._dy
    i0, i1 = cell(lo[:, 1] - pad_y, rc._y0, rc._dy, rc._ny), cell(hi[:, 1] + pad_y, rc._y0,
                                                                   rc._dy, rc._ny)
    j0, j1 = cell(lo[:, 0] - pad_x, rc._x0, rc._dx, rc._nx), cell(hi[:, 0] + pad_x, rc._x0,
                                                                   rc._dx, rc._nx)
    return (numpy_range_max(tables[0], i0, i1, j0, j1),
            numpy_range_max(tables[1], i0, i1, j0, j1))


def numpy_cast(rc, tables, org, d, t0, t1, touch_m, min_step_m, max_iter):
    """(hit, t of the rays still going, their indices): the compiled cast's steps in
    numpy — clipped, bounded, narrowed below the highest terrain, then marched."""
    t0, t1 = numpy_clip(rc, org, d, t0.copy(), t1.copy())
    live = np.flatnonzero(t0 <= t1)
    zmax, slope = numpy_bounds(rc, tables, org[live], d[live], t0[live], t1[live])
    dz, oz = d[live, 2], org[live, 2]
    with np.errstate(divide="ignore", invalid="ignore"):
        t_top = (zmax - oz) / dz
    a = np.where(dz < 0, np.maximum(t0[live], t_top), t0[live])
    b = np.where(dz > 0, np.minimum(t1[live], t_top), t1[live])
    b = np.where((dz == 0) & (oz > zmax), -np.inf, b)
    rate = np.zeros(len(org))
    rate[live] = -dz + slope * np.hypot(d[live, 0], d[live, 1])
    t0[live], t1[live] = a, b
    marched = live[a <= b]
    hit = np.full(len(org), np.nan)
    h, t, idx = numpy_march(rc, org[marched], d[marched], t0[marched], rate[marched],
                            t1[marched], touch_m, min_step_m, max_iter)
    hit[marched] = h
    return hit, t, marched[idx]


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
def test_the_cast_is_the_numpy_steps_to_the_bit(touch_m, min_step_m, max_iter):
    from designer.core.raycast import _block_reduce, _range_max_table

    rng = np.random.default_rng(8)
    ny, nx = 61, 83
    z = rng.normal(100.0, 3.0, (ny, nx)).cumsum(axis=1) * 0.05 + 100.0
    hf = Heightfield(5.0e5, 5.2e6, 0.5, 0.5, z)
    rc = TerrainRaycaster(hf)
    # the oracle's tables, built as the ray caster builds them
    cell_max = np.maximum(np.maximum(z[:-1, :-1], z[:-1, 1:]),
                          np.maximum(z[1:, :-1], z[1:, 1:]))
    ex, ey = np.abs(np.diff(z, axis=1)) / 0.5, np.abs(np.diff(z, axis=0)) / 0.5
    cell_slope = np.hypot(np.maximum(ex[:-1], ex[1:]), np.maximum(ey[:, :-1], ey[:, 1:]))
    tables = (_range_max_table(_block_reduce(cell_max, 8, -np.inf)),
              _range_max_table(_block_reduce(cell_slope, 8, 0.0)))
    n = 4000
    # origins over, beside and below the grid, UTM-sized
    org = np.column_stack([rng.uniform(5.0e5 - 20, 5.0e5 + 61, n),
                           rng.uniform(5.2e6 - 20, 5.2e6 + 50, n), rng.uniform(90, 200, n)])
    d = rng.normal(size=(n, 3))
    d[: n // 2, 2] = -np.abs(d[: n // 2, 2]) * rng.uniform(0.05, 2.0, n // 2)  # grazing to steep
    d[::17, 2] = 0.0  # level rays
    d[5::31] = (0.0, 0.0, -1.0)  # vertical rays, down and up
    d[6::62] = (0.0, 0.0, 1.0)
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    t0 = np.where(rng.random(n) < 0.1, rng.uniform(0, 5, n), 0.0)
    t1 = np.where(rng.random(n) < 0.2, rng.uniform(1, 60, n), np.inf)
    hit, t_left, idx_left = numpy_cast(rc, tables, org, d, t0, t1, touch_m, min_step_m,
                                       max_iter)
    from designer.core.compiled import cterrain

    t, end = t0.copy(), t1.copy()
    found = np.full(n, np.nan)
    going = np.zeros(n, dtype=np.uint8)
    tb = rc._tables
    x0, x1, y0, y1 = rc._box
    cterrain().cast(rc._zf, rc._nx, rc._ny, rc._x0, rc._y0, rc._dx, rc._dy, tb.top, tb.slope,
                    tb.offset, tb.ncols, rc._block, tb.nkx, tb.nky, tb.top.size, x0, x1, y0, y1,
                    rc.z_max_m, org, d, t, end, touch_m, min_step_m, max_iter, found, going)
    np.testing.assert_array_equal(found, hit)
    np.testing.assert_array_equal(np.flatnonzero(going), idx_left)
    np.testing.assert_array_equal(t[going.view(bool)], t_left)
    assert np.isfinite(hit).sum() > n // 5  # the rays do meet the terrain
    assert np.isnan(hit).sum() > n // 5  # and many miss it


def test_the_cast_refuses_arrays_of_the_wrong_size():
    from designer.core.compiled import cterrain

    z = np.zeros((4, 4))
    one = np.zeros(1)
    with pytest.raises(ValueError, match="origins"):
        cterrain().cast(z, 4, 4, 0.0, 0.0, 1.0, 1.0, one, one, np.zeros(1, dtype=np.int64),
                        np.zeros(1, dtype=np.int64), 8, 1, 1, 1, 0.0, 3.0, 0.0, 3.0, 0.0,
                        np.zeros(5), np.zeros(6), np.zeros(2), np.zeros(2), 0.0, 0.0, 8,
                        np.zeros(2), np.zeros(2, dtype=np.uint8))
