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
    "colmap", "colmap_cameras", "colmap_images", "colmap_points3D",
    "odm_gcp_list", "odm_geo",
    "metashape_calibration", "metashape_cameras", "metashape_markers",
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
        "colmap/points3D.txt", "gcp_observations.csv", "gcp_truth.csv",
        "metashape/calibration.xml", "metashape/cameras_reference.csv",
        "metashape/markers_reference.csv", "odm/gcp_list.txt", "odm/geo.txt",
    ])
    assert not [p for p in (tmp_path / "out").rglob(".*")]  # atomic_path temporaries
    back = read_colmap_text_poses(paths["colmap"])
    assert max(np.abs(a.C_world - b.C_world).max() for a, b in zip(poses, back, strict=True)) \
        < 1e-6
    assert [p.image_name for p in read_opk_csv(paths["opk"])] == [p.image_name for p in poses]


def test_write_all_with_a_subset_and_an_offset(tmp_path, make_survey):
    interior, poses, gcps, obs = make_survey(51)
    paths = write_all(tmp_path, interior, poses, gcps, obs, "EPSG:32632",
                      formats=("colmap", "gcp"), colmap_offset_world=ORIGIN_WORLD)
    assert set(paths) == {"colmap", "colmap_cameras", "colmap_images", "colmap_points3D",
                          "gcp_truth", "gcp_observations"}
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
