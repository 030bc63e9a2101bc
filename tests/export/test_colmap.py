import numpy as np
import pytest

from designer.core.truth import CameraPose
from designer.export import ExportError
from designer.export.colmap import (
    colmap_camera_model,
    colmap_images_text,
    read_colmap_text_poses,
    write_colmap_text_model,
)
from designer.export.colmap_read import camera_poses, read_cameras, read_images
from designer.export.odm import odm_gcp_list_text
from tests.synthetic import LENSES, ORIGIN_WORLD, interior_for, phantom4, survey

pycolmap = pytest.importorskip("pycolmap", reason="pycolmap checks the COLMAP export")

EXPECTED_MODEL = {
    "pinhole": "PINHOLE",
    "opencv": "OPENCV",
    "full_opencv": "FULL_OPENCV",
    "fisheye": "OPENCV_FISHEYE",
    "nonsquare": "FULL_OPENCV",
}


@pytest.mark.parametrize("lens", LENSES)
def test_camera_model_name_follows_the_lens(lens):
    name, params = colmap_camera_model(interior_for(lens))
    assert name == EXPECTED_MODEL[lens]
    assert len(params) == {"PINHOLE": 4, "OPENCV": 8, "FULL_OPENCV": 12,
                           "OPENCV_FISHEYE": 8}[name]


def _model(tmp_path, seed, lens, offset=None):
    interior, poses, gcps, obs = survey(seed, lens)
    folder = write_colmap_text_model(tmp_path / "sparse", interior, poses, offset_world=offset)
    return interior, poses, gcps, obs, folder, pycolmap.Reconstruction(str(folder))


@pytest.mark.parametrize("lens", LENSES)
@pytest.mark.parametrize("seed", [10, 11])
def test_pycolmap_projects_the_gcps_where_designer_does(tmp_path, lens, seed):
    interior, poses, gcps, obs, _, rec = _model(tmp_path, seed, lens)
    assert rec.num_cameras() == 1 and rec.num_images() == len(poses)
    camera = rec.cameras[1]
    assert camera.model.name == EXPECTED_MODEL[lens]
    assert (camera.width, camera.height) == interior.image_size_px
    np.testing.assert_array_equal(camera.params, colmap_camera_model(interior)[1])

    true_xyz = {g.gcp_id: g.true_xyz for g in gcps}
    # gcp_list.txt with every role, rows in observation order: OpenCV pixels
    rows = odm_gcp_list_text(gcps, obs, "EPSG:32632", roles=("control", "check"))
    odm_px = np.array([[float(v) for v in r.split()[3:5]] for r in rows.splitlines()[1:]])
    assert len(obs) == len(odm_px) > 0
    for o, im in zip(obs, odm_px, strict=True):
        image = rec.find_image_with_name(o.image_name)
        uv_colmap = image.project_point(true_xyz[o.gcp_id])
        np.testing.assert_allclose(uv_colmap, o.uv_px, rtol=0, atol=1e-6)
        np.testing.assert_allclose(uv_colmap, im + 0.5, rtol=0, atol=1e-6)


@pytest.mark.parametrize("lens", ["opencv", "fisheye"])
def test_camera_img_from_cam_agrees_too(tmp_path, lens):
    _interior, _poses, gcps, obs, _, rec = _model(tmp_path, 12, lens)
    camera = rec.cameras[1]
    true_xyz = {g.gcp_id: g.true_xyz for g in gcps}
    for o in obs:
        image = rec.find_image_with_name(o.image_name)
        cam_from_world = image.cam_from_world()
        x_cam = cam_from_world * true_xyz[o.gcp_id]
        np.testing.assert_allclose(camera.img_from_cam(x_cam[None])[0], o.uv_px,
                                   rtol=0, atol=1e-6)


def test_offset_model_projects_offset_points(tmp_path):
    offset = ORIGIN_WORLD + [12.5, -7.25, 0.0]
    _interior, _poses, gcps, obs, folder, rec = _model(tmp_path, 13, "full_opencv", offset)
    assert "minus offset" in (folder / "images.txt").read_text()
    true_xyz = {g.gcp_id: g.true_xyz for g in gcps}
    for o in obs:
        uv = rec.find_image_with_name(o.image_name).project_point(true_xyz[o.gcp_id] - offset)
        np.testing.assert_allclose(uv, o.uv_px, rtol=0, atol=1e-7)


@pytest.mark.parametrize("offset", [None, ORIGIN_WORLD])
def test_poses_round_trip_to_a_micrometre_at_utm_size(tmp_path, offset):
    _interior, poses, _gcps, _obs, folder, rec = _model(tmp_path, 14, "opencv", offset)
    back = read_colmap_text_poses(folder, offset_world=offset)
    assert [p.image_name for p in back] == [p.image_name for p in poses]
    for a, b in zip(poses, back, strict=True):
        assert np.abs(a.C_world - b.C_world).max() < 1e-6
        np.testing.assert_allclose(b.R_cam_to_world, a.R_cam_to_world, rtol=0, atol=1e-12)
        image = rec.find_image_with_name(a.image_name)
        centre = image.projection_center() + (0 if offset is None else offset)
        assert np.abs(centre - a.C_world).max() < 1e-6


def test_images_txt_has_an_empty_points_line_after_each_image():
    poses = [CameraPose("a.png", ORIGIN_WORLD, np.eye(3)),
             CameraPose("b.png", ORIGIN_WORLD + 1, np.eye(3))]
    lines = [ln for ln in colmap_images_text(poses).splitlines() if not ln.startswith("#")]
    assert len(lines) == 4 and lines[1] == "" and lines[3] == ""
    fields = lines[0].split()
    assert len(fields) == 10 and fields[0] == "1" and fields[8] == "1" and fields[9] == "a.png"
    # nadir, image top north: CV frame x = east, y = south, z = down → q = (0, 1, 0, 0)
    np.testing.assert_allclose([float(v) for v in fields[1:5]], [0, 1, 0, 0], atol=1e-15)


def test_points3d_is_empty_and_files_are_complete(tmp_path):
    interior, poses, *_ = survey(15)
    folder = write_colmap_text_model(tmp_path / "m", interior, poses)
    assert sorted(p.name for p in folder.iterdir()) == ["cameras.txt", "images.txt", "offset.json",
                                                         "points3D.txt"]
    body = [ln for ln in (folder / "points3D.txt").read_text().splitlines()
            if not ln.startswith("#")]
    assert body == []


def test_the_reader_gives_the_same_model_from_text_and_binary(tmp_path):
    interior, poses, _gcps, _obs, folder, rec = _model(tmp_path, 15, "full_opencv", ORIGIN_WORLD)
    binary = tmp_path / "binary"
    binary.mkdir()
    rec.write_binary(str(binary))
    text_poses = read_colmap_text_poses(folder, offset_world=ORIGIN_WORLD)
    for model in (folder, binary):
        (camera,) = read_cameras(model).values()
        assert (camera.model, camera.width, camera.height) == ("FULL_OPENCV",
                                                               *interior.image_size_px)
        np.testing.assert_array_equal(camera.params, colmap_camera_model(interior)[1])
        images = read_images(model)
        assert [im.name for im in images] == [p.image_name for p in poses]
        for a, b in zip(camera_poses(images, ORIGIN_WORLD), text_poses, strict=True):
            assert np.abs(a.C_world - b.C_world).max() < 1e-6
            np.testing.assert_allclose(a.R_cam_to_world, b.R_cam_to_world, rtol=0, atol=1e-12)


def test_a_malformed_image_line_is_an_export_error(tmp_path):
    (tmp_path / "images.txt").write_text("# header\n1 1 0 0 0 0 0 0 1\n\n")
    with pytest.raises(ExportError, match="malformed image line"):
        read_colmap_text_poses(tmp_path)


def test_image_ids_follow_sorted_names_as_colmaps_feature_extractor_numbers_them(tmp_path):
    """COLMAP 3.8 numbers a folder's images in sorted-name order and point_triangulator
    pairs model and database images by IMAGE_ID: ids must follow the names, not the
    flight order (here reversed, with names whose order differs from their numbers)."""
    names = ["IMG_10.png", "IMG_9.png", "IMG_2.png", "B.png", "a.png"]
    poses = [CameraPose(n, ORIGIN_WORLD + [10.0 * i, 0, 0], np.eye(3))
             for i, n in enumerate(names)]
    lines = [ln for ln in colmap_images_text(poses).splitlines()
             if ln and not ln.startswith("#")]
    ids = {ln.split()[9]: int(ln.split()[0]) for ln in lines}
    # byte order: upper case before lower case, '1' before '2' before '9'
    assert ids == {"B.png": 1, "IMG_10.png": 2, "IMG_2.png": 3, "IMG_9.png": 4, "a.png": 5}
    assert [ln.split()[9] for ln in lines] == names  # lines keep the flight order
    folder = write_colmap_text_model(tmp_path / "m", phantom4(), poses, offset_world=ORIGIN_WORLD)
    rec = pycolmap.Reconstruction(str(folder))
    assert {img.name: img_id for img_id, img in rec.images.items()} == ids
