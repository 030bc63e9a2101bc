"""Ground truth of the vegetation: per image a mask of the pixels plants cover and one
table of the plants (docs/world.md, Vegetation and wind).

The mask is the plants' exact projection at the image's time: every triangle of every
posed plant (designer.scene.vegetation, the geometry the renderer instances) is
projected through the image's camera (distortion included) and a pixel is in the mask
when its centre (i + 0.5, j + 0.5) lies in a projected triangle (straight edges between
the projected corners). The terrain and other objects are not tested for occlusion: a
mask shows where plants are, also where a hill or a building hides them.
"""

from __future__ import annotations

import csv
import io
from pathlib import Path

import cv2
import numpy as np

from designer.atomic import atomic_path, write_text_atomic
from designer.core.interior import InteriorOrientation
from designer.core.projection import project_points
from designer.core.rolling_shutter import rolling_shutter_projection
from designer.core.truth import CameraPose, CameraSet
from designer.scene.vegetation import PlantSet, posed_set

MASK_DIR = "vegetation_masks"
PLANTS_CSV = "vegetation.csv"
PLANT_COLUMNS = ("plant", "kind", "E", "N", "H", "height_m", "crown_m", "yaw_deg",
                 "phase_deg")


def mask_name(image_name: str) -> str:
    """``IMG_001.png`` → ``IMG_001.png``; ``IMG_001.tif`` → ``IMG_001.png``."""
    return f"{Path(image_name).stem}.png"


def vegetation_mask(plants: list[PlantSet], wind, time_s: float | None, pose: CameraPose,
                    interior: InteriorOrientation, rolling: tuple | None = None) -> np.ndarray:
    """(H, W) uint8 mask, 255 where a plant posed at ``time_s`` covers the pixel centre.
    ``rolling`` (readout s, direction, velocity (3,) m/s): a rolling-shutter camera, each
    row seeing the plants (posed at the photo's time) from its own pose."""
    W, H = interior.image_size_px
    mask = np.zeros((H, W), np.uint8)
    for group in plants:
        if not len(group):
            continue
        vertices, faces = posed_set(group, wind, time_s)
        if rolling is not None:
            readout_s, direction, velocity = rolling
            uv = rolling_shutter_projection(vertices, pose.C_world, pose.R_cam_to_world,
                                            velocity, readout_s, interior, direction)
            front = np.isfinite(uv).all(axis=1)
        else:
            proj = project_points(vertices, pose.C_world, pose.R_cam_to_world, interior)
            uv, front = proj.uv_px[0], proj.in_front[0]
        ok = front[faces].all(axis=1)
        tri = uv[faces[ok]]
        tri = tri[np.isfinite(tri).all(axis=(1, 2))]
        lo, hi = tri.min(axis=1), tri.max(axis=1)
        tri = tri[(hi[:, 0] >= 0) & (hi[:, 1] >= 0) & (lo[:, 0] <= W) & (lo[:, 1] <= H)]
        if not len(tri):
            continue
        fill_triangles(mask, tri)
    return mask


#: pixels tested at once when filling triangles (memory of the vectorised test)
_FILL_BATCH_PX = 2_000_000


def fill_triangles(mask: np.ndarray, tri: np.ndarray) -> None:
    """Set to 255 the pixels of ``mask`` whose centre (i + 0.5, j + 0.5) lies inside or on
    the edge of any triangle ``tri`` (T, 3, 2) px — the rule of
    designer.render.moving_truth.fill_triangle, tested for many triangles at once:
    triangles are grouped by the size of their pixel box (powers of two) and each group's
    boxes are tested as one array."""
    H, W = mask.shape
    tri = np.asarray(tri, float).reshape(-1, 3, 2)
    lo = np.maximum(np.floor(tri.min(axis=1) - 0.5), 0).astype(np.int64)
    hi = np.minimum(np.ceil(tri.max(axis=1) + 0.5), [W, H]).astype(np.int64)
    a, b, c = tri[:, 0], tri[:, 1], tri[:, 2]
    area = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])
    ok = (hi > lo).all(axis=1) & (area != 0)
    size = np.where(ok, (hi - lo).max(axis=1), 0)
    edges = ((a, b), (b, c), (c, a))
    S = 1
    while ok.any():
        group = np.flatnonzero(ok & (size <= S))
        ok[group] = False
        step = max(1, _FILL_BATCH_PX // (S * S))
        dv, du = np.mgrid[:S, :S]
        for start in range(0, len(group), step):
            ids = group[start:start + step]
            u = lo[ids, 0, None, None] + du + 0.5
            v = lo[ids, 1, None, None] + dv + 0.5
            inside = (u < hi[ids, 0, None, None]) & (v < hi[ids, 1, None, None])
            sign = np.sign(area[ids])[:, None, None]
            for p, q in edges:
                p, q = p[ids, :, None, None], q[ids, :, None, None]
                inside &= sign * ((q[:, 0] - p[:, 0]) * (v - p[:, 1])
                                  - (q[:, 1] - p[:, 1]) * (u - p[:, 0])) >= 0
            mask[v[inside].astype(np.int64), u[inside].astype(np.int64)] = 255
        S *= 2


def plants_csv(plants: list[PlantSet]) -> str:
    """One row per plant: id, kind (or mesh file name), base (world E, N, H m), height and
    crown diameter (m), yaw and sway phase (deg)."""
    text = io.StringIO()
    writer = csv.writer(text, lineterminator="\n")
    writer.writerow(PLANT_COLUMNS)
    for group in plants:
        for k in range(len(group)):
            E, N, Hb = group.base_world[k]
            writer.writerow([int(group.ids[k]), group.kind, f"{E:.6f}", f"{N:.6f}",
                             f"{Hb:.6f}", f"{group.height_m[k]:.6f}",
                             f"{group.crown_m[k]:.6f}",
                             f"{np.degrees(group.yaw_rad[k]):.6f}",
                             f"{np.degrees(group.phase_rad[k]):.6f}"])
    return text.getvalue()


def write_vegetation_truth(truth_dir: Path, interior: InteriorOrientation | CameraSet,
                           poses: tuple[CameraPose, ...], times_s: list[float | None],
                           plants: list[PlantSet], wind, rolling=None) -> dict[str, Path]:
    """Write ``vegetation_masks/<image stem>.png`` per image and ``vegetation.csv``;
    ``interior``: the one camera, or each image's camera of a rig; ``rolling``: per image,
    its rolling shutter (readout s, direction, velocity (3,) m/s) or None (a global
    shutter)."""
    truth_dir = Path(truth_dir)
    (truth_dir / MASK_DIR).mkdir(parents=True, exist_ok=True)
    for k, (camera, t) in enumerate(zip(poses, times_s, strict=True)):
        own = (interior.interior_of(camera.image_name) if isinstance(interior, CameraSet)
               else interior)
        mask = vegetation_mask(plants, wind, t, camera, own,
                               None if rolling is None else rolling[k])
        path = truth_dir / MASK_DIR / mask_name(camera.image_name)
        with atomic_path(path) as tmp:
            if not cv2.imwrite(str(tmp), mask):
                raise OSError(f"could not write {path}")
    csv_path = truth_dir / PLANTS_CSV
    write_text_atomic(csv_path, plants_csv(plants))
    return {"vegetation": csv_path, "vegetation_masks": truth_dir / MASK_DIR}


def read_plants_csv(path: Path) -> list[dict]:
    """Rows of ``vegetation.csv`` with numbers as numbers."""
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    for row in rows:
        row["plant"] = int(row["plant"])
        for k in PLANT_COLUMNS[2:]:
            row[k] = float(row[k])
    return rows
