"""The vectorised rolling-shutter adjustment (designer.sfm.rolling_adjustment with
designer.sfm.rolling_problem, designer.sfm.schur_lm, designer.sfm.full_opencv) against
the per-observation Ceres formulation it replaced (designer.bench.rolling_reference), on
synthetic blocks (designer.bench.synthetic_rolling): the same velocities, points,
per-observation errors and cameras within stated tolerances, and the same problem size."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

pycolmap = pytest.importorskip("pycolmap")

from designer.bench.rolling_reference import adjust_rolling_ceres  # noqa: E402
from designer.bench.synthetic_rolling import BlockSpec, rolling_block  # noqa: E402
from designer.sfm.adjustment import (  # noqa: E402
    MIN_GCP_SIGMA_M,
    ControlPoint,
    PositionPriors,
    adjust,
)
from designer.sfm.full_opencv import full_opencv_params, img_from_cam  # noqa: E402
from designer.sfm.rolling_adjustment import adjust_rolling  # noqa: E402
from designer.sfm.settings import VARIABLE_PARAMS  # noqa: E402

#: the two solutions agree to these (both stop at Ceres's function tolerance 1e-9)
TOL_VELOCITY_M_S = 1e-4
TOL_POINT_M = 1e-4
TOL_ERROR_PX = 1e-4
TOL_CENTRE_M = 1e-4


def test_full_opencv_is_colmaps_projection_with_its_jacobians():
    from pycolmap import cost_functions as cf

    rng = np.random.default_rng(3)
    params = np.array([510.0, 505.0, 201.0, 149.0, -0.12, 0.05, 1e-3, -2e-3, -0.01,
                       0.02, -0.004, 0.001])
    camera = pycolmap.Camera(model="FULL_OPENCV", width=400, height=300, params=params)
    P = np.column_stack([rng.normal(0, 0.4, 50), rng.normal(0, 0.3, 50),
                         rng.uniform(1.0, 5.0, 50)])
    img, imaged, J_P, J_params = img_from_cam(np.tile(params, (50, 1)), P)
    assert imaged.all()
    np.testing.assert_allclose(img, camera.img_from_cam(P), atol=1e-9)
    identity = np.array([0, 0, 0, 1.0, 0, 0, 0])
    for k in range(50):
        r, (J_X, _, J_cam) = cf.ReprojErrorCost(camera.model, np.eye(2), np.zeros(2)) \
            .evaluate(P[k], identity, params)
        np.testing.assert_allclose(r[:, 0], img[k], atol=1e-9)
        np.testing.assert_allclose(J_P[k], J_X, atol=1e-8)
        np.testing.assert_allclose(J_params[k], J_cam, atol=1e-8)
    # a point behind the camera is not imaged (COLMAP's cost: residual 0)
    img, imaged, J_P, _ = img_from_cam(params[None], np.array([[0.1, 0.2, -1.0]]))
    assert not imaged[0] and not np.any(img) and not np.any(J_P)
    # shorter models are FULL_OPENCV's first parameters
    np.testing.assert_array_equal(full_opencv_params("PINHOLE", [1, 2, 3, 4])[4:], 0)
    with pytest.raises(ValueError, match="SIMPLE_RADIAL"):
        full_opencv_params("SIMPLE_RADIAL", [1, 2, 3, 4])


def test_tie_observations_are_the_reconstructions():
    from designer.sfm.observations import tie_observations

    rec, *_ = rolling_block(replace(BlockSpec(), strips=2, per_strip=4, points=400))
    obs = tie_observations(rec)
    ref = sorted((el.image_id, pid, *rec.images[el.image_id].points2D[el.point2D_idx].xy)
                 for pid, pt in rec.points3D.items() for el in pt.track.elements)
    got = sorted(zip(obs.image_id.tolist(), obs.point3D_id.tolist(), *obs.xy.T.tolist(),
                     strict=True))
    assert got == ref
    k = {pid: i for i, pid in enumerate(obs.point_ids.tolist())}
    for pid, pt in rec.points3D.items():
        np.testing.assert_array_equal(obs.point_xyz[k[pid]], pt.xyz)


def _control(rec, true_pts, rng, n=5):
    """Control points at ``n`` tie points' true positions, marked where they are seen."""
    out = []
    for k, pid in enumerate(list(true_pts)[:: max(1, len(true_pts) // n)][:n]):
        marks = tuple((rec.images[el.image_id].name,
                       np.asarray(rec.images[el.image_id].points2D[el.point2D_idx].xy)
                       + rng.normal(0, 0.3, 2))
                      for el in rec.points3D[pid].track.elements)
        out.append(ControlPoint(f"G{k}", true_pts[pid], np.array([0.01, 0.01, 0.015]), marks))
    return out


def _both(block, variable=(), control=(), priors=None, fix_gauge=False, max_iterations=100):
    """(reconstruction, solution, control xyz) of the reference and of the vectorised
    solver, each on its own copy of the block."""
    rec, shutters = block[0], block[3]
    ref, new = pycolmap.Reconstruction(rec), pycolmap.Reconstruction(rec)
    args = (control, 0.5, priors, MIN_GCP_SIGMA_M, max_iterations, fix_gauge)
    return (ref, *adjust_rolling_ceres(ref, variable, shutters, *args)), \
        (new, *adjust_rolling(new, variable, shutters, *args))


def _assert_same(ref, new):
    (rec_a, sol_a, xyz_a), (rec_b, sol_b, xyz_b) = ref, new
    a, b = sol_a.summary, sol_b.summary
    assert a.num_residuals_reduced == b.num_residuals_reduced
    assert a.num_effective_parameters_reduced == b.num_effective_parameters_reduced
    assert str(a.termination_type).split(".")[-1] == b.termination_type
    assert abs(a.num_successful_steps - b.num_successful_steps) <= 1
    assert b.final_cost == pytest.approx(a.final_cost, rel=1e-6)
    assert set(sol_a.velocities) == set(sol_b.velocities)
    for name, v in sol_a.velocities.items():
        np.testing.assert_allclose(sol_b.velocities[name], v, atol=TOL_VELOCITY_M_S)
    for pid, pt in rec_a.points3D.items():
        np.testing.assert_allclose(rec_b.points3D[pid].xyz, pt.xyz, atol=TOL_POINT_M)
    assert set(sol_a.point_errors_px) == set(sol_b.point_errors_px)
    for pid, e in sol_a.point_errors_px.items():
        np.testing.assert_allclose(np.sort(sol_b.point_errors_px[pid]), np.sort(e),
                                   atol=TOL_ERROR_PX)
    for image_id, image in rec_a.images.items():
        np.testing.assert_allclose(rec_b.images[image_id].projection_center(),
                                   image.projection_center(), atol=TOL_CENTRE_M)
    assert set(xyz_a) == set(xyz_b)
    for gid, xyz in xyz_a.items():
        np.testing.assert_allclose(xyz_b[gid], xyz, atol=TOL_POINT_M)
    return rec_a, rec_b


@pytest.fixture(scope="module")
def block():
    rec, true_pts, true_C, shutters = rolling_block(BlockSpec(points=1200), seed=2)
    priors = PositionPriors({n: C.copy() for n, C in true_C.items()}, 0.02, 0.03)
    return rec, true_pts, priors, shutters


def test_with_position_priors_the_solution_is_the_ceres_one(block):
    _assert_same(*_both(block, priors=block[2]))


def test_with_control_points_the_solution_is_the_ceres_one(block):
    control = _control(block[0], block[1], np.random.default_rng(4))
    _assert_same(*_both(block, control=control))


def test_without_a_datum_the_gauge_is_the_ceres_one(block):
    _assert_same(*_both(block, fix_gauge=True))


def test_the_estimated_interior_parameters_are_the_ceres_ones(block):
    """Self-calibration (radial: focal, principal point, k1 k2 k3) for three steps — a
    nadir block leaves it weakly determined, so both stop at the same step count."""
    rec = block[0]
    rec_a, rec_b = _assert_same(*_both(block, VARIABLE_PARAMS["radial"], priors=block[2],
                                       max_iterations=3))
    np.testing.assert_allclose(rec_b.cameras[1].params, rec_a.cameras[1].params,
                               rtol=1e-6, atol=1e-6)
    assert np.any(rec_b.cameras[1].params != rec.cameras[1].params)


def test_the_plain_adjustment_still_takes_control_points(block):
    """COLMAP's own adjustment (no rolling shutter) with control marks and the shared
    set-up (designer.sfm.block_setup): the control points end near their survey."""
    rec, true_pts = block[0], block[1]
    control = _control(rec, true_pts, np.random.default_rng(5))
    plain = pycolmap.Reconstruction(rec)
    result = adjust(plain, "fixed", control, marking_sigma_px=0.3)
    assert result.termination == "CONVERGENCE" and result.sigma0 < 2.0
    for cp in control:
        assert np.linalg.norm(result.control_xyz_local[cp.gcp_id] - cp.surveyed_local) < 0.05


def test_openblas_runs_on_one_thread_inside_the_block_and_as_before_after():
    import scipy.linalg  # noqa: F401  (loads scipy's OpenBLAS)

    from designer.sfm.blas_threads import one_blas_thread, openblas_threads

    before = openblas_threads()
    with one_blas_thread():
        assert all(n == 1 for n in openblas_threads())
    assert openblas_threads() == before


def test_the_benchmark_prints_its_table(capsys):
    from designer.cli.main import main

    assert main(["bench", "rolling-adjustment", "--repeats", "1", "--scale", "0.05"]) == 0
    out = capsys.readouterr().out
    assert "per-observation Ceres (before)" in out and "vectorised Schur LM (now)" in out
