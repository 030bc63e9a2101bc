"""The study factor ``oblique-tilt-deg``: every oblique mount tilts, the nadir one stays."""

from __future__ import annotations

import numpy as np
import pytest

from designer.project.validate import semantic_problems
from designer.study.factors import FACTORS
from designer.survey.project_poses import project_images
from tests.synthetic import rig_survey, small_survey


def test_oblique_tilt_turns_every_oblique_mount_and_keeps_its_direction():
    f = FACTORS["oblique-tilt-deg"]
    assert f.stage == "render"
    base = rig_survey(n_stations=1)
    assert f.get(base) == 45.0
    steep = f.set(base, f.parse("30"))
    assert f.get(steep) == 30.0
    assert semantic_problems(steep) == []
    mounts = {mt.suffix: mt for mt in steep.trajectory.rigs[0].mounts}
    assert (mounts["_N"].omega_deg, mounts["_N"].phi_deg) == (0.0, 0.0)
    assert (mounts["_F"].omega_deg, mounts["_B"].omega_deg) == (30.0, -30.0)
    assert (mounts["_L"].phi_deg, mounts["_R"].phi_deg) == (30.0, -30.0)
    assert mounts["_B"].kappa_deg == 180.0
    # the same as a rig built at 30 degrees, image by image
    built = project_images(rig_survey(n_stations=1, tilt_deg=30.0), None)
    varied = project_images(steep, None)
    for a, b in zip(built.stations, varied.stations, strict=True):
        assert a.image_name == b.image_name
        assert np.allclose(a.R_cam_to_world, b.R_cam_to_world, atol=1e-12)


def test_oblique_tilt_needs_a_rig_and_a_sensible_angle():
    f = FACTORS["oblique-tilt-deg"]
    assert f.get(small_survey()) is None
    with pytest.raises(ValueError, match="flies no camera rig"):
        f.set(small_survey(), 30.0)
    with pytest.raises(ValueError, match="at most 90"):
        f.set(rig_survey(n_stations=1), 120.0)
    with pytest.raises(ValueError):
        f.parse("steep")
