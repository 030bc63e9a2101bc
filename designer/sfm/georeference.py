"""Georeferencing helpers in the local frame: GCP triangulation, similarity fits.

``rec`` is always a pycolmap Reconstruction in local coordinates (world − offset).
"""

from __future__ import annotations

import numpy as np

from designer.errors import DesignerError


def translation(t: np.ndarray):
    import pycolmap

    return pycolmap.Sim3d(1.0, pycolmap.Rotation3d(), np.asarray(t, dtype=float))


def triangulate_gcps(rec, observations, rolling=None
                     ) -> tuple[dict[str, np.ndarray], dict[str, int]]:
    """Local coordinates of each GCP seen in ≥ 2 registered images, and how many
    registered images see each GCP (also those that could not be triangulated).
    ``rolling``: image name → (velocity, RollingShutterImage) of compensated images: a
    mark at row v is seen from the centre moved by its row's delay times the velocity."""
    import pycolmap

    def pose(img, uv):
        cfw = img.cam_from_world()
        if not rolling or img.name not in rolling:
            return cfw
        from designer.core.rolling_shutter import row_delay_s

        vel, s = rolling[img.name]
        delay = float(row_delay_s(uv[1], rec.cameras[img.camera_id].height, s.readout_s,
                                  s.direction))
        R = cfw.rotation.matrix()
        C = img.projection_center() + delay * np.asarray(vel, float)
        return pycolmap.Rigid3d(cfw.rotation, -R @ C)

    by_name = {img.name: img for img in rec.images.values() if img.has_pose}
    grouped: dict[str, list] = {}
    for o in observations:
        if o.image_name in by_name:
            grouped.setdefault(o.gcp_id, []).append(o)
    out = {}
    for gcp_id, obs in grouped.items():
        if len(obs) < 2:
            continue
        images = [by_name[o.image_name] for o in obs]
        cams = [rec.cameras[img.camera_id] for img in images]
        uv = np.array([o.uv_px for o in obs], dtype=float)
        result = pycolmap.estimate_triangulation(
            uv, [pose(img, p) for img, p in zip(images, uv, strict=True)], cams)
        if result is not None:
            out[gcp_id] = np.asarray(result["xyz"], dtype=float).reshape(3)
    return out, {k: len(v) for k, v in grouped.items()}


def fit_similarity(src: np.ndarray, tgt: np.ndarray, max_error_m: float, what: str):
    """Robust similarity mapping ``src`` onto ``tgt`` (local m), or a DesignerError."""
    import pycolmap

    ransac = pycolmap.RANSACOptions()
    ransac.max_error = max_error_m
    sim = pycolmap.estimate_sim3d_robust(np.asarray(src, float), np.asarray(tgt, float),
                                         ransac)
    if sim is None:
        raise DesignerError(f"no similarity fits the {what}; check that they are right")
    return sim["tgt_from_src"] if isinstance(sim, dict) else sim


def image_residuals_px(rec, xyz_local: np.ndarray, marks) -> np.ndarray:
    """Reprojection residuals (n, 2) px of a point at its marks [(image name, uv), ...]."""
    by_name = {img.name: img for img in rec.images.values() if img.has_pose}
    out = []
    for name, uv in marks:
        img = by_name.get(name)
        if img is None:
            continue
        cam = rec.cameras[img.camera_id]
        X_cam = img.cam_from_world() * np.asarray(xyz_local, float)
        if X_cam[2] <= 0:
            continue
        out.append(np.asarray(cam.img_from_cam(X_cam), float).reshape(2) - np.asarray(uv))
    return np.array(out).reshape(-1, 2)
