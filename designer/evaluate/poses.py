"""Camera pose errors of a reconstruction against the true poses, optionally after a
7-parameter similarity alignment (Umeyama 1991).

Poses are designer's :class:`~designer.core.truth.CameraPose`: perspective
centre C (world, m) and R_cam_to_world (photogrammetric camera axes). Per camera:
position error dX, dY, dZ (estimated − true, m) and the rotation error, the angle of
R_trueᵀ·R_est in degrees (independent of Euler conventions). Cameras are matched by
image name; unmatched truth cameras are listed as not registered.

Readers (:func:`read_camera_poses`) take a COLMAP model folder, designer's
``camera_poses_opk.csv``, Metashape's "Omega Phi Kappa" camera export (or its reference
CSV) and OpenDroneMap's ``odm_report/shots.geojson``.
"""

from __future__ import annotations

import json
import os
from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np

from designer.core.rotation import (
    R_CV_FROM_PHOTO,
    rotation_from_opk,
    rotation_from_rotvec,
    rotvec_from_rotation,
)
from designer.core.truth import CameraPose
from designer.errors import DesignerError


def similarity_transform(src, dst, *, with_scale: bool = True):
    """(s, R, t) minimising Σ|dst − (s·R·src + t)|² (Umeyama 1991), src/dst (N, 3).

    Centroids are subtracted first, so UTM-sized coordinates keep full precision.
    Needs N >= 3 points not all on a line.
    """
    src = np.asarray(src, dtype=np.float64)
    dst = np.asarray(dst, dtype=np.float64)
    if src.shape != dst.shape or src.ndim != 2 or src.shape[1] != 3 or len(src) < 3:
        raise DesignerError(f"a similarity needs >= 3 matched points, got {len(src)}")
    mu_s, mu_d = src.mean(axis=0), dst.mean(axis=0)
    a, b = src - mu_s, dst - mu_d
    cov = b.T @ a / len(src)
    U, S, Vt = np.linalg.svd(cov)
    if S[1] < 1e-12 * max(S[0], 1e-300):
        raise DesignerError("the matched camera centres lie on a line: no unique alignment")
    D = np.diag([1.0, 1.0, np.sign(np.linalg.det(U @ Vt)) or 1.0])
    R = U @ D @ Vt
    s = float(np.trace(np.diag(S) @ D) / np.mean(np.sum(a * a, axis=1))) if with_scale else 1.0
    t = mu_d - s * R @ mu_s
    return s, R, t


def _by_name(poses) -> dict[str, CameraPose]:
    if isinstance(poses, Mapping):
        return dict(poses)
    return {p.image_name: p for p in poses}


def camera_pose_errors(
    estimated: Sequence[CameraPose] | Mapping[str, CameraPose],
    truth: Sequence[CameraPose] | Mapping[str, CameraPose],
    *,
    align: bool = True,
    with_scale: bool = True,
) -> dict:
    """Per-camera and summary pose errors as a JSON-ready dict (metres, degrees).

    With ``align`` the estimated poses are first mapped by the similarity (s, R, t)
    that best fits their centres onto the true ones (``with_scale=False``: a rigid
    motion); the alignment is reported. Without it, errors are in the frame the
    estimates were given in (e.g. after georeferencing with GCPs).
    """
    est, tru = _by_name(estimated), _by_name(truth)
    names = [n for n in tru if n in est]
    if not names:
        raise DesignerError("no camera of the reconstruction matches a true camera by image "
                            f"name (e.g. truth {next(iter(tru), '?')!r}, estimate "
                            f"{next(iter(est), '?')!r})")
    C_est = np.array([est[n].C_world for n in names])
    C_true = np.array([tru[n].C_world for n in names])
    R_est = np.array([est[n].R_cam_to_world for n in names])
    R_true = np.array([tru[n].R_cam_to_world for n in names])
    alignment = None
    if align:
        s, Ra, t = similarity_transform(C_est, C_true, with_scale=with_scale)
        C_est = s * C_est @ Ra.T + t
        R_est = Ra @ R_est
        angle = np.degrees(np.linalg.norm(rotvec_from_rotation(Ra)))
        alignment = {"scale": s, "rotation_deg": float(angle), "rotation": Ra.tolist(),
                     "translation": t.tolist(), "with_scale": with_scale}
    d = C_est - C_true
    rel = np.einsum("nji,njk->nik", R_true, R_est)  # R_trueᵀ · R_est
    # |Log(R)|, not arccos((trace − 1) / 2), which loses half the digits near 0
    rot_deg = np.degrees(np.linalg.norm(rotvec_from_rotation(rel), axis=-1))
    cameras = [{"image": n, "dX": float(d[i, 0]), "dY": float(d[i, 1]), "dZ": float(d[i, 2]),
                "dXYZ": float(np.linalg.norm(d[i])), "rotation_deg": float(rot_deg[i])}
               for i, n in enumerate(names)]
    sq = d * d
    summary = {
        "n": len(names),
        "rmse_X": float(np.sqrt(sq[:, 0].mean())), "rmse_Y": float(np.sqrt(sq[:, 1].mean())),
        "rmse_Z": float(np.sqrt(sq[:, 2].mean())),
        "rmse_XY": float(np.sqrt((sq[:, 0] + sq[:, 1]).mean())),
        "rmse_XYZ": float(np.sqrt(sq.sum(axis=1).mean())),
        "max_XYZ": float(np.sqrt(sq.sum(axis=1)).max()),
        "rotation_rmse_deg": float(np.sqrt(np.mean(rot_deg ** 2))),
        "rotation_median_deg": float(np.median(rot_deg)),
        "rotation_max_deg": float(rot_deg.max()),
    }
    return {"aligned": align, "alignment": alignment, "cameras": cameras, "summary": summary,
            "not_registered": [n for n in tru if n not in est],
            "unknown": sorted(n for n in est if n not in tru)}


def format_pose_table(result: dict) -> list[str]:
    """Markdown lines: the summary row of a :func:`camera_pose_errors` result."""
    s = result["summary"]
    lines = ["| cameras | RMSE X | RMSE Y | RMSE Z | RMSE XYZ | max XYZ | rot. RMSE | rot. max |",
             "|---|---|---|---|---|---|---|---|",
             f"| {s['n']} | {s['rmse_X']:.4f} m | {s['rmse_Y']:.4f} m | {s['rmse_Z']:.4f} m | "
             f"{s['rmse_XYZ']:.4f} m | {s['max_XYZ']:.4f} m | {s['rotation_rmse_deg']:.4f}° | "
             f"{s['rotation_max_deg']:.4f}° |"]
    a = result["alignment"]
    if a:
        lines += ["", f"Aligned by a {'similarity' if a['with_scale'] else 'rigid motion'}: "
                      f"scale {a['scale']:.6f}, rotation {a['rotation_deg']:.4f}°, "
                      f"translation {', '.join(f'{v:.3f}' for v in a['translation'])} m."]
    if result["not_registered"]:
        lines += ["", f"Not registered: {len(result['not_registered'])} of "
                      f"{s['n'] + len(result['not_registered'])} images."]
    return lines


# --------------------------------------------------------------------------- readers
def read_camera_poses(path: str | os.PathLike, *, offset_world=None) -> list[CameraPose]:
    """Camera poses from a COLMAP model folder, an ω φ κ table or ODM's shots.geojson.

    ω φ κ tables (designer's camera_poses_opk.csv, Metashape's "Omega Phi Kappa" export
    or reference CSV): a name column, X, Y, Z, then ω, φ, κ in degrees with
    R = Rx(ω)·Ry(φ)·Rz(κ), camera axes x right, y image top, z backwards — designer's
    convention, and Metashape's (see designer.export.metashape). ODM's shots.geojson
    (opendm/shots.py): ``translation`` = camera centre in the output CRS, ``rotation``
    = Rodrigues vector of world → camera in the CV frame. ``offset_world`` is added to
    every centre (COLMAP model default: the offset.json beside the model, else none).
    """
    from designer.export.colmap_read import (
        camera_poses,
        model_files,
        model_offset_world,
        read_images,
    )

    path = Path(path)
    offset = np.zeros(3) if offset_world is None else np.asarray(offset_world, np.float64)
    if path.is_dir():
        if model_files(path) is None:
            raise DesignerError(f"{path} is not a COLMAP model (no cameras/images .txt/.bin)")
        if offset_world is None:
            offset = model_offset_world(path)
        return camera_poses(read_images(path), offset)
    if not path.is_file():
        raise DesignerError(f"camera poses {path} do not exist")
    if path.suffix.lower() in (".geojson", ".json"):
        return _read_shots_geojson(path, offset)
    return _read_opk_table(path, offset)


def _read_shots_geojson(path: Path, offset: np.ndarray) -> list[CameraPose]:
    try:
        features = json.loads(path.read_text(encoding="utf-8"))["features"]
        poses = []
        for f in features:
            p = f["properties"]
            R_cv = rotation_from_rotvec(np.array(p["rotation"], dtype=float))
            R = (R_CV_FROM_PHOTO @ R_cv).T
            poses.append(CameraPose(p["filename"], np.array(p["translation"], float) + offset,
                                    R))
        return poses
    except (KeyError, TypeError, ValueError) as exc:
        raise DesignerError(f"{path} is not an OpenDroneMap shots.geojson ({exc!r})") from None


def _read_opk_table(path: Path, offset: np.ndarray) -> list[CameraPose]:
    header, rows = None, []
    for line in path.read_text(encoding="utf-8").splitlines():
        s = line.strip()
        if not s:
            continue
        if s.startswith("#"):
            if not rows:  # the last comment line before the data may name the columns
                header = s.lstrip("#").strip()
        elif _is_numeric_row(s):
            rows.append(s)
        elif not rows:
            header = s
        else:
            raise DesignerError(f"camera poses {path}: row {s!r} is not name, X, Y, Z, "
                                "omega, phi, kappa")
    if not rows:
        raise DesignerError(f"camera poses {path} have no rows")
    delimiter = next((d for d in (",", "\t", ";") if d in rows[0]), None)

    def split(s: str) -> list[str]:
        return [v.strip() for v in (s.split(delimiter) if delimiter else s.split())]

    names = [h.lower() for h in split(header)] if header else []
    want = {"name": ("image", "label", "photoid", "#label", "name", "filename", "camera"),
            "x": ("x", "x_est", "easting"), "y": ("y", "y_est", "northing"),
            "z": ("z", "z_est", "height", "altitude"),
            "o": ("omega", "omega_deg", "omega_est"), "p": ("phi", "phi_deg", "phi_est"),
            "k": ("kappa", "kappa_deg", "kappa_est")}
    cols = {k: next((names.index(n) for n in v if n in names), None) for k, v in want.items()}
    if None in cols.values():
        if names and any(c is not None for k, c in cols.items() if k in "opk"):
            raise DesignerError(f"camera poses {path}: need name, X, Y, Z, omega, phi, kappa "
                                f"columns, found {names}")
        cols = dict(zip(want, range(7), strict=True))  # Metashape's order, no header
    poses = []
    for s in rows:
        v = split(s)
        try:
            C = np.array([float(v[cols[k]]) for k in "xyz"]) + offset
            opk = np.radians([float(v[cols[k]]) for k in "opk"])
        except (ValueError, IndexError):
            raise DesignerError(f"camera poses {path}: row {s!r} is not name, X, Y, Z, omega, "
                                "phi, kappa") from None
        poses.append(CameraPose(v[cols["name"]], C, rotation_from_opk(*opk)))
    return poses


def _is_numeric_row(s: str) -> bool:
    parts = s.replace(",", " ").replace("\t", " ").replace(";", " ").split()
    try:
        [float(p) for p in parts[1:]]
    except ValueError:
        return False
    return len(parts) >= 7
