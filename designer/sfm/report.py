"""What a reconstruction reports: GCP errors (control and check apart), the estimated
interior orientation against the truth, camera errors, and the files they go to.

All errors are estimated − true, world metres; image residuals in px.
"""

from __future__ import annotations

import numpy as np

from designer.atomic import atomic_path, write_text_atomic
from designer.sfm.settings import PARAM_NAMES

#: radii (fractions of the half-diagonal) of the reported radial-distortion difference
RADIAL_CURVE_SAMPLES = 11


def rmse_stats(rows: list[dict]) -> dict:
    """RMSE per axis, horizontal and 3D (m), and image RMSE (px) of GCP rows."""
    if not rows:
        return {"n": 0}
    d = np.array([[r["dx_m"], r["dy_m"], r["dz_m"]] for r in rows])
    px = np.concatenate([np.asarray(r["image_residuals_px"]).reshape(-1, 2) for r in rows])
    rmse = np.sqrt(np.mean(d ** 2, axis=0))
    return {"n": len(rows), "rmse_x_m": float(rmse[0]), "rmse_y_m": float(rmse[1]),
            "rmse_z_m": float(rmse[2]), "rmse_xy_m": float(np.hypot(rmse[0], rmse[1])),
            "rmse_xyz_m": float(np.sqrt(np.sum(rmse ** 2))),
            "mean_z_m": float(np.mean(d[:, 2])),
            "image_rmse_px": float(np.sqrt(np.mean(np.sum(px ** 2, axis=1))))
            if len(px) else None}


def k1_beyond_focal_trade(estimated: np.ndarray, true: np.ndarray,
                          size_px: tuple[int, int]) -> float:
    """The radial distortion error that can bend a flat block, as a k1 error: on flat
    ground under parallel axes, a camera of focal length c·f with radial terms c²·k1,
    c⁴·k2, c⁶·k3 images the plane exactly as the true camera from c times the height, so
    that part of a k1 error (the "focal trade") moves the cameras, not the ground. The
    rest — the estimated radial factor minus the true one scaled to the estimated focal
    length (c = f_est / f_true), fitted by least squares as δ·ρ² over the normalised
    radii ρ out to the image corner — is returned as δ (dimensionless, FULL_OPENCV
    parameters; 0 for a camera that differs from the truth by the trade alone)."""
    est, tru = np.asarray(estimated, float), np.asarray(true, float)
    f_est, f_true = 0.5 * (est[0] + est[1]), 0.5 * (tru[0] + tru[1])
    c = f_est / f_true
    W, H = size_px
    rho2 = (np.linspace(0.0, np.hypot(W / 2, H / 2), 64) / f_est) ** 2
    k_est = est[4] * rho2 + est[5] * rho2 ** 2 + est[8] * rho2 ** 3
    k_eq = (c ** 2 * tru[4] * rho2 + c ** 4 * tru[5] * rho2 ** 2
            + c ** 6 * tru[8] * rho2 ** 3)
    d = k_est - k_eq
    return float(np.dot(d, rho2) / np.dot(rho2, rho2))


def _radial_px(params: np.ndarray, r_px: np.ndarray) -> np.ndarray:
    """Radial displacement (px) at image radius ``r_px`` of FULL_OPENCV parameters."""
    f = 0.5 * (params[0] + params[1])
    rho2 = (r_px / f) ** 2
    return r_px * (params[4] * rho2 + params[5] * rho2 ** 2 + params[8] * rho2 ** 3)


def intrinsics_report(estimated: np.ndarray, true: np.ndarray, start: np.ndarray,
                      size_px: tuple[int, int]) -> dict:
    """Estimated vs true FULL_OPENCV parameters, Δf/Δc in px, and the difference of the
    radial distortion (px) from the principal point to the image corner."""
    est, tru, sta = (np.asarray(a, float) for a in (estimated, true, start))
    W, H = size_px
    r = np.linspace(0.0, np.hypot(W / 2, H / 2), RADIAL_CURVE_SAMPLES)
    diff = _radial_px(est, r) - _radial_px(tru, r)
    return {
        "estimated": dict(zip(PARAM_NAMES, est.tolist(), strict=True)),
        "true": dict(zip(PARAM_NAMES, tru.tolist(), strict=True)),
        "start": dict(zip(PARAM_NAMES, sta.tolist(), strict=True)),
        "delta_f_px": float(0.5 * (est[0] + est[1] - tru[0] - tru[1])),
        "delta_fx_px": float(est[0] - tru[0]), "delta_fy_px": float(est[1] - tru[1]),
        "delta_cx_px": float(est[2] - tru[2]), "delta_cy_px": float(est[3] - tru[3]),
        "delta_k1": float(est[4] - tru[4]), "delta_k2": float(est[5] - tru[5]),
        "k1_beyond_focal_trade": k1_beyond_focal_trade(est, tru, size_px),
        "delta_k3": float(est[8] - tru[8]), "delta_p1": float(est[6] - tru[6]),
        "delta_p2": float(est[7] - tru[7]),
        "radial_difference_px": {"radius_px": r.tolist(), "difference_px": diff.tolist(),
                                 "max_abs_px": float(np.max(np.abs(diff)))},
    }


def camera_errors(estimated: dict, truth: dict) -> dict:
    """Centre errors (m) and rotation angle errors (deg) of images in both dicts of
    name → (C_world (3,), R_cam_from_world (3, 3))."""
    names = sorted(set(estimated) & set(truth))
    if not names:
        return {"n": 0}
    dC = np.array([estimated[n][0] - truth[n][0] for n in names])
    angles = []
    for n in names:
        R = estimated[n][1] @ truth[n][1].T
        angles.append(np.degrees(np.arccos(np.clip((np.trace(R) - 1) / 2, -1, 1))))
    rmse = np.sqrt(np.mean(dC ** 2, axis=0))
    return {"n": len(names), "rmse_x_m": float(rmse[0]), "rmse_y_m": float(rmse[1]),
            "rmse_z_m": float(rmse[2]), "max_position_error_m":
            float(np.max(np.linalg.norm(dC, axis=1))),
            "rmse_angle_deg": float(np.sqrt(np.mean(np.square(angles)))),
            "max_angle_deg": float(np.max(angles))}


def write_cloud_ply(rec, path, offset: np.ndarray) -> None:
    """The sparse cloud (world = local + offset) as binary PLY with double coordinates
    and uchar colours."""
    from plyfile import PlyData, PlyElement

    pts = list(rec.points3D.values())
    data = np.empty(len(pts), dtype=[("x", "f8"), ("y", "f8"), ("z", "f8"),
                                     ("red", "u1"), ("green", "u1"), ("blue", "u1")])
    if pts:
        xyz = np.array([p.xyz for p in pts]) + np.asarray(offset, float)
        rgb = np.array([p.color for p in pts])
        data["x"], data["y"], data["z"] = xyz.T
        data["red"], data["green"], data["blue"] = rgb.T
    with atomic_path(path) as tmp:
        PlyData([PlyElement.describe(data, "vertex")]).write(str(tmp))


def write_gcp_residuals(rows: list[dict], path) -> None:
    """id, role, images, image RMSE (px), estimated X Y Z and dX dY dZ (world m)."""
    lines = ["# GCP residuals: estimated minus true coordinates, world m; image_rmse_px = "
             "reprojection RMSE at the marked image positions",
             "id,role,images,image_rmse_px,X,Y,Z,dX,dY,dZ"]
    for r in rows:
        X, Y, Z = r["estimated"]
        px = np.asarray(r["image_residuals_px"]).reshape(-1, 2)
        rms = float(np.sqrt(np.mean(np.sum(px ** 2, axis=1)))) if len(px) else float("nan")
        lines.append(f"{r['id']},{r['role']},{r['images']},{rms!r},{X!r},{Y!r},{Z!r},"
                     f"{r['dx_m']!r},{r['dy_m']!r},{r['dz_m']!r}")
    write_text_atomic(path, "\n".join(lines) + "\n")
