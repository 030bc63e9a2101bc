"""Levenberg–Marquardt for bundle adjustment: points eliminated by the Schur complement.

The unknowns are split as bundle adjustment splits them: many 3D points (3 each) and a
few hundred "camera-side" parameters (poses, velocities, interior orientation). Each
observation's residual (m values) depends on one point and on its image's camera-side
parameters, given in the image's local column layout (``image_cols``: image × local
column → global camera-side column, −1 for a parameter held constant). The normal
equations

    [U  W] [δc]     [g_c]
    [Wᵀ V] [δp] = − [g_p]

have a block-diagonal V (3 × 3 per point), so the points are eliminated:
(U − W V⁻¹ Wᵀ) δc = −g_c + W V⁻¹ g_p, a dense system the size of the camera side, solved
by Cholesky; then δp = V⁻¹ (−g_p − Wᵀ δc). With V⁻¹ = Kᵀ K (K the inverse of V's Cholesky
factor, closed form per point), W V⁻¹ Wᵀ = G Gᵀ for G = W Kᵀ: per chunk of points that
few images share, G is laid out dense (those images' columns × the points' 3) and
multiplied by itself with one BLAS syrk — no Python loop over observations or points.

The iteration is Ceres's Levenberg–Marquardt (its defaults): damping diag(JᵀJ) clamped to
[1e-6, 1e32] divided by a trust radius that starts at 1e4, grows by
1 / max(1/3, 1 − (2ρ − 1)³) after a step whose gain ratio ρ exceeds 1e-3 and shrinks by
a doubling factor after a rejected one; it stops (CONVERGENCE) when a step changes the
cost by at most ``function_tolerance`` relative, or the step is at most
``parameter_tolerance`` relative to the parameters, or the gradient's largest component
is at most ``gradient_tolerance``; NO_CONVERGENCE after ``max_iterations`` steps.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol

import numpy as np

MIN_DIAGONAL = 1e-6
MAX_DIAGONAL = 1e32
INITIAL_RADIUS = 1e4
MAX_RADIUS = 1e16
MIN_RADIUS = 1e-32
MIN_RELATIVE_DECREASE = 1e-3
#: points per chunk of the Schur complement's dense products
CHUNK_POINTS = 500


@dataclass
class Linearization:
    """A problem linearised at its current parameters (residuals whitened)."""

    cost: float
    #: observation residuals (n, m), their camera-side Jacobians in the image-local
    #: columns (n, m, c) and point Jacobians (n, m, 3)
    r: np.ndarray
    J_c: np.ndarray
    J_p: np.ndarray
    #: JᵀJ and Jᵀr of the terms on points alone (priors): (P, 3, 3), (P, 3)
    point_H: np.ndarray
    point_g: np.ndarray
    #: JᵀJ and Jᵀr of the terms on the camera side alone, global columns
    cam_H: np.ndarray
    cam_g: np.ndarray


class SchurProblem(Protocol):
    """What :func:`solve` asks of a problem; a state is the problem's own object."""

    def linearize(self, state) -> Linearization: ...
    def moved(self, state, delta_c: np.ndarray, delta_p: np.ndarray): ...
    def parameter_norm(self, state) -> float: ...


@dataclass
class LMSummary:
    """The figures of a solve, under the names of a Ceres summary's fields."""

    initial_cost: float
    final_cost: float
    num_successful_steps: int
    num_unsuccessful_steps: int
    termination_type: str
    num_residuals_reduced: int
    num_effective_parameters_reduced: int


class SchurLayout:
    """The fixed structure of the observations: ``obs_image`` and ``obs_point`` (n,),
    sorted by image then point; ``image_cols`` (images, c) global camera-side column of
    each image-local column or −1; ``n_cam`` camera-side columns, ``n_points`` points
    (each observed at least once)."""

    def __init__(self, obs_image: np.ndarray, obs_point: np.ndarray, image_cols: np.ndarray,
                 n_cam: int, n_points: int, chunk_points: int = CHUNK_POINTS):
        self.obs_image = np.asarray(obs_image, np.int64)
        self.obs_point = np.asarray(obs_point, np.int64)
        key = self.obs_image * n_points + self.obs_point
        if np.any(np.diff(key) < 0):
            raise ValueError("observations must be sorted by image, then point")
        self.image_cols = np.asarray(image_cols, np.int64)
        self.n_images, self.c = self.image_cols.shape
        self.n_cam, self.n_points = n_cam, n_points
        self.image_start = np.searchsorted(self.obs_image, np.arange(self.n_images + 1))
        self.by_point = np.argsort(self.obs_point, kind="stable")
        counts = np.bincount(self.obs_point, minlength=n_points)
        if np.any(counts == 0):
            raise ValueError("every point needs an observation")
        self.point_start = np.concatenate([[0], np.cumsum(counts)[:-1]])
        # a point observed twice in one image is one block of W: its observations summed
        blocks, first = np.unique(key, return_index=True)
        self.unique_blocks = len(blocks) == len(key)
        self.block_first = first
        repeat = np.ones(len(key), bool)
        repeat[first] = False
        self.repeat_rows = np.flatnonzero(repeat)  # observations after their block's first
        self.repeat_block = np.searchsorted(blocks, key[self.repeat_rows])
        self._chunks(blocks // n_points, blocks % n_points, chunk_points)
        # scatter of image-local (c × c) blocks and c-vectors into the global system
        valid = self.image_cols >= 0
        self.local_valid = np.flatnonzero(valid.ravel())
        g = self.image_cols.ravel()[self.local_valid]
        self.local_global = g
        self.pair_index = (g[:, None] * n_cam + g[None, :]).ravel()
        cols = self.image_cols
        both = (cols[:, :, None] >= 0) & (cols[:, None, :] >= 0)
        self.diag_mask = both
        self.diag_index = (cols[:, :, None] * n_cam + cols[:, None, :])[both]

    def _chunks(self, block_image: np.ndarray, block_point: np.ndarray, size: int) -> None:
        """Points in chunks of ``size`` that few images share (ordered by their first and
        last image): for each, the blocks, where each block's c × 3 values go in the
        chunk's dense (images · c) × (3 · points) matrix, and its rows' image-local
        columns."""
        c, n_points = self.c, self.n_points
        first = np.full(n_points, self.n_images)
        np.minimum.at(first, block_point, block_image)
        last = np.zeros(n_points, np.int64)
        np.maximum.at(last, block_point, block_image)
        rank = np.empty(n_points, np.int64)
        rank[np.lexsort((last, first))] = np.arange(n_points)
        chunk = rank[block_point] // size
        by_chunk = np.argsort(chunk, kind="stable")
        bounds = np.searchsorted(chunk[by_chunk], np.arange(chunk.max(initial=-1) + 2))
        self.chunks = []
        for k in range(len(bounds) - 1):
            blocks = by_chunk[bounds[k]:bounds[k + 1]]
            images, loc_i = np.unique(block_image[blocks], return_inverse=True)
            points, loc_p = np.unique(block_point[blocks], return_inverse=True)
            width = 3 * len(points)
            flat = ((loc_i[:, None, None] * c + np.arange(c)[None, :, None]) * width
                    + 3 * loc_p[:, None, None] + np.arange(3)[None, None, :])
            # the chunk's images in runs of consecutive ones: (first row in the chunk,
            # first row in the whole matrix, rows), so the product is added by slices
            breaks = np.flatnonzero(np.diff(images) != 1) + 1
            starts = np.concatenate([[0], breaks])
            ends = np.concatenate([breaks, [len(images)]])
            runs = [(int(a) * c, int(images[a]) * c, int(b - a) * c)
                    for a, b in zip(starts, ends, strict=True)]
            self.chunks.append((blocks, flat.ravel(), len(images) * c, width, runs))

    def point_sum(self, per_obs: np.ndarray) -> np.ndarray:
        """Sum of per-observation rows by point: (P, ...)."""
        return np.add.reduceat(per_obs[self.by_point], self.point_start, axis=0)

    def image_sum(self, per_obs: np.ndarray) -> np.ndarray:
        """Sum of per-observation rows by image: (images, ...) (zero for an image
        without observations)."""
        out = np.zeros((self.n_images,) + per_obs.shape[1:])
        has = self.image_start[1:] > self.image_start[:-1]
        if per_obs.shape[0]:
            out[has] = np.add.reduceat(per_obs, self.image_start[:-1][has], axis=0)
        return out

    def scatter_vector(self, local: np.ndarray) -> np.ndarray:
        """Image-local vectors (images, c) summed into the global columns."""
        return np.bincount(self.local_global, weights=local.ravel()[self.local_valid],
                           minlength=self.n_cam)

    def gram(self, G: np.ndarray) -> np.ndarray:
        """Σ over points of G_p G_pᵀ for per-observation (n, c, 3) blocks G (G_p: the
        blocks of point p's observations, stacked by image), as the global (n_cam, n_cam)
        matrix: per chunk of points one dense symmetric rank-k product (BLAS syrk)."""
        from scipy.linalg.blas import dsyrk

        if not self.unique_blocks:  # a block's later observations added to its first
            G_all = G
            G = G_all[self.block_first]
            np.add.at(G, self.repeat_block, G_all[self.repeat_rows])
        n = self.n_images * self.c
        local = np.zeros((n, n))
        for blocks, flat, rows, width, runs in self.chunks:
            dense = np.zeros(rows * width)
            dense[flat] = G[blocks].ravel()
            product = dsyrk(1.0, dense.reshape(rows, width))  # its upper triangle
            for k, (a, ga, na) in enumerate(runs):
                for b, gb, nb in runs[k:]:
                    local[ga:ga + na, gb:gb + nb] += product[a:a + na, b:b + nb]
        local = np.triu(local)  # upper triangles added: images are in order
        local += np.triu(local, 1).T
        sub = local[np.ix_(self.local_valid, self.local_valid)]
        return np.bincount(self.pair_index, weights=sub.ravel(),
                           minlength=self.n_cam * self.n_cam).reshape(self.n_cam, self.n_cam)


def _outer_sum(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Σ_m a[:, m, :, None] · b[:, m, None, :] for (n, m, i) and (n, m, j): (n, i, j), aᵀ b
    per row (numpy's stacked matmul: 6 times as fast as einsum at these sizes)."""
    return np.matmul(a.transpose(0, 2, 1), b)


def _inverse_cholesky_3x3(V: np.ndarray) -> np.ndarray | None:
    """K = L⁻¹ for the Cholesky factors L Lᵀ = V of (P, 3, 3) symmetric positive definite
    matrices (so V⁻¹ = Kᵀ K); None when one is not positive definite."""
    a, b, c = V[:, 0, 0], V[:, 1, 0], V[:, 2, 0]
    e, f, i = V[:, 1, 1], V[:, 2, 1], V[:, 2, 2]
    with np.errstate(invalid="ignore", divide="ignore"):
        l11 = np.sqrt(a)
        l21, l31 = b / l11, c / l11
        l22 = np.sqrt(e - l21 * l21)
        l32 = (f - l21 * l31) / l22
        l33 = np.sqrt(i - l31 * l31 - l32 * l32)
    if not (np.all(np.isfinite(l33)) and np.all(l11 > 0) and np.all(l22 > 0)
            and np.all(l33 > 0)):
        return None
    K = np.zeros_like(V)
    K[:, 0, 0], K[:, 1, 1], K[:, 2, 2] = 1.0 / l11, 1.0 / l22, 1.0 / l33
    K[:, 1, 0] = -l21 / (l11 * l22)
    K[:, 2, 1] = -l32 / (l22 * l33)
    K[:, 2, 0] = (l21 * l32 - l22 * l31) / (l11 * l22 * l33)
    return K


def _step(layout: SchurLayout, lin: Linearization, radius: float):
    """The damped Gauss–Newton step (δc, δp), its model's cost reduction and the
    gradient's largest component; None when the reduced system is not positive definite."""
    from scipy.linalg import LinAlgError, cho_factor, cho_solve

    L = layout
    n_img, c = L.n_images, L.c
    U_loc = np.zeros((n_img, c, c))
    g_loc = np.zeros((n_img, c))
    for i in range(n_img):
        a, b = L.image_start[i], L.image_start[i + 1]
        if b > a:
            J = lin.J_c[a:b].reshape(-1, c)
            U_loc[i] = J.T @ J
            g_loc[i] = J.T @ lin.r[a:b].ravel()
    U = np.bincount(L.diag_index, weights=U_loc[L.diag_mask],
                    minlength=L.n_cam * L.n_cam).reshape(L.n_cam, L.n_cam) + lin.cam_H
    g_c = L.scatter_vector(g_loc) + lin.cam_g
    V = L.point_sum(_outer_sum(lin.J_p, lin.J_p)) + lin.point_H
    g_p = L.point_sum(_outer_sum(lin.J_p, lin.r[:, :, None])[:, :, 0]) + lin.point_g

    d_c = np.clip(np.diag(U), MIN_DIAGONAL, MAX_DIAGONAL) / radius
    d_p = np.clip(np.diagonal(V, axis1=1, axis2=2), MIN_DIAGONAL, MAX_DIAGONAL) / radius
    U_d = U + np.diag(d_c)
    V_d = V.copy()
    V_d[:, [0, 1, 2], [0, 1, 2]] += d_p
    # V⁻¹ = Kᵀ K with K = chol(V)⁻¹: W V⁻¹ Wᵀ = G Gᵀ for G = W Kᵀ = J_cᵀ (J_p Kᵀ)
    K = _inverse_cholesky_3x3(V_d)
    if K is None:
        return None
    K_obs = K[L.obs_point]
    JK = np.matmul(lin.J_p, K_obs.transpose(0, 2, 1))                    # (n, 2, 3)
    G = _outer_sum(lin.J_c, JK)                                           # (n, c, 3)
    S = U_d - L.gram(G)
    h = np.matmul(K, g_p[:, :, None])[:, :, 0]  # K g_p
    Gh = np.matmul(G, h[L.obs_point][:, :, None])[:, :, 0]
    rhs = -g_c + L.scatter_vector(L.image_sum(Gh))
    try:
        delta_c = cho_solve(cho_factor(S), rhs) if L.n_cam else np.zeros(0)
    except LinAlgError:
        return None
    if not np.all(np.isfinite(delta_c)):
        return None
    local = np.where(L.image_cols >= 0, delta_c[np.maximum(L.image_cols, 0)], 0.0) \
        if L.n_cam else np.zeros((n_img, c))
    # δp = V⁻¹ (−g_p − Wᵀ δc) = Kᵀ (−K g_p − Gᵀ δc)
    coupled = L.point_sum(np.matmul(local[L.obs_image][:, None, :], G)[:, 0, :])
    rest = -h - coupled
    delta_p = np.matmul(rest[:, None, :], K)[:, 0, :]  # Kᵀ rest
    g_dot = float(g_c @ delta_c + np.sum(g_p * delta_p))
    damped = float(d_c @ delta_c ** 2 + np.sum(d_p * delta_p ** 2))
    gradient_max = max(float(np.max(np.abs(g_c), initial=0.0)),
                       float(np.max(np.abs(g_p), initial=0.0)))
    return delta_c, delta_p, 0.5 * (damped - g_dot), gradient_max


def solve(problem: SchurProblem, layout: SchurLayout, state, max_iterations: int = 100,
          function_tolerance: float = 1e-9, gradient_tolerance: float = 1e-10,
          parameter_tolerance: float = 1e-8, n_residuals: int = 0):
    """Minimise the problem's cost from ``state``: (the final state, :class:`LMSummary`).
    ``n_residuals``: the residual count the summary reports. OpenBLAS runs on one thread
    meanwhile (designer.sfm.blas_threads: its dense systems are small)."""
    import scipy.linalg  # noqa: F401  (loads scipy's OpenBLAS before its threads are set)

    from designer.sfm.blas_threads import one_blas_thread

    with one_blas_thread():
        return _solve(problem, layout, state, max_iterations, function_tolerance,
                      gradient_tolerance, parameter_tolerance, n_residuals)


def _solve(problem, layout, state, max_iterations, function_tolerance, gradient_tolerance,
           parameter_tolerance, n_residuals):
    radius, decrease = INITIAL_RADIUS, 2.0
    lin = problem.linearize(state)
    initial = cost = lin.cost
    good = bad = 0
    termination = "NO_CONVERGENCE"
    while good + bad < max_iterations:
        step = _step(layout, lin, radius)
        if step is None:
            bad += 1
            radius /= decrease
            decrease *= 2.0
            if radius < MIN_RADIUS:
                termination = "FAILURE"
                break
            continue
        delta_c, delta_p, model_reduction, gradient_max = step
        if gradient_max <= gradient_tolerance:
            termination = "CONVERGENCE"
            break
        step_norm = float(np.sqrt(delta_c @ delta_c + np.sum(delta_p * delta_p)))
        if step_norm <= (problem.parameter_norm(state) + parameter_tolerance) \
                * parameter_tolerance:
            termination = "CONVERGENCE"
            break
        candidate = problem.moved(state, delta_c, delta_p)
        # linearised at once: a step is rejected seldom, and then only its Jacobian is lost
        candidate_lin = problem.linearize(candidate)
        new_cost = candidate_lin.cost
        if abs(cost - new_cost) <= function_tolerance * cost:
            termination = "CONVERGENCE"
            if new_cost < cost:
                state, cost = candidate, new_cost
                good += 1
            break
        rho = (cost - new_cost) / model_reduction if model_reduction > 0 else -1.0
        if np.isfinite(new_cost) and rho > MIN_RELATIVE_DECREASE:
            good += 1
            state, cost = candidate, new_cost
            radius = min(MAX_RADIUS, radius / max(1.0 / 3.0, 1.0 - (2.0 * rho - 1.0) ** 3))
            decrease = 2.0
            lin = candidate_lin
        else:
            bad += 1
            radius /= decrease
            decrease *= 2.0
            if radius < MIN_RADIUS:
                termination = "CONVERGENCE"
                break
    return state, LMSummary(initial, cost, good, bad, termination, n_residuals,
                            layout.n_cam + 3 * layout.n_points)
