"""The DTM and DSM from one build of the terrain: each equal, array for array, to the
surface built on its own, and the terrain built once for both."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

import designer.scene.build as build
from designer.scene.surfaces import true_surface, true_surfaces
from tests.synthetic import count_calls
from tests.world.building_helpers import building_project
from tests.world.moving_helpers import moving_project
from tests.world.vegetation_helpers import vegetation_project


def _everything():
    """Targets, buildings, swaying shrubs and a moving box on one flat site."""
    p = vegetation_project(density_per_m2=0.1)
    scene = replace(p.scene, buildings=building_project().scene.buildings,
                    moving_objects=moving_project().scene.moving_objects)
    return replace(p, scene=scene)


@pytest.mark.parametrize("with_targets", [True, False])
@pytest.mark.parametrize("at_time_s", [None, 1.0])
def test_both_surfaces_from_one_build_equal_the_surfaces_built_alone(tmp_path, with_targets,
                                                                     at_time_s):
    p = _everything()
    both = true_surfaces(p, tmp_path, ("dtm", "dsm"), with_targets=with_targets,
                         at_time_s=at_time_s)
    assert list(both) == ["dtm", "dsm"]
    for surface, (vertices, faces) in both.items():
        alone_v, alone_f = true_surface(p, tmp_path, surface, with_targets=with_targets,
                                        at_time_s=at_time_s)
        assert vertices.dtype == alone_v.dtype and faces.dtype == alone_f.dtype
        assert np.array_equal(vertices, alone_v) and np.array_equal(faces, alone_f)
    # what stands on the ground is in the DSM only, the moving box only at a moment
    (dtm_v, dtm_f), (dsm_v, dsm_f) = both["dtm"], both["dsm"]
    assert len(dtm_f) < len(dsm_f)
    assert np.array_equal(dsm_v[:len(dtm_v)], dtm_v)
    static_v, _ = true_surface(p, tmp_path, "dsm", with_targets=with_targets)
    assert (len(dsm_v) > len(static_v)) == (at_time_s is not None)


def test_the_terrain_is_built_once_for_both_surfaces(tmp_path, monkeypatch):
    p = _everything()
    heightfields = count_calls(monkeypatch, build, "build_heightfield")
    meshes = count_calls(monkeypatch, build, "build_terrain_mesh")
    targets = count_calls(monkeypatch, build, "build_targets")
    true_surfaces(p, tmp_path, ("dsm", "dtm"), at_time_s=1.0)
    assert (len(heightfields), len(meshes), len(targets)) == (1, 1, 1)
    for surface in ("dsm", "dtm"):  # built alone, each builds its own
        true_surface(p, tmp_path, surface, at_time_s=1.0)
    assert (len(heightfields), len(meshes), len(targets)) == (3, 3, 3)


def test_the_surfaces_come_in_the_order_asked_and_a_bad_name_is_refused(tmp_path):
    p = _everything()
    assert list(true_surfaces(p, tmp_path, ("dsm", "dtm"))) == ["dsm", "dtm"]
    assert list(true_surfaces(p, tmp_path, "dtm")) == ["dtm"]
    with pytest.raises(ValueError, match="'dem': give one of dtm, dsm"):
        true_surfaces(p, tmp_path, ("dtm", "dem"))
