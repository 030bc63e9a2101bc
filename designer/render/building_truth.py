"""Ground truth of the buildings: their meshes (``buildings.ply``) and per image a mask
of the pixels they cover (``building_masks/<image stem>.png``), docs/world.md.

The mask is the buildings' exact projection: the corners of every triangle are
projected through the image's camera (distortion included) and a pixel is 255 when its
centre lies in one of the projected triangles (straight edges between the projected
corners; a triangle with a corner behind the camera is left out). The terrain is not
tested for occlusion: the mask shows where the buildings are, also where a hill hides
them.

``buildings.ply``: binary little-endian PLY, ``double x, y, z`` world coordinates (m),
faces ``list uchar int vertex_indices`` counter-clockwise seen from outside and
``int building``, the index of the building in the ``comment building K ID`` lines.
"""

from __future__ import annotations

from pathlib import Path

import cv2
import numpy as np

from designer.atomic import atomic_path
from designer.core.interior import InteriorOrientation
from designer.core.projection import project_points
from designer.core.rolling_shutter import rolling_shutter_projection
from designer.core.truth import CameraPose, CameraSet
from designer.render.moving_truth import fill_triangle

BUILDING_MASK_DIR = "building_masks"
BUILDINGS_PLY = "buildings.ply"


def building_mask(buildings, pose: CameraPose, interior: InteriorOrientation,
                  rolling: tuple | None = None) -> np.ndarray:
    """(H, W) uint8 mask, 255 where a building's projection covers the pixel centre.
    ``rolling`` (readout s, direction, velocity (3,) m/s): a rolling-shutter camera, each
    row seeing the buildings from its own pose (designer.core.rolling_shutter)."""
    W, H = interior.image_size_px
    mask = np.zeros((H, W), np.uint8)
    for b in buildings:
        if rolling is not None:
            readout_s, direction, velocity = rolling
            uv = rolling_shutter_projection(b.vertices_world, pose.C_world,
                                            pose.R_cam_to_world, velocity, readout_s,
                                            interior, direction)
            front = np.isfinite(uv).all(axis=1)
        else:
            proj = project_points(b.vertices_world, pose.C_world, pose.R_cam_to_world,
                                  interior)
            uv, front = proj.uv_px[0], proj.in_front[0]
        ok = front[b.faces].all(axis=1)
        tri = uv[b.faces[ok]]
        tri = tri[np.isfinite(tri).all(axis=(1, 2))]
        for corners in tri:
            fill_triangle(mask, corners)
    return mask


def write_buildings_ply(path: Path, buildings) -> None:
    """All buildings in one PLY (module docstring), atomically."""
    vertices = np.vstack([b.vertices_world for b in buildings])
    starts = np.cumsum([0] + [len(b.vertices_world) for b in buildings[:-1]])
    faces = np.vstack([b.faces + s for b, s in zip(buildings, starts, strict=True)])
    owner = np.concatenate([np.full(len(b.faces), k) for k, b in enumerate(buildings)])
    vertex = np.empty(len(vertices), dtype=[("x", "<f8"), ("y", "<f8"), ("z", "<f8")])
    vertex["x"], vertex["y"], vertex["z"] = vertices.T
    face = np.empty(len(faces), dtype=[("n", "u1"), ("v", "<i4", (3,)), ("b", "<i4")])
    face["n"], face["v"], face["b"] = 3, faces, owner
    header = ["ply", "format binary_little_endian 1.0",
              "comment designer buildings: X east, Y north, Z up, metres, world coordinates"]
    header += [f"comment building {k} {b.id}" for k, b in enumerate(buildings)]
    header += [f"element vertex {len(vertex)}", "property double x", "property double y",
               "property double z", f"element face {len(face)}",
               "property list uchar int vertex_indices", "property int building", "end_header"]
    with atomic_path(Path(path)) as tmp, open(tmp, "wb") as f:
        f.write(("\n".join(header) + "\n").encode("ascii"))
        f.write(vertex.tobytes())
        f.write(face.tobytes())


def write_building_truth(truth_dir: Path, interior: InteriorOrientation | CameraSet,
                         poses: tuple[CameraPose, ...], buildings, rolling=None
                         ) -> dict[str, Path]:
    """Write ``buildings.ply`` and ``building_masks/<image stem>.png`` per image;
    ``interior``: the one camera, or each image's camera of a rig; ``rolling``: per image,
    its rolling shutter (readout s, direction, velocity (3,) m/s) or None (a global
    shutter)."""
    truth_dir = Path(truth_dir)
    (truth_dir / BUILDING_MASK_DIR).mkdir(parents=True, exist_ok=True)
    for k, camera in enumerate(poses):
        path = truth_dir / BUILDING_MASK_DIR / f"{Path(camera.image_name).stem}.png"
        frame_rolling = None if rolling is None else rolling[k]
        with atomic_path(path) as tmp:
            own = (interior.interior_of(camera.image_name)
                   if isinstance(interior, CameraSet) else interior)
            if not cv2.imwrite(str(tmp), building_mask(buildings, camera, own,
                                                       frame_rolling)):
                raise OSError(f"could not write {path}")
    ply = truth_dir / BUILDINGS_PLY
    write_buildings_ply(ply, list(buildings))
    return {"buildings": ply, "building_masks": truth_dir / BUILDING_MASK_DIR}
