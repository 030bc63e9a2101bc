import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from designer.core.rotation import rotation_from_opk
from designer.core.truth import CameraPose
from designer.export import ExportError
from designer.export.tables import (
    gcp_observations_csv,
    read_gcp_observations_csv,
    read_gcp_truth_csv,
    read_opk_csv,
    write_gcp_observations_csv,
    write_gcp_truth_csv,
    write_opk_csv,
)
from tests.synthetic import ORIGIN_WORLD


def test_opk_csv_round_trips_through_rotation_from_opk(tmp_path, make_survey):
    _interior, poses, _gcps, _obs = make_survey(40)
    path = write_opk_csv(tmp_path / "opk.csv", poses, "EPSG:32632")
    text = path.read_text()
    assert "image,X,Y,Z,omega_deg,phi_deg,kappa_deg" in text.splitlines()
    back = read_opk_csv(path)
    assert [p.image_name for p in back] == [p.image_name for p in poses]
    for a, b in zip(poses, back, strict=True):
        np.testing.assert_array_equal(b.C_world, a.C_world)  # exact at ORIGIN_WORLD size
        np.testing.assert_allclose(b.R_cam_to_world, a.R_cam_to_world, rtol=0, atol=1e-9)


@settings(max_examples=60, deadline=None)
@given(
    omega=st.floats(-180, 180),
    phi=st.one_of(st.floats(-90, 90), st.sampled_from([-90.0, 90.0, -89.9999, 89.9999])),
    kappa=st.floats(-180, 180),
)
def test_opk_round_trip_for_any_orientation(tmp_path_factory, omega, phi, kappa):
    R = rotation_from_opk(*np.radians([omega, phi, kappa]))
    pose = CameraPose("a.png", ORIGIN_WORLD + [0.1, 0.2, 0.3], R)
    path = write_opk_csv(tmp_path_factory.mktemp("opk") / "opk.csv", [pose], "EPSG:32632")
    (back,) = read_opk_csv(path)
    np.testing.assert_allclose(back.R_cam_to_world, R, rtol=0, atol=1e-9)


def test_gcp_truth_csv_round_trips_exactly(tmp_path, make_survey):
    _interior, _poses, gcps, _obs = make_survey(41)
    back = read_gcp_truth_csv(write_gcp_truth_csv(tmp_path / "gcps.csv", gcps, "EPSG:32632"))
    for a, b in zip(gcps, back, strict=True):
        assert (a.gcp_id, a.role) == (b.gcp_id, b.role)
        for name in ("true_xyz", "surveyed_xyz", "sigma_xyz"):
            np.testing.assert_array_equal(getattr(a, name), getattr(b, name))


def test_gcp_observations_csv_round_trips_and_states_the_pixel_convention(tmp_path, make_survey):
    _interior, _poses, _gcps, obs = make_survey(42)
    text = gcp_observations_csv(obs)
    assert "top-left corner of the top-left pixel" in text
    assert "gcp_id,image,u_px,v_px" in text.splitlines()
    back = read_gcp_observations_csv(write_gcp_observations_csv(tmp_path / "o.csv", obs))
    for a, b in zip(obs, back, strict=True):
        assert (a.gcp_id, a.image_name) == (b.gcp_id, b.image_name)
        np.testing.assert_array_equal(a.uv_px, b.uv_px)


def test_reader_rejects_a_table_with_other_columns(tmp_path):
    path = tmp_path / "x.csv"
    path.write_text("# something\nimage,E,N,H\n")
    with pytest.raises(ExportError, match="expected columns"):
        read_opk_csv(path)


def test_non_finite_numbers_are_never_written():
    from designer.export._text import fmt

    assert fmt(-0.0) == "0.0" and fmt(5000000.123456789) == "5000000.123456789"
    with pytest.raises(ExportError, match="non-finite"):
        fmt(float("nan"))
