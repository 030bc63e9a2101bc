"""Rolling-shutter projection: each image row is exposed at its own instant.

Model (docs/world.md, "Rolling shutter"; the form Metashape and Pix4D use):

* the image's pose (perspective centre ``C_world``, ``R_cam_to_world``) is the pose of
  the **first row read**, at the image's time t0;
* the rows are read one after the other over ``readout_s`` seconds: row r (0 = first
  row read) is exposed at t0 + r / H · readout_s, H the image height in px. With the
  direction ``top-to-bottom`` the first row read is the top row (v from 0 to 1), with
  ``bottom-to-top`` the bottom row;
* during the readout the camera moves at the constant velocity ``velocity_world_m_s``
  (world frame, m/s) and keeps its attitude.

In continuous pixel coordinates (origin at the top-left corner, v down) row r covers
v ∈ [r, r + 1) and its centre is v = r + ½, so a point seen at row coordinate v is
exposed ``delay_s(v) = (v − ½) / H · readout_s`` after t0 (top-to-bottom) or
``(H − ½ − v) / H · readout_s`` (bottom-to-top): exact at every row centre, the straight
line through the per-row instants in between (a sensor's rows are a staircase in time;
the two differ by at most half a row's motion).

A world point P is therefore seen where ``v = proj_v(P, C + velocity · delay_s(v))``;
:func:`rolling_shutter_projection` solves this for v by Newton's method on the row (the
camera moves a small fraction of a row per row, so it converges in a few steps) and
raises :class:`RollingShutterError` where it does not converge (the point would move
across the image faster than the readout sweeps it).

numpy only; frames and pixels as in :mod:`designer.core.projection`.
"""

from __future__ import annotations

from typing import Literal

import numpy as np

from designer.core.interior import InteriorOrientation
from designer.core.projection import project_points
from designer.errors import DesignerError

Direction = Literal["top-to-bottom", "bottom-to-top"]
DIRECTIONS: tuple[str, ...] = ("top-to-bottom", "bottom-to-top")
#: Newton steps before giving up
MAX_ITERATIONS = 50
#: convergence: the row changes by less than this (px); float64 world coordinates of
#: UTM size resolve about 1e-9 m, a few 1e-8 px at survey scales
TOLERANCE_PX = 1e-7
#: the solved row must reproduce itself to this (px)
RESIDUAL_PX = 1e-5


class RollingShutterError(DesignerError, ArithmeticError):
    """The rolling-shutter projection does not converge for some point."""


def row_delay_s(v_px, image_height_px: int, readout_s: float,
                direction: Direction = "top-to-bottom") -> np.ndarray:
    """Seconds after the first row's instant at which continuous row coordinate ``v_px``
    (px, 0 at the image top) is exposed (module docstring); exact at row centres."""
    v = np.asarray(v_px, dtype=float)
    if direction == "top-to-bottom":
        rows = v - 0.5
    elif direction == "bottom-to-top":
        rows = image_height_px - 0.5 - v
    else:
        raise ValueError(f"rolling-shutter direction {direction!r}; use one of {DIRECTIONS}")
    return rows / image_height_px * readout_s


def row_time_s(row: int, image_height_px: int, readout_s: float,
               direction: Direction = "top-to-bottom") -> float:
    """Seconds after the first row's instant at which image row ``row`` (0 = top row) is
    exposed: r / H · readout_s with r counted from the first row read."""
    return float(row_delay_s(row + 0.5, image_height_px, readout_s, direction))


def rolling_shutter_projection(
    points_world: np.ndarray,
    C_first_row_world: np.ndarray,
    R_cam_to_world: np.ndarray,
    velocity_world_m_s: np.ndarray,
    readout_s: float,
    interior: InteriorOrientation,
    direction: Direction = "top-to-bottom",
) -> np.ndarray:
    """(N, 2) pixel coordinates (u, v) where a rolling-shutter image shows the world
    points (N, 3); NaN for a point behind the camera.

    ``C_first_row_world`` (3,) and ``R_cam_to_world`` (3, 3) are the pose of the first
    row read; the camera moves at ``velocity_world_m_s`` (3,) during ``readout_s``.
    With ``readout_s == 0`` this is the global-shutter projection.
    Raises RollingShutterError where the row iteration does not converge.
    """
    P = np.asarray(points_world, dtype=float).reshape(-1, 3)
    C = np.asarray(C_first_row_world, dtype=float).reshape(3)
    R = np.asarray(R_cam_to_world, dtype=float).reshape(3, 3)
    vel = np.asarray(velocity_world_m_s, dtype=float).reshape(3)
    H = interior.image_height_px
    if not (np.isfinite(readout_s) and readout_s >= 0):
        raise ValueError(f"readout_s = {readout_s!r}; must be a finite number >= 0")
    if direction not in DIRECTIONS:
        raise ValueError(f"rolling-shutter direction {direction!r}; use one of {DIRECTIONS}")

    def project_at(v: np.ndarray) -> np.ndarray:
        # the camera at C + vel·δ sees P where the camera at C sees P − vel·δ
        delay = row_delay_s(v, H, readout_s, direction)
        return project_points(P - delay[:, None] * vel, C, R, interior).uv_px[0]

    uv = project_points(P, C, R, interior).uv_px[0]
    if readout_s == 0 or not np.any(vel):
        return uv
    ok = np.isfinite(uv[:, 1])
    v = np.where(ok, uv[:, 1], 0.0)
    step_v = 1e-3  # px: finite-difference step of the row function's slope
    # Newton on each point's row; a point whose iteration breaks down (its image moving
    # as fast as the readout sweeps, or leaving the camera's front) is dropped (NaN) —
    # allowed only far outside the image, where masks and observations do not look
    active, failed = ok.copy(), np.zeros(len(P), bool)
    for _ in range(MAX_ITERATIONS):
        if not active.any():
            break
        idx = np.flatnonzero(active)
        vi = v[idx]
        sub = P[idx]
        delay = row_delay_s(vi, H, readout_s, direction)
        g = project_points(sub - delay[:, None] * vel, C, R, interior).uv_px[0][:, 1]
        delay2 = row_delay_s(vi + step_v, H, readout_s, direction)
        g2 = project_points(sub - delay2[:, None] * vel, C, R, interior).uv_px[0][:, 1]
        slope = (g2 - g) / step_v
        # slope ≥ 1: the image moves down as fast as the readout sweeps it
        bad = ~(np.isfinite(g) & np.isfinite(slope) & (slope < 1.0 - 1e-6))
        failed[idx[bad]] = True
        active[idx[bad]] = False
        good = ~bad
        dv = (g[good] - vi[good]) / (1.0 - slope[good])
        v[idx[good]] = vi[good] + dv
        active[idx[good][np.abs(dv) < TOLERANCE_PX]] = False
    failed |= active  # not converged within MAX_ITERATIONS
    uv = project_at(np.where(failed | ~ok, 0.0, v))
    failed |= ok & ~(np.abs(uv[:, 1] - v) < RESIDUAL_PX)
    uv[~ok | failed] = np.nan
    if not failed.any():
        return uv
    # dropped points must be far outside the image (their global-shutter position)
    W = interior.image_width_px
    glob = project_points(P[failed], C, R, interior).uv_px[0]
    margin = 0.5 * max(W, H)
    inside = (np.isfinite(glob).all(axis=1) & (glob[:, 0] > -margin)
              & (glob[:, 0] < W + margin) & (glob[:, 1] > -margin) & (glob[:, 1] < H + margin))
    if not inside.any():
        return uv
    raise RollingShutterError(
        "the rolling-shutter projection did not converge: the camera moves across the "
        "image faster than the readout sweeps it (velocity "
        f"{np.linalg.norm(vel):.3g} m/s, readout {readout_s:g} s); shorten the readout or "
        "slow the flight")
