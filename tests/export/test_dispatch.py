import json
import pathlib

import numpy as np
import pytest

import designer.atomic
from designer.core.truth import CameraPose, GcpObservation
from designer.export import FORMATS, ExportError, write_all
from designer.export.colmap import read_colmap_text_poses
from designer.export.tables import read_opk_csv
from tests.synthetic import ORIGIN_WORLD

ALL_KEYS = {
    "colmap", "colmap_cameras", "colmap_images", "colmap_points3D", "colmap_offset",
    "colmap_database", "odm_gcp_list", "odm_geo",
    "metashape_calibration", "metashape_cameras", "metashape_markers",
    "metashape_markers_xml",
    "opk", "gcp_truth", "gcp_observations",
}


def files_under(folder: pathlib.Path) -> list[str]:
    return sorted(str(p.relative_to(folder)) for p in folder.rglob("*") if p.is_file())


def test_write_all_writes_every_format_and_leaves_no_temporary_files(tmp_path, make_survey):
    interior, poses, gcps, obs = make_survey(50)
    paths = write_all(tmp_path / "out", interior, poses, gcps, obs, "EPSG:32632")
    assert set(paths) == ALL_KEYS
    for key, path in paths.items():
        assert path.exists(), key
    assert files_under(tmp_path / "out") == sorted([
        "camera_poses_opk.csv", "colmap/cameras.txt", "colmap/images.txt",
        "colmap/points3D.txt", "colmap/offset.json", "colmap/database.db",
        "gcp_observations.csv",
        "gcp_truth.csv", "metashape/calibration.xml", "metashape/cameras_reference.csv",
        "metashape/markers_reference.csv", "metashape/markers.xml", "odm/gcp_list.txt",
        "odm/geo.txt",
    ])
    assert not [p for p in (tmp_path / "out").rglob(".*")]  # atomic_path temporaries
    back = read_colmap_text_poses(paths["colmap"])  # adds offset.json's offset back
    assert max(np.abs(a.C_world - b.C_world).max() for a, b in zip(poses, back, strict=True)) \
        < 1e-9
    assert [p.image_name for p in read_opk_csv(paths["opk"])] == [p.image_name for p in poses]


def test_write_all_with_a_subset_and_an_offset(tmp_path, make_survey):
    interior, poses, gcps, obs = make_survey(51)
    paths = write_all(tmp_path, interior, poses, gcps, obs, "EPSG:32632",
                      formats=("colmap", "gcp"), colmap_offset=ORIGIN_WORLD)
    assert set(paths) == {"colmap", "colmap_cameras", "colmap_images", "colmap_points3D",
                          "colmap_offset", "colmap_database", "gcp_truth", "gcp_observations"}
    assert json.loads(paths["colmap_offset"].read_text())["offset_world_m"] == \
        ORIGIN_WORLD.tolist()
    back = read_colmap_text_poses(paths["colmap"], offset_world=ORIGIN_WORLD)
    for a, b in zip(poses, back, strict=True):
        assert np.abs(a.C_world - b.C_world).max() < 1e-9


@pytest.mark.parametrize(
    ("change", "fragment"),
    [
        (dict(formats=("colmap", "pix4d")), "unknown export format"),
        (dict(crs="EPSG:32632\nEPSG:4326"), "single line"),
        (dict(crs="my local grid"), "OpenDroneMap cannot read"),
        (dict(observations=[GcpObservation("GCP01", "nope.png", [1.0, 2.0])]), "unknown image"),
        (dict(observations=[GcpObservation("nope", "IMG_0000.png", [1.0, 2.0])]),
         "unknown GCP"),
    ],
)
def test_bad_input_writes_nothing(tmp_path, change, fragment, make_survey):
    interior, poses, gcps, obs = make_survey(52)
    args = dict(interior=interior, poses=poses, gcps=gcps, observations=obs, crs="EPSG:32632")
    args.update(change)
    with pytest.raises(ExportError, match=fragment):
        write_all(tmp_path / "out", **args)
    assert not (tmp_path / "out").exists()


def test_a_failing_write_leaves_no_partial_file(tmp_path, monkeypatch, make_survey):
    interior, poses, gcps, obs = make_survey(53)
    out = tmp_path / "out"
    write_all(out, interior, poses, gcps, obs, "EPSG:32632", formats=("opk",))
    before = (out / "camera_poses_opk.csv").read_bytes()
    written = []
    real_write_bytes = pathlib.Path.write_bytes

    def half_then_fail(self, data):
        # the disk fills up half way through the second file
        if written:
            real_write_bytes(self, data[: len(data) // 2])
            raise OSError(28, "No space left on device")
        written.append(self)
        return real_write_bytes(self, data)

    monkeypatch.setattr(pathlib.Path, "write_bytes", half_then_fail)
    moved = [CameraPose(p.image_name, p.C_world + 1.0, p.R_cam_to_world) for p in poses]
    with pytest.raises(OSError, match="No space"):
        write_all(out, interior, moved, gcps, obs, "EPSG:32632", formats=("opk", "gcp"))
    monkeypatch.undo()
    # camera_poses_opk.csv was rewritten completely before the failure; gcp_truth.csv
    # failed half way and does not exist, not even in part
    assert (out / "camera_poses_opk.csv").read_bytes() != before
    assert [p.C_world[0] for p in read_opk_csv(out / "camera_poses_opk.csv")] == [
        p.C_world[0] for p in moved]
    assert files_under(out) == ["camera_poses_opk.csv"]  # no partial file, no temporary


def test_a_failing_rewrite_keeps_the_old_file(tmp_path, monkeypatch, make_survey):
    interior, poses, gcps, obs = make_survey(54)
    paths = write_all(tmp_path, interior, poses, gcps, obs, "EPSG:32632", formats=("odm",))
    before = {k: p.read_bytes() for k, p in paths.items()}

    def fail(src, dst):
        raise OSError("rename failed")

    monkeypatch.setattr(designer.atomic.os, "replace", fail)
    with pytest.raises(OSError, match="rename failed"):
        moved = [CameraPose(p.image_name, p.C_world + 1.0, p.R_cam_to_world) for p in poses]
        write_all(tmp_path, interior, moved, gcps, obs, "EPSG:32632", formats=("odm",))
    monkeypatch.undo()
    assert {k: p.read_bytes() for k, p in paths.items()} == before
    assert files_under(tmp_path) == ["odm/gcp_list.txt", "odm/geo.txt"]


def test_formats_constant_matches_the_brief():
    assert FORMATS == ("colmap", "odm", "metashape", "opk", "gcp")


def _model_centres(folder: pathlib.Path) -> np.ndarray:
    """Camera centres exactly as images.txt states them (no offset added)."""
    return np.array([p.C_world for p in read_colmap_text_poses(folder, offset_world=np.zeros(3))])


def test_the_colmap_model_is_local_by_default(tmp_path, make_survey):
    """float32 (COLMAP's dense stage) at UTM size moves a centre by decimetres: the
    default model holds centres near 0 and names the rounded mean centre in offset.json."""
    interior, poses, gcps, obs = make_survey(55)
    paths = write_all(tmp_path, interior, poses, gcps, obs, "EPSG:32632", formats=("colmap",))
    offset = json.loads(paths["colmap_offset"].read_text())
    C = np.array([p.C_world for p in poses])
    assert offset["choice"] == "local" and offset["crs"] == "EPSG:32632"
    assert offset["offset_world_m"] == np.round(C.mean(axis=0)).tolist()
    local = _model_centres(paths["colmap"])
    assert np.abs(local).max() < 1e4
    np.testing.assert_allclose(local + offset["offset_world_m"], C, rtol=0, atol=1e-9)
    # float32 of the local centres is still within 0.1 mm; of the world ones it is not
    assert np.abs(local.astype(np.float32) - local).max() < 1e-4
    assert np.abs(C.astype(np.float32) - C).max() > 1e-2
    assert "(E0, N0, H0) = (" + ", ".join(repr(v) for v in offset["offset_world_m"]) in \
        paths["colmap_images"].read_text()


@pytest.mark.parametrize("choice", ["none", "500100,5000200,10", (500100.0, 5000200.0, 10.0)])
def test_the_colmap_offset_can_be_none_or_explicit(tmp_path, make_survey, choice):
    interior, poses, gcps, obs = make_survey(56)
    paths = write_all(tmp_path, interior, poses, gcps, obs, "EPSG:32632", formats=("colmap",),
                      colmap_offset=choice)
    expected = [0.0, 0.0, 0.0] if choice == "none" else [500100.0, 5000200.0, 10.0]
    offset = json.loads(paths["colmap_offset"].read_text())
    assert offset["offset_world_m"] == expected
    assert offset["choice"] == ("none" if choice == "none" else "explicit")
    C = np.array([p.C_world for p in poses])
    np.testing.assert_allclose(_model_centres(paths["colmap"]) + expected, C, rtol=0, atol=1e-8)


@pytest.mark.parametrize("choice", ["loc", "1,2", "1,2,x", "1,2,nan"])
def test_a_bad_colmap_offset_is_refused_before_writing(tmp_path, make_survey, choice):
    interior, poses, gcps, obs = make_survey(57)
    with pytest.raises(ExportError, match="offset"):
        write_all(tmp_path / "out", interior, poses, gcps, obs, "EPSG:32632",
                  colmap_offset=choice)
    assert not (tmp_path / "out").exists()


def test_a_bad_colmap_offset_on_the_command_line_stops_before_any_work(tmp_path,
                                                                       small_project_file):
    import subprocess
    import sys

    project = small_project_file()
    out = subprocess.run([sys.executable, "-m", "designer", "render", str(project), "-o",
                          str(tmp_path / "out"), "--colmap-offset", "1,2"],
                         capture_output=True, text=True)
    assert out.returncode == 2, out.stderr
    assert "--colmap-offset" in out.stderr and "Traceback" not in out.stderr
    assert not (tmp_path / "out").exists()
