"""Write a compared cloud as PLY with its signed distance as a per-vertex scalar.

Binary little-endian PLY: ``double x, y, z`` in world coordinates (UTM-sized values keep
~1e-9 m; CloudCompare offers its global shift when loading them), ``uchar red, green,
blue`` and ``float nx, ny, nz`` when the cloud has them, then ``double
scalar_signed_distance`` (metres; NaN where the point was beyond the maximum
distance). CloudCompare imports every extra vertex property as a scalar field and
strips the ``scalar_`` prefix it writes itself, so the field appears as
"signed_distance"; plyfile, Open3D, PDAL and MeshLab read it too.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from designer.atomic import atomic_path
from designer.errors import DesignerError

SCALAR_NAME = "scalar_signed_distance"


def write_distances_ply(
    path: str | os.PathLike,
    xyz_world,
    distances,
    *,
    rgb=None,
    normals=None,
    scalar_name: str = SCALAR_NAME,
    comments: tuple[str, ...] = (),
    chunk: int = 1 << 21,
) -> Path:
    """Write points (N, 3) with ``distances`` (N,) as a binary PLY, atomically; the path."""
    xyz = np.asarray(xyz_world)
    d = np.asarray(distances)
    n = len(xyz)
    if xyz.ndim != 2 or xyz.shape[1] != 3 or d.shape != (n,):
        raise DesignerError(f"need (N, 3) points and (N,) distances, got {xyz.shape} and "
                            f"{d.shape}")
    fields = [("x", "<f8"), ("y", "<f8"), ("z", "<f8")]
    if rgb is not None:
        fields += [("red", "u1"), ("green", "u1"), ("blue", "u1")]
    if normals is not None:
        fields += [("nx", "<f4"), ("ny", "<f4"), ("nz", "<f4")]
    fields.append((scalar_name, "<f8"))
    ply_type = {"<f8": "double", "<f4": "float", "u1": "uchar"}
    header = ["ply", "format binary_little_endian 1.0",
              "comment designer signed distances: X east, Y north, Z up, metres; "
              f"{scalar_name} > 0 above/outside the mesh"]
    header += [f"comment {c}" for c in comments if "\n" not in c and "\r" not in c]
    header.append(f"element vertex {n}")
    header += [f"property {ply_type[t]} {name}" for name, t in fields]
    header.append("end_header")
    dtype = np.dtype(fields)
    path = Path(path)
    rgb = None if rgb is None else np.asarray(rgb)
    normals = None if normals is None else np.asarray(normals)
    block = np.empty(min(n, chunk), dtype=dtype)
    with atomic_path(path) as tmp, open(tmp, "wb") as fh:
        fh.write(("\n".join(header) + "\n").encode("ascii"))
        for s in range(0, n, chunk):  # bounded memory for very large clouds
            e = min(n, s + chunk)
            part = block[:e - s]
            for i, c in enumerate("xyz"):
                part[c] = xyz[s:e, i]
            if rgb is not None:
                for i, c in enumerate(("red", "green", "blue")):
                    part[c] = rgb[s:e, i]
            if normals is not None:
                for i, c in enumerate(("nx", "ny", "nz")):
                    part[c] = normals[s:e, i]
            part[scalar_name] = d[s:e]
            fh.write(part.view(np.uint8))  # the buffer itself, no copy
    return path
