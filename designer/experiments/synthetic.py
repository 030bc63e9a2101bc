"""Exactly area-sampled checkerboard images: what a perfect renderer would write.

A board has unit squares in board coordinates (x, y); square (⌊x⌋, ⌊y⌋) is white when
⌊x⌋ + ⌊y⌋ is odd. ``H_image_from_board`` (3 × 3) maps board points to continuous pixel
coordinates (docs/conventions.md: pixel (i, j) covers [i, i+1) × [j, j+1)). A pixel's
value is the exact fraction of its area that is white — a 1 px box filter with infinitely
many samples — computed by clipping the pixel square with the square edges crossing it:

* board lines map to straight image lines under any homography, and a straight line
  meets a convex pixel iff it separates two of the pixel's corners, so the corners'
  board coordinates tell which lines (at most one x = k and one y = l; squares must be
  wider than a pixel's diagonal) cross the pixel;
* inside the pixel the colour is base ⊕ [x ≥ k] ⊕ [y ≥ l]; with a, b, ab the areas of
  the pixel in {x ≥ k}, {y ≥ l} and both, white = a + b − 2ab (or 1 minus it);
* areas come from clipping the pixel's edges against half-planes and summing
  ½ (x₁y₂ − x₂y₁) over the clipped edges plus the chord along the line (exact to
  float64 rounding, no supersampling).

The coverage (linear light, black 0, white 1) is then encoded like Cycles' output:
sRGB transfer function, 8-bit codes.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from designer.effects.srgb import encode_image


def coverage(H_image_from_board: np.ndarray, size_px: tuple[int, int]) -> np.ndarray:
    """(H, W) float64 white fraction of every pixel of a (W, H) image of the board."""
    W, H = size_px
    Hinv = np.linalg.inv(np.asarray(H_image_from_board, float))
    v, u = np.mgrid[0:H + 1, 0:W + 1].astype(float)
    xy = _apply(Hinv, u, v)
    fx, fy = np.floor(xy[0]), np.floor(xy[1])
    corners_x = np.stack([fx[:-1, :-1], fx[:-1, 1:], fx[1:, :-1], fx[1:, 1:]])
    corners_y = np.stack([fy[:-1, :-1], fy[:-1, 1:], fy[1:, :-1], fy[1:, 1:]])
    kx0, kx1 = corners_x.min(0), corners_x.max(0)
    ky0, ky1 = corners_y.min(0), corners_y.max(0)
    if (kx1 - kx0).max() > 1 or (ky1 - ky0).max() > 1:
        raise ValueError("two parallel square edges cross one pixel: board squares must be "
                         "wider than a pixel's diagonal")
    base = (kx0 + ky0) % 2  # colour where x < kx0 + 1 and y < ky0 + 1
    out = base.copy()
    jj, ii = np.nonzero((kx1 > kx0) | (ky1 > ky0))
    if jj.size:
        square = _pixel_squares(ii.astype(float), jj.astype(float))
        # half-planes x >= kx0 + 1 and y >= ky0 + 1 as image lines n·(u, v) + c >= 0
        line_a = Hinv[0][None, :] - (kx0[jj, ii] + 1)[:, None] * Hinv[2][None, :]
        line_b = Hinv[1][None, :] - (ky0[jj, ii] + 1)[:, None] * Hinv[2][None, :]
        sign = np.sign(_apply_rows(Hinv[2], ii + 0.5, jj + 0.5))  # w > 0 in front
        line_a *= sign[:, None]
        line_b *= sign[:, None]
        in_a = _clip(square, line_a)
        a, b = _area(in_a), _area(_clip(square, line_b))
        ab = _area(_clip(in_a, line_b))
        xor = a + b - 2 * ab
        out[jj, ii] = np.where(base[jj, ii] == 1, 1 - xor, xor)
    return out


def render(H_image_from_board: np.ndarray, size_px: tuple[int, int]) -> np.ndarray:
    """(H, W) uint8 sRGB image of the board, as Cycles would write it with a 1 px box filter
    and infinitely many samples."""
    return encode_image(coverage(H_image_from_board, size_px).astype(np.float32), np.uint8)


def _apply(M: np.ndarray, u: np.ndarray, v: np.ndarray) -> np.ndarray:
    w = M[2, 0] * u + M[2, 1] * v + M[2, 2]
    return np.stack([(M[0, 0] * u + M[0, 1] * v + M[0, 2]) / w,
                     (M[1, 0] * u + M[1, 1] * v + M[1, 2]) / w])


def _apply_rows(row: np.ndarray, u: np.ndarray, v: np.ndarray) -> np.ndarray:
    return row[0] * u + row[1] * v + row[2]


def _pixel_squares(i: np.ndarray, j: np.ndarray) -> np.ndarray:
    """(P, 4, 2, 2) directed edges (start, end) of the unit squares at (i, j), CCW in (u, v)."""
    p = np.stack([np.stack([i, j], -1), np.stack([i + 1, j], -1),
                  np.stack([i + 1, j + 1], -1), np.stack([i, j + 1], -1)], 1)
    return np.stack([p, np.roll(p, -1, axis=1)], 2)


def _clip(edges: np.ndarray, line: np.ndarray) -> np.ndarray:
    """Clip a convex polygon, given as directed edges (P, E, 2, 2), to the half-plane
    n·p + c >= 0 (``line`` (P, 3) = (n_u, n_v, c)): the inside parts of the edges (empty
    parts become zero-length) plus the chord from exit to entry point, (P, E + 1, 2, 2)."""
    n, c = line[:, None, :2], line[:, None, 2]
    p, q = edges[:, :, 0], edges[:, :, 1]
    sp = np.einsum("pek,pek->pe", p, np.broadcast_to(n, p.shape)) + c
    sq = np.einsum("pek,pek->pe", q, np.broadcast_to(n, q.shape)) + c
    with np.errstate(invalid="ignore", divide="ignore"):
        t = sp / (sp - sq)  # only used where sp, sq differ in sign
        crossing = p + t[..., None] * (q - p)
    p_in, q_in = sp >= 0, sq >= 0
    exits, entries = p_in & ~q_in, ~p_in & q_in
    start = np.where(p_in[..., None], p, np.where(entries[..., None], crossing, p))
    end = np.where(q_in[..., None], q, np.where(exits[..., None], crossing, start))
    start = np.where((p_in | q_in)[..., None], start, p)
    end = np.where((p_in | q_in)[..., None], end, p)
    exit_point = np.einsum("pe,pek->pk", exits.astype(float), np.nan_to_num(crossing))
    entry_point = np.einsum("pe,pek->pk", entries.astype(float), np.nan_to_num(crossing))
    chord = np.stack([exit_point, entry_point], 1)[:, None]
    return np.concatenate([np.stack([start, end], 2), chord], 1)


def _area(edges: np.ndarray) -> np.ndarray:
    """Area of polygons given as directed edges (P, E, 2, 2) (shoelace over the edges)."""
    a, b = edges[:, :, 0], edges[:, :, 1]
    return 0.5 * np.sum(a[..., 0] * b[..., 1] - b[..., 0] * a[..., 1], axis=1)


# ------------------------------------------------------------------ random boards
@dataclass(frozen=True)
class SyntheticBoard:
    """One synthetic image: its board → image map, and the corners it shows (K, 2) px."""

    H_image_from_board: np.ndarray
    size_px: tuple[int, int]
    corners_uv_px: np.ndarray
    square_px: float
    skew: float
    aspect: float
    rotation_deg: float


def random_board(rng: np.random.Generator, size_px: tuple[int, int] = (160, 160),
                 square_px: tuple[float, float] = (14.0, 60.0), max_skew: float = 0.5,
                 min_aspect: float = 0.5, margin_px: float = 10.0) -> SyntheticBoard:
    """A board under a random similarity × skew × aspect map, translated at random.

    Board → image: p = t + s · R(θ) · [[1, κ], [0, α]] · (x, y) with the square size
    s log-uniform in ``square_px``, θ uniform, skew κ uniform in ±``max_skew``, aspect α
    uniform in [``min_aspect``, 1] (foreshortening), t uniform over a whole square. The
    corners are the lattice points at least ``margin_px`` inside the image.
    """
    W, H = size_px
    s = float(np.exp(rng.uniform(*np.log(square_px))))
    theta = rng.uniform(0, 2 * np.pi)
    kappa = rng.uniform(-max_skew, max_skew)
    alpha = rng.uniform(min_aspect, 1.0)
    c, si = np.cos(theta), np.sin(theta)
    A = s * np.array([[c, -si], [si, c]]) @ np.array([[1.0, kappa], [0.0, alpha]])
    t = np.array([W / 2, H / 2]) + A @ rng.uniform(0, 1, 2)
    Hm = np.eye(3)
    Hm[:2, :2], Hm[:2, 2] = A, t
    # lattice points that can fall inside the image
    reach = int(np.ceil(np.hypot(W, H) / (s * min(alpha, 1.0) / (1 + abs(kappa))))) + 2
    g = np.arange(-reach, reach + 1, dtype=float)
    gx, gy = (a.ravel() for a in np.meshgrid(g, g))
    uv = (A @ np.stack([gx, gy])).T + t
    keep = ((uv[:, 0] >= margin_px) & (uv[:, 0] <= W - margin_px)
            & (uv[:, 1] >= margin_px) & (uv[:, 1] <= H - margin_px))
    return SyntheticBoard(Hm, (W, H), uv[keep], s, float(kappa), float(alpha),
                          float(np.degrees(theta)))
