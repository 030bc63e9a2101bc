"""The rendered checker centres against the exported GCP observations, shared by the
hard-case render tests (docs/hard-cases.md)."""

from __future__ import annotations

import cv2
import numpy as np

from designer.export.tables import read_gcp_observations_csv, read_gcp_truth_csv
from tests.render.helpers import detect_centres

#: the mean detected-minus-exported centre (px) per axis, and the largest single one: the
#: geometry is exact; the spread is antialiasing at 8 samples (docs/conventions.md)
MEAN_PX, MAX_PX = 0.05, 0.5
#: oblique targets: the detector's window reaches past their foreshortened checker
MAX_PX_OBLIQUE = {"horizontal cameras (phi = ±90°)": 0.8}
#: horizontal cameras see the targets obliquely: only those seen ≥ 20° below the horizon
#: are measured (flatter ones are under 8 px tall)
MIN_DEPRESSION_DEG = 20.0



def measured_centres(summary, half_window):
    """(detected − exported) px of every observation inside the image, away from the
    border, seen steeply enough."""
    obs = read_gcp_observations_csv(summary.ground_truth["gcp_observations"])
    truth = {g.gcp_id: g.true_xyz for g in read_gcp_truth_csv(summary.ground_truth["gcp_truth"])}
    centres = {p.image_name: p.C_world for p in summary.prepared.poses}
    W, H = summary.prepared.interior.image_size_px
    rng = np.random.default_rng(0)
    out = []
    for name in sorted({o.image_name for o in obs}):
        rows = [o for o in obs if o.image_name == name]
        uv = np.array([o.uv_px for o in rows])
        d = np.array([centres[name] - truth[o.gcp_id] for o in rows])
        depression = np.degrees(np.arcsin(d[:, 2] / np.linalg.norm(d, axis=1)))
        keep = ((uv[:, 0] > 10) & (uv[:, 0] < W - 10) & (uv[:, 1] > 10) & (uv[:, 1] < H - 10)
                & (depression >= MIN_DEPRESSION_DEG))
        if keep.any():
            gray = cv2.imread(str(summary.images_dir / name), cv2.IMREAD_GRAYSCALE)
            out.append(detect_centres(gray, uv[keep], rng, half_window) - uv[keep])
    return np.concatenate(out) if out else np.zeros((0, 2))
