"""The published direction of doming held (James & Robson 2014; docs/studies.md, "Doming"):
on a flat block whose tie points leave the radial distortion weakly determined, a
self-calibrated parallel (nadir) block bends into a dome or bowl and a convergent one
(20° forward tilt, alternating with the line direction) does not — processed by
designer's own mapper settings and final adjustment (designer.bench.doming: a synthetic
block, no render). A change to processing that removes the dome of the parallel block,
or puts one into the convergent block, fails here."""

from __future__ import annotations

import numpy as np
import pytest

from designer.bench import doming

pytestmark = pytest.mark.slow

REPLICATES = 3


@pytest.fixture(scope="module")
def results():
    return doming.compare_geometries(doming.SMALL, REPLICATES)


def test_the_parallel_block_domes_and_the_convergent_block_does_not(results):
    nadir = [abs(r.dome_gsd) for r in results["nadir"]]
    convergent = [abs(r.dome_gsd) for r in results["convergent"]]
    print(f"|dome| nadir {np.round(nadir, 2)} GSD, convergent {np.round(convergent, 2)} GSD")
    assert np.mean(nadir) >= 0.5, nadir
    assert np.mean(convergent) <= 0.5 * np.mean(nadir), (nadir, convergent)
    # not one lucky replicate: the parallel block domes more in most replicates
    assert sum(n > c for n, c in zip(nadir, convergent, strict=True)) >= 2


def test_the_convergent_block_is_flat_to_a_fraction_of_a_gsd(results):
    rms = [r.rms_z_gsd for r in results["convergent"]]
    assert max(abs(r.dome_gsd) for r in results["convergent"]) < 0.5
    assert max(rms) < 1.0, rms


def test_the_dome_follows_the_k1_error_beyond_the_focal_trade():
    """A fixed camera wrong by +0.01 in k1 alone domes the nadir block by several GSD
    and the convergent block by less: the dome per unit of k1 error the replicates'
    domes come from (the focal trade itself bends nothing)."""
    nadir = doming.fixed_k1_dome_gsd(doming.SMALL, "nadir", 0.01)
    convergent = doming.fixed_k1_dome_gsd(doming.SMALL, "convergent", 0.01)
    print(f"dome of a k1 error of +0.01: nadir {nadir:+.2f} GSD, convergent {convergent:+.2f} GSD")
    assert 2.0 < nadir < 8.0
    assert 0.0 < convergent < nadir
    assert doming.fixed_k1_dome_gsd(doming.SMALL, "nadir", -0.01) < -2.0


def test_the_focal_trade_bends_nothing():
    """A camera differing from the truth by the exact trade of a flat block (c·f, c²·k1,
    c⁴·k2) has no k1 error beyond it; a k1 error without the trade is all beyond it."""
    from designer.sfm.report import k1_beyond_focal_trade

    true = doming.FlatBlock().true_params()
    c = 0.9
    traded = true.copy()
    traded[:2] *= c
    traded[4] *= c ** 2
    traded[5] *= c ** 4
    assert abs(k1_beyond_focal_trade(traded, true, (640, 480))) < 1e-12
    wrong = true.copy()
    wrong[4] += 0.01
    assert k1_beyond_focal_trade(wrong, true, (640, 480)) == pytest.approx(0.01)
