import numpy as np
import pytest

from designer.core.truth import GroundControlPoint, observe_gcps
from designer.errors import DesignerError
from designer.evaluate import gcp_errors, read_gcp_estimates_csv, triangulate_gcps
from designer.export.colmap import write_colmap_text_model
from designer.export.tables import write_gcp_truth_csv
from tests.synthetic import ORIGIN_WORLD, grid_gcps, grid_poses, mapping_camera


def test_errors_and_rmse_split_by_role():
    truth = [GroundControlPoint("A", "control", [0, 0, 0], [0, 0, 0], [0, 0, 0]),
             GroundControlPoint("B", "control", [10, 0, 0], [10, 0, 0], [0, 0, 0]),
             GroundControlPoint("C", "check", [0, 10, 0], [0, 10, 0], [0, 0, 0]),
             GroundControlPoint("D", "check", [5, 5, 5], [5, 5, 5], [0, 0, 0])]
    est = {"A": [0.03, 0.04, 0.0], "B": [10.0, 0.0, -0.02], "C": [0.0, 10.0, 0.12],
           "X": [1, 2, 3]}
    r = gcp_errors(est, truth)
    assert [p["gcp_id"] for p in r["points"]] == ["A", "B", "C"]
    assert r["points"][0]["dXY"] == pytest.approx(0.05)
    c = r["summary"]["control"]
    assert c["n"] == 2
    assert c["rmse_X"] == pytest.approx(np.sqrt(0.03 ** 2 / 2))
    assert c["rmse_XY"] == pytest.approx(np.sqrt(0.05 ** 2 / 2))
    assert c["rmse_Z"] == pytest.approx(np.sqrt(0.02 ** 2 / 2))
    assert c["rmse_XYZ"] == pytest.approx(np.sqrt((0.05 ** 2 + 0.02 ** 2) / 2))
    assert r["summary"]["check"]["n"] == 1
    assert r["summary"]["check"]["rmse_Z"] == pytest.approx(0.12)
    assert r["summary"]["all"]["n"] == 3
    assert r["missing"] == ["D"] and r["unknown"] == ["X"]
    with pytest.raises(DesignerError, match="no GCP"):
        gcp_errors({"Z": [0, 0, 0]}, truth)


def test_estimates_csv_reads_common_layouts(tmp_path):
    (tmp_path / "a.csv").write_text("# from Metashape\nLabel,X,Y,Z\nG1,1.5,2.5,3.5\nG2,4,5,6\n")
    (tmp_path / "b.csv").write_text("gcp_id;easting;northing;height\nG1;1.5;2.5;3.5\n")
    assert np.array_equal(read_gcp_estimates_csv(tmp_path / "a.csv")["G1"], [1.5, 2.5, 3.5])
    assert np.array_equal(read_gcp_estimates_csv(tmp_path / "b.csv")["G1"], [1.5, 2.5, 3.5])
    gs = grid_gcps()
    write_gcp_truth_csv(tmp_path / "gcp_truth.csv", gs, "EPSG:32632")
    back = read_gcp_estimates_csv(tmp_path / "gcp_truth.csv")
    assert np.array_equal(back["GCP3"], gs[3].true_xyz)
    (tmp_path / "c.csv").write_text("name,a,b\nG1,1,2\n")
    with pytest.raises(DesignerError, match="need an id column"):
        read_gcp_estimates_csv(tmp_path / "c.csv")


@pytest.mark.parametrize("distortion", [False, True])
def test_triangulation_from_a_colmap_model_recovers_the_truth(tmp_path, distortion):
    cam, ps, gs = mapping_camera(distortion), grid_poses(), grid_gcps()
    obs = observe_gcps(gs, ps, cam)
    # a model in local coordinates, as SfM software writes it; the offset goes back on
    write_colmap_text_model(tmp_path, cam, ps, offset_world=ORIGIN_WORLD)
    est = triangulate_gcps(tmp_path, obs, offset_world=ORIGIN_WORLD)
    assert set(est) == {g.gcp_id for g in gs}
    r = gcp_errors(est, gs)
    assert r["summary"]["all"]["max_XYZ"] < 1e-6


def test_triangulation_from_a_binary_model(tmp_path):
    pycolmap = pytest.importorskip("pycolmap")
    cam, ps, gs = mapping_camera(), grid_poses(), grid_gcps()
    (tmp_path / "txt").mkdir()
    (tmp_path / "bin").mkdir()
    write_colmap_text_model(tmp_path / "txt", cam, ps, offset_world=ORIGIN_WORLD)
    pycolmap.Reconstruction(str(tmp_path / "txt")).write_binary(str(tmp_path / "bin"))
    est = triangulate_gcps(tmp_path / "bin", observe_gcps(gs, ps, cam),
                           offset_world=ORIGIN_WORLD)
    assert gcp_errors(est, gs)["summary"]["all"]["max_XYZ"] < 1e-6
