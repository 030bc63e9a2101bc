"""COLMAP's FULL_OPENCV camera model, vectorised, with its analytic Jacobians.

Parameters in COLMAP's order: fx fy cx cy k1 k2 p1 p2 k3 k4 k5 k6 (px for fx … cy). A
CV-frame point P (x right, y down, z forward; any unit) is imaged at

    u, v = x/z, y/z;  r² = u² + v²
    radial = (1 + k1 r² + k2 r⁴ + k3 r⁶) / (1 + k4 r² + k5 r⁴ + k6 r⁶)
    x_d = u · radial + 2 p1 u v + p2 (r² + 2u²);  y_d = v · radial + 2 p2 u v + p1 (r² + 2v²)
    img = (fx x_d + cx, fy y_d + cy)   (px, COLMAP's continuous pixel coordinates)

as ``colmap/sensor/models.h`` (FullOpenCVCameraModel) does; PINHOLE's and OPENCV's
parameters are the first 4 and 8 of these, so :func:`full_opencv_params` pads them with
zeros. A point at z below machine epsilon is not imaged (COLMAP's cost then returns a
zero residual): its flag is False and its pixel and Jacobians are zero.
"""

from __future__ import annotations

import numpy as np

#: camera models whose parameters are a prefix of FULL_OPENCV's (COLMAP's names)
PREFIX_MODELS = {"PINHOLE": 4, "OPENCV": 8, "FULL_OPENCV": 12}


def full_opencv_params(model_name: str, params) -> np.ndarray:
    """A camera's parameters as the 12 of FULL_OPENCV (zeros for a shorter model's
    missing distortion); ValueError for a model that is not a prefix of it."""
    if model_name not in PREFIX_MODELS:
        raise ValueError(f"camera model {model_name}: the vectorised adjustment supports "
                         f"{', '.join(PREFIX_MODELS)}")
    out = np.zeros(12)
    p = np.asarray(params, float)
    out[:PREFIX_MODELS[model_name]] = p
    return out


def img_from_cam(params: np.ndarray, P: np.ndarray, jacobians: bool = True,
                 param_index=None):
    """Pixels of CV-frame points ``P`` (N, 3) with per-point FULL_OPENCV ``params``
    (N, 12): (uv px (N, 2), imaged (N,) bool, ∂uv/∂P (N, 2, 3), ∂uv/∂params (N, 2, k));
    the parameters' Jacobian for the indices ``param_index`` (default all 12: k = 12),
    the Jacobians None with ``jacobians`` False."""
    fx, fy, cx, cy, k1, k2, p1, p2, k3, k4, k5, k6 = params.T
    z = P[:, 2]
    imaged = z >= np.finfo(float).eps
    iz = np.where(imaged, 1.0 / np.where(imaged, z, 1.0), 0.0)
    u, v = P[:, 0] * iz, P[:, 1] * iz
    uu, vv, uv_ = u * u, v * v, u * v
    r2 = uu + vv
    r4 = r2 * r2
    r6 = r4 * r2
    num = 1.0 + k1 * r2 + k2 * r4 + k3 * r6
    den = 1.0 + k4 * r2 + k5 * r4 + k6 * r6
    radial = num / den
    xd = u * radial + 2.0 * p1 * uv_ + p2 * (r2 + 2.0 * uu)
    yd = v * radial + 2.0 * p2 * uv_ + p1 * (r2 + 2.0 * vv)
    img = np.stack([fx * xd + cx, fy * yd + cy], axis=1)
    img[~imaged] = 0.0
    if not jacobians:
        return img, imaged, None, None

    # ∂(x_d, y_d)/∂(u, v); radial' = ∂radial/∂r²
    dradial = ((k1 + 2.0 * k2 * r2 + 3.0 * k3 * r4) * den
               - num * (k4 + 2.0 * k5 * r2 + 3.0 * k6 * r4)) / (den * den)
    dxu = radial + 2.0 * uu * dradial + 2.0 * p1 * v + 6.0 * p2 * u
    dxv = 2.0 * uv_ * dradial + 2.0 * p1 * u + 2.0 * p2 * v
    dyu = 2.0 * uv_ * dradial + 2.0 * p2 * v + 2.0 * p1 * u
    dyv = radial + 2.0 * vv * dradial + 2.0 * p2 * u + 6.0 * p1 * v
    # ∂(u, v)/∂P = [[1/z, 0, −u/z], [0, 1/z, −v/z]]
    J_P = np.zeros((len(P), 2, 3))
    J_P[:, 0, 0] = fx * dxu * iz
    J_P[:, 0, 1] = fx * dxv * iz
    J_P[:, 0, 2] = -fx * (dxu * u + dxv * v) * iz
    J_P[:, 1, 0] = fy * dyu * iz
    J_P[:, 1, 1] = fy * dyv * iz
    J_P[:, 1, 2] = -fy * (dyu * u + dyv * v) * iz

    if param_index is not None and not len(param_index):
        return img, imaged, J_P, np.zeros((len(P), 2, 0))
    J_params = np.zeros((len(P), 2, 12))
    J_params[:, 0, 0] = xd
    J_params[:, 1, 1] = yd
    J_params[:, 0, 2] = 1.0
    J_params[:, 1, 3] = 1.0
    for k, rk in ((4, r2), (5, r4), (8, r6)):  # k1 k2 k3: numerator
        J_params[:, 0, k] = fx * u * rk / den
        J_params[:, 1, k] = fy * v * rk / den
    for k, rk in ((9, r2), (10, r4), (11, r6)):  # k4 k5 k6: denominator
        J_params[:, 0, k] = -fx * u * radial * rk / den
        J_params[:, 1, k] = -fy * v * radial * rk / den
    J_params[:, 0, 6] = fx * 2.0 * uv_  # p1
    J_params[:, 1, 6] = fy * (r2 + 2.0 * vv)
    J_params[:, 0, 7] = fx * (r2 + 2.0 * uu)  # p2
    J_params[:, 1, 7] = fy * 2.0 * uv_
    J_params[~imaged] = 0.0
    if param_index is not None:
        J_params = J_params[:, :, param_index]
    return img, imaged, J_P, J_params
