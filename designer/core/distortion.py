"""Lens distortion models on normalised computer-vision camera coordinates.

Frames and units (docs/conventions.md):

* normalised coordinates are (x/z, y/z) in the CV camera frame (x right, y down,
  z forward); they are dimensionless (pixels divided by the focal length in pixels)
  and passed as float64 arrays shaped (N, 2);
* rays are CV-frame direction vectors shaped (N, 3);
* "undistorted" is the ideal pinhole image of a ray, "distorted" is where the lens
  puts it; ``K_px`` then maps distorted normalised coordinates to pixels.

Both models use OpenCV's definitions (``cv2.projectPoints`` with
dist = (k1, k2, p1, p2, k3); ``cv2.fisheye``), which the tests use as reference.
Inverses are solved by Newton's method and verified afterwards: a point whose forward
residual exceeds ``tol`` or whose solution lies where the lens map folds over fails
(NaN plus a status, or ``NotInvertibleError``), never a silent wrong answer.
No function modifies its inputs.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields
from functools import lru_cache
from typing import TypeAlias

import numpy as np

from designer.errors import CameraModelError, NotInvertibleError

# Status of a point in an inverse (0 = solved), and the fixes that are not "reduce …".
_OK, _NONFINITE, _OUT_OF_RANGE, _NO_CONVERGENCE, _FOLDED, _BEHIND = range(6)
_FIXES = {_NONFINITE: "pass finite coordinates",
          _BEHIND: "use rays_from_distorted for rays 90° or more off axis"}
#: points per block in BrownConrady.distort: keeps the temporaries in the CPU cache
_CHUNK = 1 << 13


def _points(a: np.ndarray, ncols: int, name: str) -> np.ndarray:
    arr = np.asarray(a, dtype=np.float64)
    if arr.ndim != 2 or arr.shape[1] != ncols:
        raise ValueError(f"{name} must be shaped (N, {ncols}), got {arr.shape}")
    return arr


def _horner(s: np.ndarray, coeffs: tuple[float, ...]) -> np.ndarray:
    """c0 + c1·s + c2·s² + … for ``coeffs`` (lowest order first), skipping zero high orders."""
    n = len(coeffs)
    while n > 1 and not coeffs[n - 1]:
        n -= 1
    if n == 1:
        return np.full(np.shape(s), coeffs[0])
    out = np.multiply(s, coeffs[n - 1])
    for c in coeffs[n - 2 : 0 : -1]:
        out += c
        out *= s
    out += coeffs[0]
    return out


@lru_cache(maxsize=256)
def _first_positive_root(coeffs: tuple[float, ...]) -> float:
    """Smallest real s > 0 with 1 + c1·s + c2·s² + … = 0 (``coeffs`` lowest first), else inf.

    Solved as the largest root t = 1/s of the monic t^n + c1·t^(n-1) + … + cn, which stays
    well scaled however small the high-order coefficients are. Remembered per
    coefficients: a survey's every image inverts the same lens (a plan's ~100 calls).
    """
    roots = np.roots(np.array(coeffs, dtype=float) / coeffs[0])
    real = roots.real[(np.abs(roots.imag) <= 1e-9 * np.abs(roots)) & (roots.real > 0)]
    return 1.0 / float(real.max()) if real.size else math.inf


class _Model:
    """Behaviour shared by both models: a radial map g(t) = t·(1 + k1 t² + k2 t⁴ + …) on
    t = undistorted radius (Brown) or θ (fisheye), its safeguarded inverse, the failure
    reports and the image check. Models provide ``_radial``, ``_cap``, ``_where``, ``_solve``.
    """

    _name = ""
    _cap = math.inf  # largest meaningful t

    def __post_init__(self) -> None:
        for f in fields(self):
            value = getattr(self, f.name)
            number = isinstance(value, int | float | np.integer | np.floating)
            if isinstance(value, bool) or not number or not math.isfinite(value):
                raise CameraModelError(
                    f"{type(self).__name__}.{f.name} = {value!r} is not a finite number"
                )
            object.__setattr__(self, f.name, float(value))

    def to_dict(self) -> dict:
        """{'model': 'brown_conrady' | 'fisheye_equidistant', coefficient: value, …}."""
        return {"model": self._name, **{f.name: getattr(self, f.name) for f in fields(self)}}

    # ------------------------------------------------------------ the radial map
    def _radial(self) -> tuple[float, ...]:
        raise NotImplementedError

    def _g(self, t: np.ndarray) -> np.ndarray:
        return t * _horner(t * t, self._radial())

    def _dg(self, t: np.ndarray) -> np.ndarray:
        return _horner(t * t, tuple((2 * i + 1) * c for i, c in enumerate(self._radial())))

    def _max_monotone(self) -> float:
        return math.sqrt(_first_positive_root(
            tuple((2 * i + 1) * c for i, c in enumerate(self._radial()))))

    def _limits(self) -> tuple[float, float, float]:
        """(t limit, distorted radius g reaches there, end of the monotone region)."""
        mono = self._max_monotone()
        limit = min(mono, self._cap)
        if limit == math.inf:
            return limit, math.inf, mono
        # a vanishing coefficient puts the limit far past any image (k2 = -1e-250: t ~ 1e125)
        # where g overflows: the distorted radius there is past every float, +inf
        with np.errstate(over="ignore", invalid="ignore"):
            reach = float(self._g(np.float64(limit)))
        return limit, reach if math.isfinite(reach) else math.inf, mono

    def _invert_radial(self, target: np.ndarray, tol: float, max_iter: int) -> np.ndarray:
        """t in [0, limit] with |g(t) − target| <= tol (N,), NaN where there is none:
        Newton's method, safeguarded by bisection on a bracket where g increases: a Newton
        step that leaves the bracket or shrinks less than halfway is replaced by bisection."""
        limit, reach, mono = self._limits()
        t_out = np.full_like(target, np.nan)
        idx = np.flatnonzero((target < reach) | ((target <= reach) & (mono > limit)))
        goal = target[idx]
        with np.errstate(all="ignore"):
            hi = np.full_like(goal, limit)
            if limit == math.inf:  # g increases without bound: double until it brackets
                hi = np.maximum(goal, 1.0)
                for _ in range(64):
                    short = self._g(hi) < goal
                    if not short.any():
                        break
                    hi[short] *= 2.0
            lo, t = np.zeros_like(goal), np.minimum(goal, hi)
            last = hi.copy()  # the previous step's length
            for _ in range(max_iter):
                f = self._g(t) - goal
                done = np.abs(f) <= tol
                if done.any():
                    t_out[idx[done]] = t[done]
                    if done.all():
                        break
                    idx, goal, t, f, lo, hi, last = (
                        a[~done] for a in (idx, goal, t, f, lo, hi, last))
                hi = np.where(f > 0, t, hi)
                lo = np.where(f < 0, t, lo)
                step = f / self._dg(t)
                new = t - step
                bisect = ~((new > lo) & (new < hi) & (np.abs(step) < 0.5 * last))  # or NaN
                new[bisect] = 0.5 * (lo[bisect] + hi[bisect])
                last = np.abs(new - t)
                t = new
        return t_out

    # ------------------------------------------------------------------ inverse
    def _solve(self, xy_dist, tol: float, max_iter: int) -> tuple[np.ndarray, np.ndarray]:
        raise NotImplementedError

    def _where(self, limit: float) -> str:
        raise NotImplementedError

    def _fold_within(self, xy: np.ndarray) -> str | None:
        """A message if the map folds inside the region of undistorted points ``xy``."""
        return None

    def undistort_with_status(
        self, xy_dist: np.ndarray, tol: float = 1e-12, max_iter: int = 50
    ) -> tuple[np.ndarray, np.ndarray]:
        """Distorted → undistorted normalised coordinates (N, 2) and an ok mask (N,).

        Rows without a verified inverse (forward residual <= ``tol``, normalised units,
        inside the monotone region) are NaN with ok = False.
        """
        xy, codes = self._solve(xy_dist, tol, max_iter)
        return xy, codes == _OK

    def undistort(self, xy_dist: np.ndarray, tol: float = 1e-12, max_iter: int = 50) -> np.ndarray:
        """Distorted → undistorted normalised coordinates (N, 2), to ``tol`` (normalised).

        Raises NotInvertibleError if any point has no verified inverse.
        """
        xy, codes = self._solve(xy_dist, tol, max_iter)
        self._raise_failures(xy_dist, codes)
        return xy

    def _describe(self) -> str:
        named = ", ".join(f"{n}={getattr(self, n):g}" for n in self._nonzero())
        return f"{type(self).__name__} with {named or 'zero coefficients'}"

    def _nonzero(self) -> list[str]:
        return [f.name for f in fields(self) if getattr(self, f.name)]

    def _fix(self) -> str:
        names = ", ".join(f"|{n}|" for n in self._nonzero())
        return f"reduce {names + ' or ' if names else ''}the image size/field of view"

    def _reason(self, code: int, xd: np.ndarray) -> str:
        limit, reach, _ = self._limits()
        where = self._where(limit)
        return {
            _NONFINITE: "the coordinate is not finite",
            _OUT_OF_RANGE: f"its distorted radius {math.hypot(*xd):.6g} is beyond {reach:.6g}, "
            f"the largest the model reaches (at {where})",
            _NO_CONVERGENCE: "Newton's method did not reach the tolerance (the point may lie "
            "outside the range of the lens map)",
            _FOLDED: "the only solution found lies where the lens map folds (Jacobian not "
            f"positive definite{'' if limit == math.inf else ', or beyond ' + where})",
            _BEHIND: "its ray is 90° or more off axis and has no normalised coordinates",
        }[code]

    def _raise_failures(self, xy_dist, codes: np.ndarray) -> None:
        bad = np.flatnonzero(codes)
        if bad.size == 0:
            return
        code, xd = int(codes[bad[0]]), np.asarray(xy_dist, dtype=np.float64)[bad[0]]
        raise NotInvertibleError(
            f"{bad.size} of {len(codes)} points cannot be undistorted with {self!r}: the first, "
            f"at normalised ({xd[0]:.6g}, {xd[1]:.6g}), because {self._reason(code, xd)}; "
            f"{_FIXES.get(code) or self._fix()}"
        )

    def invertibility_problem(
        self, fx_px: float, fy_px: float, cx_px: float, cy_px: float,
        width_px: float, height_px: float,
    ) -> str | None:
        """None if every point of the image [0, W] × [0, H] (continuous pixel coordinates,
        top-left corner origin) has a unique undistorted preimage in the monotone region.

        Exact for the radial terms: the farthest image point (a corner) must lie inside
        the distorted radius the monotone part of the map reaches. Tangential terms are
        checked by inverting a 65 × 65 grid over the image, border included, and by
        requiring a positive definite Jacobian on a polar grid over the disc holding the
        preimages (which makes the map one-to-one there).
        Otherwise returns one sentence naming the coefficients, where and the fix.
        """
        if not (fx_px > 0 and fy_px > 0 and width_px > 0 and height_px > 0):
            raise CameraModelError("focal lengths and image size must be > 0 px")
        grid = np.linspace(0.0, 1.0, 65)
        unit = np.stack(np.meshgrid(grid, grid), axis=-1).reshape(-1, 2)
        corner = ((unit == 0.0) | (unit == 1.0)).all(axis=1)
        uv = unit * [width_px, height_px]
        xd = (uv - [cx_px, cy_px]) / [fx_px, fy_px]
        rd = np.hypot(xd[:, 0], xd[:, 1])
        limit, reach, mono = self._limits()
        if rd.max() >= reach:
            what = "folds the lens map" if mono <= limit else "needs rays more than 180° off axis"
            return (
                f"{self._describe()} {what} inside the image: {int((rd[corner] >= reach).sum())} "
                f"image corner(s) lie at distorted radius up to {rd.max():.4g}, beyond "
                f"{reach:.4g}, the largest the model reaches (at {self._where(limit)}); "
                f"{self._fix()}"
            )
        xy, codes = self._solve(xd, 1e-6 / max(fx_px, fy_px), 50)
        codes[codes == _BEHIND] = _OK
        if not codes.any():
            return self._fold_within(xy)
        i = int(np.flatnonzero(codes)[0])
        return (
            f"{self._describe()} makes pixel ({uv[i, 0]:.1f}, {uv[i, 1]:.1f}) not invertible "
            f"because {self._reason(int(codes[i]), xd[i])}; {self._fix()}"
        )


@dataclass(frozen=True)
class BrownConrady(_Model):
    """Brown–Conrady radial and tangential distortion, OpenCV's model and coefficients.

    On normalised CV coordinates (x, y), r² = x² + y², radial = 1 + k1 r² + k2 r⁴ + k3 r⁶:
    x_d = x·radial + 2 p1 x y + p2 (r² + 2x²),  y_d = y·radial + p1 (r² + 2y²) + 2 p2 x y.
    Identical to ``cv2.projectPoints`` with dist = (k1, k2, p1, p2, k3).
    """

    k1: float = 0.0
    k2: float = 0.0
    k3: float = 0.0
    p1: float = 0.0
    p2: float = 0.0

    _name = "brown_conrady"

    @property
    def is_identity(self) -> bool:
        """True if every coefficient is zero: distort and undistort return their input."""
        return not (self.k1 or self.k2 or self.k3 or self.p1 or self.p2)

    def _radial(self) -> tuple[float, ...]:
        return (1.0, self.k1, self.k2, self.k3)

    def _where(self, limit: float) -> str:
        return f"undistorted r = {limit:.6g}, {math.degrees(math.atan(limit)):.1f}° off axis"

    def max_monotone_radius(self) -> float:
        """Largest undistorted normalised radius up to which r·radial(r) strictly increases.

        math.inf if the radial map increases everywhere (tangential terms ignored).
        """
        return self._max_monotone()

    def _fold_within(self, xy: np.ndarray) -> str | None:
        # Radially, J is positive definite inside max_monotone_radius; tangential terms
        # can fold it sooner. J is symmetric, and a map whose symmetric Jacobian is
        # positive definite on a convex set is one-to-one there.
        if not (self.p1 or self.p2):
            return None
        r = np.linspace(0.0, np.hypot(xy[:, 0], xy[:, 1]).max(), 129)
        a = np.linspace(0.0, 2 * np.pi, 256, endpoint=False)
        x, y = np.outer(r, np.cos(a)).ravel(), np.outer(r, np.sin(a)).ravel()
        j00, j01, j11 = self._jacobian_terms(x, y)
        bad = np.flatnonzero(~((j00 * j11 - j01 * j01 > 0) & (j00 + j11 > 0)))
        if bad.size == 0:
            return None
        i = bad[np.argmin(np.hypot(x[bad], y[bad]))]
        return (
            f"{self._describe()} folds the lens map within the field of view: the Jacobian is not "
            f"positive definite at undistorted ({x[i]:.4g}, {y[i]:.4g}); {self._fix()}"
        )

    def distort(self, xy: np.ndarray) -> np.ndarray:
        """Undistorted → distorted normalised coordinates, (N, 2) → (N, 2)."""
        xy = _points(xy, 2, "xy")
        out = np.empty_like(xy)
        for start in range(0, len(xy), _CHUNK):
            self._distort_block(xy[start : start + _CHUNK], out[start : start + _CHUNK])
        return out

    def _distort_block(self, xy: np.ndarray, out: np.ndarray) -> None:
        k1, k2, k3, p1, p2 = self.k1, self.k2, self.k3, self.p1, self.p2
        x, y = xy[:, 0], xy[:, 1]
        x2 = x * x
        y2 = y * y
        r2 = x2 + y2
        radial = _horner(r2, (1.0, k1, k2, k3))
        np.multiply(xy, radial[:, None], out=out)
        if p1 or p2:
            # x_d += p2 (r² + 2x²) + 2 p1 xy;  y_d += p1 (r² + 2y²) + 2 p2 xy
            xy2 = x * y
            xy2 *= 2.0
            for c, sq, col, other in ((p2, x2, 0, p1), (p1, y2, 1, p2)):
                sq *= 2.0
                sq += r2
                sq *= c
                sq += other * xy2
                out[:, col] += sq

    def distort_xy(self, x: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Component form of :meth:`distort` for contiguous 1-D arrays x, y (N,).

        Returns new arrays (x_d, y_d); the projection hot path uses it on cache-sized
        chunks, where separate contiguous components are about twice as fast as (N, 2).
        """
        r2 = x * x
        r2 += y * y
        radial = _horner(r2, (1.0, self.k1, self.k2, self.k3))
        xd = x * radial
        yd = y * radial
        if self.p1 or self.p2:
            xy2 = x * y
            xy2 *= 2.0
            t = x * x
            t *= 2.0
            t += r2
            t *= self.p2
            t += self.p1 * xy2
            xd += t
            t = y * y
            t *= 2.0
            t += r2
            t *= self.p1
            t += self.p2 * xy2
            yd += t
        return xd, yd

    def _jacobian_terms(self, x: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, ...]:
        """(J00, J01 = J10, J11) of the map at undistorted points x, y (N,)."""
        r2 = x * x + y * y
        radial = _horner(r2, self._radial())
        # d radial / dx = x · 2 (k1 + 2 k2 r² + 3 k3 r⁴)
        d_radial = _horner(r2, (2.0 * self.k1, 4.0 * self.k2, 6.0 * self.k3))
        j01 = x * y * d_radial
        j01 += 2.0 * (self.p1 * x + self.p2 * y)
        j00 = x * x * d_radial
        j00 += radial + 2.0 * self.p1 * y + 6.0 * self.p2 * x
        d_radial *= y * y
        j11 = d_radial + radial + 6.0 * self.p1 * y + 2.0 * self.p2 * x
        return j00, j01, j11

    def jacobian(self, xy: np.ndarray) -> np.ndarray:
        """d(distorted)/d(undistorted) at undistorted normalised points: (N, 2) → (N, 2, 2)."""
        xy = _points(xy, 2, "xy")
        j00, j01, j11 = self._jacobian_terms(xy[:, 0], xy[:, 1])
        return np.stack([j00, j01, j01, j11], axis=1).reshape(-1, 2, 2)

    def distort_rays(self, rays_cv: np.ndarray) -> np.ndarray:
        """CV-frame directions (N, 3) → distorted normalised coordinates (N, 2).

        Rows with z <= 0 (not in front of the camera) are NaN.
        """
        rays = _points(rays_cv, 3, "rays_cv")
        z = rays[:, 2:]
        xy = np.full((len(rays), 2), np.nan)
        np.divide(rays[:, :2], z, out=xy, where=z > 0)
        return self.distort(xy)

    def rays_from_distorted(self, xy_dist: np.ndarray, tol: float = 1e-12) -> np.ndarray:
        """Distorted normalised coordinates (N, 2) → unit CV-frame rays (N, 3), z > 0.

        Raises NotInvertibleError where the inverse fails (see ``undistort``).
        """
        xy = self.undistort(xy_dist, tol=tol)
        rays = np.column_stack([xy, np.ones(len(xy))])
        return rays / np.linalg.norm(rays, axis=1, keepdims=True)

    def _solve(self, xy_dist, tol, max_iter):
        """Start at the radial-only inverse, then 2-D Newton with backtracking, kept inside
        the monotone disc; finally verify every point."""
        xd = _points(xy_dist, 2, "xy_dist")
        r_max = self.max_monotone_radius()
        finite = np.isfinite(xd).all(axis=1)
        tol2 = tol * tol
        with np.errstate(all="ignore"):
            rd = np.hypot(xd[:, 0], xd[:, 1])
            scale = self._invert_radial(rd, tol, max_iter) / rd
            scale[rd == 0] = 1.0
            beyond = np.isnan(scale)  # outside the radial range: start inside the disc
            scale[beyond] = np.minimum(1.0, 0.9 * r_max / rd[beyond])
            xy = xd * scale[:, None]
            idx = np.flatnonzero(finite)
            target = xd[idx]
            res = self.distort(xy[idx]) - target
            err2 = np.einsum("ij,ij->i", res, res)
            for _ in range(max_iter):
                keep = np.flatnonzero(~(err2 <= tol2))
                if keep.size == 0:
                    break
                if keep.size < idx.size:
                    idx, target, res, err2 = idx[keep], target[keep], res[keep], err2[keep]
                cur = xy[idx]
                j00, j01, j11 = self._jacobian_terms(cur[:, 0], cur[:, 1])
                step = np.column_stack([j11 * res[:, 0] - j01 * res[:, 1],
                                        j00 * res[:, 1] - j01 * res[:, 0]])
                step /= (j00 * j11 - j01 * j01)[:, None]
                singular = np.flatnonzero(~np.isfinite(step).all(axis=1))
                step[singular] = res[singular]  # fall back to a fixed-point step
                new, new_res, new_err2 = np.empty_like(cur), np.empty_like(res), err2.copy()
                worse = slice(None)
                for _ in range(30):  # backtracking: accept steps that reduce the residual
                    new[worse] = self._clamp(cur[worse] - step[worse], r_max)
                    new_res[worse] = self.distort(new[worse]) - target[worse]
                    new_err2[worse] = np.einsum("ij,ij->i", new_res[worse], new_res[worse])
                    worse = np.flatnonzero(~(new_err2 < err2))
                    if worse.size == 0:
                        break
                    step[worse] *= 0.5
                new[worse] = cur[worse]  # stalled: no step helps, left to fail verification
                xy[idx] = new
                res, err2 = new_res, new_err2
                if worse.size:
                    moving = np.ones(idx.size, dtype=bool)
                    moving[worse] = False
                    idx, target, res, err2 = idx[moving], target[moving], res[moving], err2[moving]
            # Verify every point: residual, local invertibility, monotone region.
            resid = self.distort(xy) - xd
            resid2 = np.einsum("ij,ij->i", resid, resid)
            j00, j01, j11 = self._jacobian_terms(xy[:, 0], xy[:, 1])
            r2 = np.einsum("ij,ij->i", xy, xy)
            posdef = (j00 * j11 - j01 * j01 > 0) & (j00 + j11 > 0)  # J is symmetric
            good = finite & (resid2 <= tol2) & posdef & (r2 < r_max**2)
            beyond = rd >= self._limits()[1]
        codes = np.full(len(xd), _OK, dtype=np.int8)
        codes[~good] = np.where(resid2[~good] <= tol2, _FOLDED, _NO_CONVERGENCE)
        codes[~good & beyond] = _OUT_OF_RANGE
        codes[~finite] = _NONFINITE
        xy[~good] = np.nan
        return xy, codes

    @staticmethod
    def _clamp(xy: np.ndarray, r_max: float) -> np.ndarray:
        """Pull iterates back inside the monotone disc, where the solution must lie."""
        if math.isinf(r_max):
            return xy
        r = np.hypot(xy[:, 0], xy[:, 1])
        limit = r_max * (1.0 - 1e-12)
        outside = r > limit
        xy[outside] *= (limit / r[outside])[:, None]
        return xy


@dataclass(frozen=True)
class FisheyeEquidistant(_Model):
    """OpenCV's fisheye (equidistant) model, ``cv2.fisheye``.

    A ray at angle θ (radians) from the optical axis lands at distorted normalised radius
    θ_d = θ (1 + k1 θ² + k2 θ⁴ + k3 θ⁶ + k4 θ⁸), in the ray's azimuth.
    """

    k1: float = 0.0
    k2: float = 0.0
    k3: float = 0.0
    k4: float = 0.0

    _name = "fisheye_equidistant"
    _cap = math.pi

    @property
    def is_identity(self) -> bool:
        """Always False: even with zero coefficients the equidistant map is not a pinhole."""
        return False

    def _radial(self) -> tuple[float, ...]:
        return (1.0, self.k1, self.k2, self.k3, self.k4)

    def _where(self, limit: float) -> str:
        return f"θ = {math.degrees(limit):.2f}°"

    def max_monotone_theta(self) -> float:
        """Largest θ (radians) up to which θ_d(θ) strictly increases; math.inf if always."""
        return self._max_monotone()

    def _scale_radius(self, xy: np.ndarray, r: np.ndarray, theta: np.ndarray) -> np.ndarray:
        scale = np.divide(self._g(theta), r, out=np.ones_like(r), where=r > 0)
        return xy * scale[:, None]

    def distort(self, xy: np.ndarray) -> np.ndarray:
        """Undistorted normalised coordinates of rays with z > 0 (N, 2) → distorted (N, 2)."""
        xy = _points(xy, 2, "xy")
        r = np.hypot(xy[:, 0], xy[:, 1])
        return self._scale_radius(xy, r, np.arctan(r))

    def distort_rays(self, rays_cv: np.ndarray) -> np.ndarray:
        """CV-frame directions (N, 3), any θ = atan2(hypot(x, y), z) → distorted (N, 2).

        The zero vector and rays exactly backwards (θ = 180°, azimuth undefined) are NaN.
        """
        rays = _points(rays_cv, 3, "rays_cv")
        r = np.hypot(rays[:, 0], rays[:, 1])
        out = self._scale_radius(rays[:, :2], r, np.arctan2(r, rays[:, 2]))
        out[(r == 0) & ~(rays[:, 2] > 0)] = np.nan
        return out

    def jacobian(self, xy: np.ndarray) -> np.ndarray:
        """d(distorted)/d(undistorted) at normalised points (z > 0): (N, 2) → (N, 2, 2)."""
        xy = _points(xy, 2, "xy")
        x, y = xy[:, 0], xy[:, 1]
        r2 = x * x + y * y
        r = np.sqrt(r2)
        theta = np.arctan(r)
        positive = r > 0
        s = np.divide(self._g(theta), r, out=np.ones_like(r), where=positive)  # θ_d / r
        # c = (ds/dr) / r; its cancellation near r = 0 costs only ~eps once multiplied by x².
        c = np.divide(self._dg(theta) / (1.0 + r2) - s, r2, out=np.zeros_like(r), where=positive)
        jac = np.empty((len(xy), 2, 2))
        jac[:, 0, 0] = s + c * x * x
        jac[:, 0, 1] = jac[:, 1, 0] = c * x * y
        jac[:, 1, 1] = s + c * y * y
        return jac

    def _solve_theta(self, xy_dist, tol, max_iter):
        """θ (N,), θ_d (N,) and status codes for distorted normalised points."""
        xd = _points(xy_dist, 2, "xy_dist")
        td = np.hypot(xd[:, 0], xd[:, 1])
        theta = self._invert_radial(td, tol, max_iter)
        _, reach, mono = self._limits()
        with np.errstate(invalid="ignore"):
            good = (np.abs(self._g(theta) - td) <= tol) & (self._dg(theta) > 0)
            good &= (theta < mono) & (theta <= math.pi)
            in_range = (td < reach) | ((td <= reach) & (mono > math.pi))
        codes = np.full(len(td), _OK, dtype=np.int8)
        codes[~good] = np.where(np.isfinite(theta[~good]), _FOLDED, _NO_CONVERGENCE)
        codes[~in_range] = _OUT_OF_RANGE
        codes[~np.isfinite(td)] = _NONFINITE
        theta[~good] = np.nan
        return theta, td, codes

    def _solve(self, xy_dist, tol, max_iter):
        theta, td, codes = self._solve_theta(xy_dist, tol, max_iter)
        codes[(codes == _OK) & (theta >= 0.5 * math.pi)] = _BEHIND
        with np.errstate(invalid="ignore"):
            scale = np.divide(np.tan(theta), td, out=np.ones_like(td), where=td > 0)
        xy = np.asarray(xy_dist, dtype=np.float64) * scale[:, None]
        xy[codes != _OK] = np.nan
        return xy, codes

    def rays_from_distorted(self, xy_dist: np.ndarray, tol: float = 1e-12) -> np.ndarray:
        """Distorted normalised coordinates (N, 2) → unit CV-frame rays (N, 3).

        θ may exceed 90° (z < 0) for lenses wider than 180°. Raises NotInvertibleError
        where θ_d has no verified preimage with θ in [0, min(max_monotone_theta, π)].
        """
        theta, td, codes = self._solve_theta(xy_dist, tol, 50)
        self._raise_failures(xy_dist, codes)
        scale = np.divide(np.sin(theta), td, out=np.zeros_like(td), where=td > 0)
        xy = np.asarray(xy_dist, dtype=np.float64) * scale[:, None]
        return np.column_stack([xy, np.cos(theta)])


#: a lens distortion model
Distortion: TypeAlias = BrownConrady | FisheyeEquidistant
