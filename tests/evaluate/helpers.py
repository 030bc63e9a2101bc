"""Shared steps of the evaluation tests: the example project, points on a mesh and a PLY
writer for them."""

from __future__ import annotations

import numpy as np
from plyfile import PlyData, PlyElement

#: the example survey project shipped with designer (relative to the repository root)
EXAMPLE = "resources/examples/survey/survey.xml"


def points_on_mesh(vertices, faces, n, offset_m, rng):
    """Points on random faces, moved ``offset_m`` along the face normal."""
    f = rng.integers(0, len(faces), n)
    a, b, c = (vertices[faces[f, k]] for k in range(3))
    r1, r2 = rng.uniform(size=(2, n, 1))
    s = np.sqrt(r1)
    p = (1 - s) * a + s * (1 - r2) * b + s * r2 * c
    nrm = np.cross(b - a, c - a)
    return p + offset_m * nrm / np.linalg.norm(nrm, axis=1, keepdims=True)


def write_cloud(path, xyz):
    """A PLY file of the points ``xyz`` (N, 3), float64."""
    v = np.empty(len(xyz), dtype=[("x", "f8"), ("y", "f8"), ("z", "f8")])
    v["x"], v["y"], v["z"] = xyz.T
    PlyData([PlyElement.describe(v, "vertex")]).write(str(path))
