import numpy as np
import pytest

from designer.core.projection import project_points
from designer.core.rotation import rotation_from_opk
from designer.core.truth import (
    CameraPose,
    GcpObservation,
    GroundControlPoint,
    observe_gcps,
)
from designer.errors import DesignerError, InvalidDataError
from tests.synthetic import ORIGIN_WORLD, interior_for, random_gcps, random_poses, survey


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_observations_are_the_in_image_projections_of_the_true_positions(seed):
    interior, poses, gcps, obs = survey(seed)
    proj = project_points(
        np.stack([g.true_xyz for g in gcps]),
        np.stack([p.C_world for p in poses]),
        np.stack([p.R_cam_to_world for p in poses]),
        interior,
    )
    expected = {
        (gcps[i].gcp_id, poses[m].image_name): proj.uv_px[m, i]
        for m, i in zip(*np.nonzero(proj.in_image), strict=True)
    }
    assert len(obs) == len(expected) > 0
    W, H = interior.image_size_px
    for o in obs:
        np.testing.assert_array_equal(o.uv_px, expected[(o.gcp_id, o.image_name)])
        assert 0 <= o.uv_px[0] < W and 0 <= o.uv_px[1] < H
    # ordered by GCP, then by image, in input order
    keys = [([g.gcp_id for g in gcps].index(o.gcp_id),
             [p.image_name for p in poses].index(o.image_name)) for o in obs]
    assert keys == sorted(keys)


def test_surveyed_coordinates_do_not_move_the_observations():
    interior, poses, gcps, obs = survey(3)
    moved = [GroundControlPoint(g.gcp_id, g.role, g.true_xyz, g.surveyed_xyz + 5.0, g.sigma_xyz)
             for g in gcps]
    again = observe_gcps(moved, poses, interior)
    assert [(o.gcp_id, o.image_name) for o in again] == [(o.gcp_id, o.image_name) for o in obs]
    for a, b in zip(again, obs, strict=True):
        np.testing.assert_array_equal(a.uv_px, b.uv_px)


def test_visible_fn_removes_occluded_observations():
    interior, poses, gcps, obs = survey(4)
    calls = []

    def visible(gcp_index, pose_index):
        calls.append((gcp_index, pose_index))
        return (gcp_index + pose_index) % 2 == 0

    kept = observe_gcps(gcps, poses, interior, visible_fn=visible)
    index = {g.gcp_id: i for i, g in enumerate(gcps)}
    pindex = {p.image_name: m for m, p in enumerate(poses)}
    assert len(calls) == len(obs)  # only asked about points inside the image
    assert [(o.gcp_id, o.image_name) for o in kept] == [
        (o.gcp_id, o.image_name) for o in obs
        if (index[o.gcp_id] + pindex[o.image_name]) % 2 == 0
    ]


def test_points_behind_or_outside_are_not_observed():
    interior = interior_for("opencv")
    C = ORIGIN_WORLD + [0, 0, 100]
    pose = CameraPose("a.png", C, np.eye(3))  # nadir
    gcps = [
        GroundControlPoint("below", "control", ORIGIN_WORLD, ORIGIN_WORLD, [0.01] * 3),
        GroundControlPoint("above", "control", C + [0, 0, 10], C, [0.01] * 3),
        GroundControlPoint("far", "check", ORIGIN_WORLD + [1000, 0, 0], ORIGIN_WORLD, [0.01] * 3),
    ]
    obs = observe_gcps(gcps, [pose], interior)
    assert [o.gcp_id for o in obs] == ["below"]
    np.testing.assert_allclose(obs[0].uv_px, [interior.cx_px, interior.cy_px], atol=1e-9)
    assert observe_gcps([], [pose], interior) == []


def test_utm_sized_coordinates_project_like_local_ones():
    """float64 throughout: moving the whole scene by 5e6 m changes nothing (< 1e-6 px)."""
    rng = np.random.default_rng(5)
    interior = interior_for("full_opencv")
    poses = random_poses(rng)
    gcps = random_gcps(rng)
    shift = -ORIGIN_WORLD
    local_poses = [CameraPose(p.image_name, p.C_world + shift, p.R_cam_to_world) for p in poses]
    local_gcps = [GroundControlPoint(g.gcp_id, g.role, g.true_xyz + shift, g.surveyed_xyz,
                                     g.sigma_xyz) for g in gcps]
    a = observe_gcps(gcps, poses, interior)
    b = observe_gcps(local_gcps, local_poses, interior)
    assert [(o.gcp_id, o.image_name) for o in a] == [(o.gcp_id, o.image_name) for o in b]
    err = max(np.abs(x.uv_px - y.uv_px).max() for x, y in zip(a, b, strict=True))
    assert err < 1e-6
    # the same scene in float32 is off by far more than a pixel: what the contract warns of
    f32 = [GroundControlPoint(g.gcp_id, g.role, g.true_xyz.astype(np.float32), g.surveyed_xyz,
                              g.sigma_xyz) for g in gcps]
    exact = {(o.gcp_id, o.image_name): o.uv_px for o in a}
    rounded = {(o.gcp_id, o.image_name): o.uv_px for o in observe_gcps(f32, poses, interior)}
    worst = max(np.abs(exact[k] - rounded[k]).max() for k in exact.keys() & rounded.keys())
    assert worst > 1.0


def test_data_classes_copy_and_freeze_their_arrays():
    C = ORIGIN_WORLD.copy()
    R = rotation_from_opk(0.1, 0.2, 0.3)
    pose = CameraPose("a.png", C, R)
    C[0] = 0.0
    assert pose.C_world[0] == ORIGIN_WORLD[0]
    with pytest.raises(ValueError):
        pose.C_world[0] = 1.0
    uv = np.array([1.0, 2.0])
    obs = GcpObservation("G1", "a.png", uv)
    uv[0] = 5.0
    assert obs.uv_px[0] == 1.0


@pytest.mark.parametrize(
    ("make", "fragment"),
    [
        (lambda: CameraPose("a b.png", ORIGIN_WORLD, np.eye(3)), "whitespace"),
        (lambda: CameraPose("a,b.png", ORIGIN_WORLD, np.eye(3)), "','"),
        (lambda: CameraPose("", ORIGIN_WORLD, np.eye(3)), "non-empty"),
        (lambda: CameraPose("a.png", ORIGIN_WORLD, 2 * np.eye(3)), "not a rotation"),
        (lambda: CameraPose("a.png", ORIGIN_WORLD, np.diag([1.0, 1.0, -1.0])), "not a rotation"),
        (lambda: CameraPose("a.png", ORIGIN_WORLD[:2], np.eye(3)), "shape"),
        (lambda: CameraPose("a.png", [np.nan, 0, 0], np.eye(3)), "finite"),
        (lambda: GroundControlPoint("G1", "tie", ORIGIN_WORLD, ORIGIN_WORLD, [0, 0, 0]), "role"),
        (lambda: GroundControlPoint("G1", "check", ORIGIN_WORLD, ORIGIN_WORLD, [0, -1, 0]), ">= 0"),
        (lambda: GroundControlPoint("#G1", "check", ORIGIN_WORLD, ORIGIN_WORLD, [0, 0, 0]),
         "comment"),
        (lambda: CameraPose("IMG#2.png", ORIGIN_WORLD, np.eye(3)), "comment"),
        (lambda: GcpObservation("G1", "a.png", [1, 2, 3]), "shape"),
    ],
)
def test_bad_ground_truth_is_rejected_with_a_message(make, fragment):
    with pytest.raises(InvalidDataError, match=fragment) as info:
        make()
    assert isinstance(info.value, DesignerError)


def test_duplicate_names_are_rejected():
    interior, poses, gcps, _ = survey(6)
    with pytest.raises(InvalidDataError, match="more than once"):
        observe_gcps(gcps, [*poses, poses[0]], interior)
    with pytest.raises(InvalidDataError, match="more than once"):
        observe_gcps([*gcps, gcps[0]], poses, interior)
