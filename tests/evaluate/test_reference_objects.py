"""The true surface of a project includes its scene objects (the validation cube)."""

import numpy as np
import pytest

from designer.evaluate.compare import reference_mesh
from designer.evaluate.distance import signed_distances
from designer.project import template, write_project


def test_the_cube_is_part_of_the_true_surface(tmp_path):
    tpl = template("validation-cube")
    path = tmp_path / "cube.xml"
    write_project(tpl.project, path)
    for name, data in tpl.files.items():
        (tmp_path / name).write_bytes(data)
    mesh = reference_mesh(path, with_targets=False)
    assert mesh.vertices.max(axis=0)[2] == pytest.approx(4.0)  # the cube's top, 4 m up
    # points on the cube's top and on one side are on the surface (distance 0)
    points = np.array([[0.5, -0.3, 4.0], [2.0, 0.7, 1.5], [10.0, 10.0, 0.0]])
    d = signed_distances(points, mesh)
    np.testing.assert_allclose(d, 0.0, atol=1e-9)
