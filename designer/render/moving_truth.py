"""Ground truth of the moving objects: per image a mask of the pixels they cover and one
table of their positions (docs/world.md, Moving objects).

The mask is the objects' exact projection: the corners of every triangle of every posed
object are projected through the image's camera (distortion included) and a pixel is in
the mask when its centre lies in one of the projected triangles (straight edges between
the projected corners). The terrain,
static scene objects and other moving objects are not tested for occlusion: a mask
shows where the objects are, also where something hides them.
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
from designer.scene.moving import MovingPose, posed_vertices

MASK_DIR = "masks"
POSITIONS_CSV = "moving_objects.csv"
POSITION_COLUMNS = ("image", "object", "X", "Y", "Z", "heading_deg", "time_s")


def mask_name(image_name: str) -> str:
    """``IMG_001.png`` → ``IMG_001_mask.png``."""
    return f"{Path(image_name).stem}_mask.png"


def object_mask(poses: tuple[MovingPose, ...], meshes: dict, pose: CameraPose,
                interior: InteriorOrientation, rolling: tuple | None = None) -> np.ndarray:
    """(H, W) uint8 mask, 255 where a moving object's projection covers the pixel
    centre (i + 0.5, j + 0.5). ``rolling`` (readout s, direction, velocity (3,) m/s): a
    rolling-shutter camera, whose rows see the objects (posed at the photo's time) each
    from its own pose (designer.core.rolling_shutter)."""
    W, H = interior.image_size_px
    mask = np.zeros((H, W), np.uint8)
    for p in poses:
        vertices, faces = meshes[p.object_id]
        if rolling is not None:
            readout_s, direction, velocity = rolling
            uv = rolling_shutter_projection(posed_vertices(vertices, p), pose.C_world,
                                            pose.R_cam_to_world, velocity, readout_s,
                                            interior, direction)
            front = np.isfinite(uv).all(axis=1)
        else:
            proj = project_points(posed_vertices(vertices, p), pose.C_world,
                                  pose.R_cam_to_world, interior)
            uv, front = proj.uv_px[0], proj.in_front[0]
        ok = front[faces].all(axis=1)
        tri = uv[faces[ok]]
        tri = tri[np.isfinite(tri).all(axis=(1, 2))]
        for corners in tri:
            fill_triangle(mask, corners)
    return mask


def fill_triangle(mask: np.ndarray, corners: np.ndarray) -> None:
    """Set to 255 the pixels of ``mask`` whose centre (i + 0.5, j + 0.5) lies inside the
    triangle ``corners`` (3, 2) px or on its edge."""
    H, W = mask.shape
    lo = np.maximum(np.floor(corners.min(axis=0) - 0.5), 0).astype(int)
    hi = np.minimum(np.ceil(corners.max(axis=0) + 0.5), [W, H]).astype(int)
    if (hi <= lo).any():
        return
    v, u = np.mgrid[lo[1]:hi[1], lo[0]:hi[0]] + 0.5
    a, b, c = corners
    area = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
    if area == 0:
        return
    sign = np.sign(area)
    inside = np.ones(u.shape, bool)
    for p, q in ((a, b), (b, c), (c, a)):
        inside &= sign * ((q[0] - p[0]) * (v - p[1]) - (q[1] - p[1]) * (u - p[0])) >= 0
    mask[lo[1]:hi[1], lo[0]:hi[0]][inside] = 255


def write_moving_truth(truth_dir: Path, interior: InteriorOrientation | CameraSet,
                       poses: tuple[CameraPose, ...], moving: tuple, meshes: dict,
                       rolling=None) -> dict[str, Path]:
    """Write ``masks/<image stem>_mask.png`` per image and ``moving_objects.csv``;
    ``interior``: the one camera, or each image's camera of a rig; ``rolling``: per image,
    its rolling shutter (readout s, direction, velocity (3,) m/s) or None (a global
    shutter)."""
    truth_dir = Path(truth_dir)
    (truth_dir / MASK_DIR).mkdir(parents=True, exist_ok=True)
    text = io.StringIO()
    writer = csv.writer(text, lineterminator="\n")
    writer.writerow(POSITION_COLUMNS)
    for k, (camera, frame_poses) in enumerate(zip(poses, moving, strict=True)):
        own = (interior.interior_of(camera.image_name) if isinstance(interior, CameraSet)
               else interior)
        mask = object_mask(frame_poses, meshes, camera, own,
                           None if rolling is None else rolling[k])
        path = truth_dir / MASK_DIR / mask_name(camera.image_name)
        with atomic_path(path) as tmp:
            if not cv2.imwrite(str(tmp), mask):
                raise OSError(f"could not write {path}")
        for p in frame_poses:
            X, Y, Z = p.position_world
            writer.writerow([camera.image_name, p.object_id, f"{X:.6f}", f"{Y:.6f}",
                             f"{Z:.6f}", f"{p.heading_deg:.6f}", f"{p.time_s:.6f}"])
    csv_path = truth_dir / POSITIONS_CSV
    write_text_atomic(csv_path, text.getvalue())
    return {"moving_objects": csv_path, "masks": truth_dir / MASK_DIR}


def read_positions_csv(path: Path) -> list[dict]:
    """Rows of ``moving_objects.csv`` with numbers as floats."""
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    for row in rows:
        for k in POSITION_COLUMNS[2:]:
            row[k] = float(row[k])
    return rows
