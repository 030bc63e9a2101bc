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
from typing import TypeAlias

import numpy as np

from designer.errors import CameraModelError, NotInvertibleError

# Status of a point in an inverse (0 = solved).
_OK, _NONFINITE, _OUT_OF_RANGE, _NO_CONVERGENCE, _FOLDED, _BEHIND = range(6)
_FIX = "reduce |k1| or the image size/field of view"
#: points per block in BrownConrady.distort: keeps the temporaries in the CPU cache
_CHUNK = 1 << 13


def _points(a: np.ndarray, ncols: int, name: str) -> np.ndarray:
    arr = np.asarray(a, dtype=np.float64)
    if arr.ndim != 2 or arr.shape[1] != ncols:
        raise ValueError(f"{name} must be shaped (N, {ncols}), got {arr.shape}")
    return arr


def _horner(s: np.ndarray | float, coeffs: tuple[float, ...]) -> np.ndarray:
    """c0 + c1·s + c2·s² + … for ``coeffs`` (lowest order first)."""
    out = np.full(np.shape(s), coeffs[-1])
    for c in coeffs[-2::-1]:
        out *= s
        out += c
    return out


def _first_positive_root(coeffs: tuple[float, ...]) -> float:
    """Smallest real s > 0 with c0 + c1·s + … = 0 (coefficients lowest first), else inf."""
    c = np.trim_zeros(np.array(coeffs[::-1], dtype=float), "f")
    if c.size < 2:
        return math.inf
    roots = np.roots(c)
    real = roots.real[(np.abs(roots.imag) <= 1e-9 * np.abs(roots)) & (roots.real > 0)]
    return float(real.min()) if real.size else math.inf


class _Model:
    """Behaviour shared by the distortion models (the dataclasses below)."""

    _name = ""

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

    def _describe(self) -> str:
        named = [f"{f.name}={getattr(self, f.name):g}" for f in fields(self) if getattr(self, f.name)]
        return f"{type(self).__name__} with {', '.join(named) or 'zero coefficients'}"

    # Provided by the models: the inverse and the limit of the monotone region.
    def _solve(self, xy_dist, tol: float, max_iter: int) -> tuple[np.ndarray, np.ndarray]:
        raise NotImplementedError

    def _limits(self) -> tuple[float, str, bool]:
        """(largest distorted radius reached, where that is, whether the map folds there)."""
        raise NotImplementedError

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

    def _reason(self, code: int, xd: np.ndarray) -> str:
        reach, where, _ = self._limits()
        return {
            _NONFINITE: "the coordinate is not finite",
            _OUT_OF_RANGE: f"its distorted radius {math.hypot(*xd):.6g} is beyond {reach:.6g}, "
            f"the largest the model reaches (at {where})",
            _NO_CONVERGENCE: "Newton's method did not reach the tolerance",
            _FOLDED: f"the only solution found lies where the lens map folds (beyond {where})",
            _BEHIND: "its ray is 90° or more off axis and has no normalised coordinates",
        }[code]

    def _raise_failures(self, xy_dist, codes: np.ndarray) -> None:
        bad = np.flatnonzero(codes)
        if bad.size == 0:
            return
        code, xd = int(codes[bad[0]]), np.asarray(xy_dist, dtype=np.float64)[bad[0]]
        fix = {_NONFINITE: "pass finite coordinates",
               _BEHIND: "use rays_from_distorted for rays 90° or more off axis"}.get(code, _FIX)
        raise NotInvertibleError(
            f"{bad.size} of {len(codes)} points cannot be undistorted with {self!r}: the first, "
            f"at normalised ({xd[0]:.6g}, {xd[1]:.6g}), because {self._reason(code, xd)}; {fix}"
        )

    def invertibility_problem(
        self, fx_px: float, fy_px: float, cx_px: float, cy_px: float,
        width_px: float, height_px: float,
    ) -> str | None:
        """None if every point of the image [0, W] × [0, H] (continuous pixel coordinates,
        top-left corner origin) has a unique undistorted preimage in the monotone region.

        Exact for the radial terms: the farthest image point (a corner) must lie inside
        the distorted radius the monotone part of the map reaches. Tangential terms are
        checked by inverting the image border (128 points per edge) and a 33 × 33 grid.
        Otherwise returns one sentence naming the coefficients, where and the fix.
        """
        if not (fx_px > 0 and fy_px > 0 and width_px > 0 and height_px > 0):
            raise CameraModelError("focal lengths and image size must be > 0 px")
        edge, grid = np.linspace(0.0, 1.0, 129), np.linspace(0.0, 1.0, 33)
        zero, one = np.zeros_like(edge), np.ones_like(edge)
        unit = np.concatenate([
            [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0]],
            np.column_stack([edge, zero]), np.column_stack([edge, one]),
            np.column_stack([zero, edge]), np.column_stack([one, edge]),
            np.stack(np.meshgrid(grid, grid), axis=-1).reshape(-1, 2),
        ])
        uv = unit * [width_px, height_px]
        xd = (uv - [cx_px, cy_px]) / [fx_px, fy_px]
        rd = np.hypot(xd[:, 0], xd[:, 1])
        reach, where, folds = self._limits()
        if rd.max() >= reach:
            what = "folds the lens map" if folds else "needs rays more than 180° off axis"
            return (
                f"{self._describe()} {what} inside the image: {int((rd[:4] >= reach).sum())} "
                f"image corner(s) lie at distorted radius up to {rd.max():.4g}, beyond "
                f"{reach:.4g}, the largest the model reaches (at {where}); {_FIX}"
            )
        _, codes = self._solve(xd, 1e-6 / max(fx_px, fy_px), 50)
        codes[codes == _BEHIND] = _OK
        if not codes.any():
            return None
        i = int(np.flatnonzero(codes)[0])
        return (
            f"{self._describe()} makes pixel ({uv[i, 0]:.1f}, {uv[i, 1]:.1f}) not invertible "
            f"because {self._reason(int(codes[i]), xd[i])}; {_FIX}"
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
        radial = np.multiply(r2, k3 or k2 or k1)  # Horner, skipping zero high orders
        if k3:
            radial += k2
            radial *= r2
        if k3 or k2:
            radial += k1
            radial *= r2
        radial += 1.0
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

    def _jacobian_terms(self, x: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, ...]:
        """(J00, J01 = J10, J11) of the map at undistorted points x, y (N,)."""
        r2 = x * x + y * y
        radial = _horner(r2, (1.0, self.k1, self.k2, self.k3))
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

    def max_monotone_radius(self) -> float:
        """Largest undistorted normalised radius up to which r·radial(r) strictly increases.

        math.inf if the radial map increases everywhere (tangential terms ignored).
        """
        return math.sqrt(_first_positive_root((1.0, 3 * self.k1, 5 * self.k2, 7 * self.k3)))

    def _limits(self) -> tuple[float, str, bool]:
        r_max = self.max_monotone_radius()
        if math.isinf(r_max):
            return math.inf, "infinity", True
        reach = r_max * float(_horner(r_max**2, (1.0, self.k1, self.k2, self.k3)))
        angle = math.degrees(math.atan(r_max))
        return reach, f"undistorted r = {r_max:.6g}, {angle:.1f}° off axis", True

    def distort_rays(self, rays_cv: np.ndarray) -> np.ndarray:
        """CV-frame directions (N, 3) → distorted normalised coordinates (N, 2).

        Rows with z <= 0 (not in front of the camera) are NaN.
        """
        rays = _points(rays_cv, 3, "rays_cv")
        z = rays[:, 2]
        front = z > 0
        if front.all():
            return self.distort(rays[:, :2] / z[:, None])
        xy = np.full((len(rays), 2), np.nan)
        xy[front] = rays[front, :2] / z[front, None]
        return self.distort(xy)

    def rays_from_distorted(self, xy_dist: np.ndarray, tol: float = 1e-12) -> np.ndarray:
        """Distorted normalised coordinates (N, 2) → unit CV-frame rays (N, 3), z > 0.

        Raises NotInvertibleError where the inverse fails (see ``undistort``).
        """
        xy = self.undistort(xy_dist, tol=tol)
        rays = np.column_stack([xy, np.ones(len(xy))])
        rays /= np.linalg.norm(rays, axis=1, keepdims=True)
        return rays

    def _solve(self, xy_dist, tol, max_iter):
        """Newton with backtracking from xy = xy_dist; then every point is verified."""
        xd = _points(xy_dist, 2, "xy_dist")
        xy = xd.copy()
        r_max = self.max_monotone_radius()
        finite = np.isfinite(xd).all(axis=1)
        tol2 = tol * tol
        with np.errstate(all="ignore"):
            idx = np.flatnonzero(finite)
            target = xd[idx]
            res = self.distort(target) - target
            err2 = np.einsum("ij,ij->i", res, res)
            for _ in range(max_iter):
                keep = np.flatnonzero(~(err2 <= tol2))
                if keep.size < idx.size:
                    idx, target, res, err2 = idx[keep], target[keep], res[keep], err2[keep]
                if idx.size == 0:
                    break
                cur = xy[idx]
                j00, j01, j11 = self._jacobian_terms(cur[:, 0], cur[:, 1])
                step = np.column_stack([j11 * res[:, 0] - j01 * res[:, 1],
                                        j00 * res[:, 1] - j01 * res[:, 0]])
                step /= (j00 * j11 - j01 * j01)[:, None]
                singular = np.flatnonzero(~np.isfinite(step).all(axis=1))
                step[singular] = res[singular]  # fall back to a fixed-point step
                new = self._clamp(cur - step, r_max)
                new_res = self.distort(new) - target
                new_err2 = np.einsum("ij,ij->i", new_res, new_res)
                # Backtracking: accept a step only where it reduces the residual.
                worse = np.flatnonzero(~(new_err2 < err2))
                for _ in range(30):
                    if worse.size == 0:
                        break
                    step[worse] *= 0.5
                    new[worse] = self._clamp(cur[worse] - step[worse], r_max)
                    new_res[worse] = self.distort(new[worse]) - target[worse]
                    new_err2[worse] = np.einsum("ij,ij->i", new_res[worse], new_res[worse])
                    worse = worse[~(new_err2[worse] < err2[worse])]
                new[worse] = cur[worse]  # stalled: no step helps, left to fail verification
                xy[idx] = new
                moving = np.ones(idx.size, dtype=bool)
                moving[worse] = False
                idx, target = idx[moving], target[moving]
                res, err2 = new_res[moving], new_err2[moving]
            # Verify every point: residual, local invertibility, monotone region.
            resid = self.distort(xy) - xd
            resid2 = np.einsum("ij,ij->i", resid, resid)
            j00, j01, j11 = self._jacobian_terms(xy[:, 0], xy[:, 1])
            r2 = np.einsum("ij,ij->i", xy, xy)
            good = finite & (resid2 <= tol2) & (j00 * j11 - j01 * j01 > 0) & (r2 < r_max**2)
            beyond = np.hypot(xd[:, 0], xd[:, 1]) >= self._limits()[0]
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

    @property
    def is_identity(self) -> bool:
        """Always False: even with zero coefficients the equidistant map is not a pinhole."""
        return False

    def _theta_d(self, theta: np.ndarray) -> np.ndarray:
        return theta * _horner(theta * theta, (1.0, self.k1, self.k2, self.k3, self.k4))

    def _dtheta_d(self, theta: np.ndarray) -> np.ndarray:
        coeffs = (1.0, 3 * self.k1, 5 * self.k2, 7 * self.k3, 9 * self.k4)
        return _horner(theta * theta, coeffs)

    def max_monotone_theta(self) -> float:
        """Largest θ (radians) up to which θ_d(θ) strictly increases; math.inf if always."""
        coeffs = (1.0, 3 * self.k1, 5 * self.k2, 7 * self.k3, 9 * self.k4)
        return math.sqrt(_first_positive_root(coeffs))

    def _limits(self) -> tuple[float, str, bool]:
        mono = self.max_monotone_theta()
        limit = min(mono, math.pi)
        return float(self._theta_d(np.float64(limit))), f"θ = {math.degrees(limit):.2f}°", (
            mono <= math.pi
        )

    def _scale_radius(self, xy: np.ndarray, r: np.ndarray, theta: np.ndarray) -> np.ndarray:
        scale = np.divide(self._theta_d(theta), r, out=np.ones_like(r), where=r > 0)
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
        s = np.divide(self._theta_d(theta), r, out=np.ones_like(r), where=positive)  # θ_d / r
        # c = (ds/dr) / r; its cancellation near r = 0 costs only ~eps once multiplied by x².
        c = np.divide(self._dtheta_d(theta) / (1.0 + r2) - s, r2,
                      out=np.zeros_like(r), where=positive)
        jac = np.empty((len(xy), 2, 2))
        jac[:, 0, 0] = s + c * x * x
        jac[:, 0, 1] = jac[:, 1, 0] = c * x * y
        jac[:, 1, 1] = s + c * y * y
        return jac

    def _solve_theta(self, xy_dist, tol, max_iter):
        """θ (N,), θ_d (N,) and status codes: safeguarded Newton on θ_d(θ) = |xy_dist|."""
        xd = _points(xy_dist, 2, "xy_dist")
        td = np.hypot(xd[:, 0], xd[:, 1])
        mono = self.max_monotone_theta()
        limit = min(mono, math.pi)
        reach = self._limits()[0]
        finite = np.isfinite(td)
        in_range = (td < reach) | ((td <= reach) & (mono > math.pi))
        theta = np.full_like(td, np.nan)
        idx = np.flatnonzero(finite & in_range)
        th = np.minimum(td[idx], limit)
        lo, hi = np.zeros_like(th), np.full_like(th, limit)  # θ_d(lo) <= target <= θ_d(hi)
        with np.errstate(all="ignore"):
            for _ in range(max_iter):
                f = self._theta_d(th) - td[idx]
                done = np.abs(f) <= tol
                theta[idx[done]] = th[done]
                idx, th, f, lo, hi = idx[~done], th[~done], f[~done], lo[~done], hi[~done]
                if idx.size == 0:
                    break
                hi = np.where(f > 0, th, hi)
                lo = np.where(f < 0, th, lo)
                th = th - f / self._dtheta_d(th)
                bisect = ~((th > lo) & (th < hi))  # outside the bracket, or NaN
                th[bisect] = 0.5 * (lo[bisect] + hi[bisect])
            resid = np.abs(self._theta_d(theta) - td)
            good = (resid <= tol) & (self._dtheta_d(theta) > 0) & (theta < mono)
            good &= theta <= math.pi
        codes = np.full(len(td), _OK, dtype=np.int8)
        codes[~good] = np.where(np.isfinite(theta[~good]), _FOLDED, _NO_CONVERGENCE)
        codes[~in_range] = _OUT_OF_RANGE
        codes[~finite] = _NONFINITE
        theta[~good] = np.nan
        return theta, td, codes

    def _solve(self, xy_dist, tol, max_iter):
        theta, td, codes = self._solve_theta(xy_dist, tol, max_iter)
        codes[(codes == _OK) & (theta >= 0.5 * math.pi)] = _BEHIND
        with np.errstate(all="ignore"):
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
