"""Dense cloud (OpenCV SGBM + COLMAP fusion) on a small real render; PLY and LAZ files."""

from __future__ import annotations

import re

import laspy
import numpy as np
import pycolmap
import pytest
import rasterio.crs
from plyfile import PlyData

from designer.core.layout import images_dir
from designer.errors import DesignerError
from designer.evaluate.compare import reference_mesh
from designer.evaluate.distance import signed_distances
from designer.sfm.dense import (
    DenseCloud,
    dense_cloud,
    write_dense_ply,
    write_las,
    write_local_model,
)

GSD_M = 0.06  # small_flight_survey: 30 m flying height, 10 um pixels, 5 mm lens
UTM = np.array([512_345.0, 5_406_789.0, 250.0])


@pytest.fixture(scope="module")
def sparse(survey, survey_cache, tmp_path_factory):
    """The session's rendered survey (``survey``, from conftest.py: a dozen 640 x 480
    images) triangulated with its known poses (features and matches from the run's shared
    cache), the model shifted into a local frame (world − origin), and the project (for
    the true mesh)."""
    from designer.sfm.reconstruct import reconstruct

    folder = tmp_path_factory.mktemp("dense")
    reconstruct(survey, folder / "sparse", mode="known-poses", log=lambda m: None,
                feature_cache=survey_cache)
    local = folder / "sparse-local"
    origin = write_local_model(folder / "sparse" / "model", local)
    rec = pycolmap.Reconstruction(str(local))
    # the local model is the world model shifted: camera centres differ by the origin
    world = pycolmap.Reconstruction(str(folder / "sparse" / "model"))
    name = next(iter(rec.images.values())).name
    assert np.allclose(world.find_image_with_name(name).projection_center() - origin,
                       rec.find_image_with_name(name).projection_center(), atol=1e-9)
    return {"images": images_dir(survey), "model": local, "origin": origin,
            "project": survey.parent / "project.xml",
            "n_sparse": rec.num_points3D(), "folder": folder}


@pytest.fixture(scope="module")
def dense(sparse):
    messages: list[str] = []
    cloud = dense_cloud(sparse["images"], sparse["model"], sparse["folder"] / "dense",
                        origin_world=sparse["origin"], log=messages.append)
    return cloud, messages


def _model_with(sparse, tmp_path, keep) -> str:
    """The local sparse model with only the images ``keep(names)`` chooses registered."""
    rec = pycolmap.Reconstruction(str(sparse["model"]))
    names = sorted(img.name for img in rec.images.values())
    kept = set(keep(names))
    for img in list(rec.images.values()):
        if img.name not in kept:
            rec.deregister_frame(img.frame_id)
    out = tmp_path / "model"
    out.mkdir()
    rec.write(str(out))
    return out


@pytest.mark.blender
@pytest.mark.slow
def test_dense_cloud_is_dense_and_lies_on_the_true_surface(sparse, dense):
    cloud, messages = dense
    assert len(cloud) >= 20 * sparse["n_sparse"]
    assert cloud.points_world.dtype == np.float64
    assert 499_970 < np.median(cloud.points_world[:, 0]) < 500_030  # world, not local
    mesh = reference_mesh(sparse["project"])
    d = signed_distances(cloud.points_world, (mesh.vertices, mesh.faces))
    assert np.median(np.abs(d)) <= GSD_M
    assert abs(np.median(d)) <= 0.25 * GSD_M  # no vertical bias
    assert cloud.colors_rgb.dtype == np.uint8 and cloud.colors_rgb.std() > 5
    assert cloud.matcher == "opencv-sgbm + colmap stereo_fusion"
    assert {"undistort_s", "pairs_s", "depth_maps_s", "fusion_s"} <= set(cloud.stage_seconds)
    assert any("depth map 12/12" in m for m in messages)


@pytest.mark.blender
@pytest.mark.slow
def test_a_rerun_resumes_from_the_written_depth_maps(sparse, dense):
    work = sparse["folder"] / "dense"
    maps = sorted((work / "workspace" / "stereo" / "depth_maps").glob("*.geometric.bin"))
    stamps = [p.stat().st_mtime_ns for p in maps]
    messages: list[str] = []
    again = dense_cloud(sparse["images"], sparse["model"], work,
                        origin_world=sparse["origin"], log=messages.append)
    assert any("resuming" in m for m in messages)
    assert not any(re.match(r"dense: depth map \d", m) for m in messages)
    assert [p.stat().st_mtime_ns for p in maps] == stamps
    # the same depth maps fuse into the same cloud, bit for bit
    assert np.array_equal(again.points_world, dense[0].points_world)
    assert np.array_equal(again.colors_rgb, dense[0].colors_rgb)


@pytest.mark.blender
@pytest.mark.slow
def test_the_area_of_interest_box_crops_the_cloud(sparse, dense):
    cloud = dense[0]
    centre = np.median(cloud.points_world, axis=0)
    box = (centre - [10, 10, 100], centre + [10, 10, 100])
    cropped = dense_cloud(sparse["images"], sparse["model"], sparse["folder"] / "dense",
                          origin_world=sparse["origin"], bounds_world=box, log=lambda m: None)
    assert 0 < len(cropped) < 0.5 * len(cloud)
    assert (cropped.points_world >= box[0] - 1e-3).all()
    assert (cropped.points_world <= box[1] + 1e-3).all()


@pytest.mark.blender
@pytest.mark.slow
def test_cancelling_stops_before_any_depth_map(sparse, tmp_path):
    with pytest.raises(DesignerError, match="cancelled; run again"):
        dense_cloud(sparse["images"], sparse["model"], tmp_path / "w",
                    origin_world=sparse["origin"], cancel=lambda: True, log=lambda m: None)
    assert not list((tmp_path / "w" / "workspace" / "stereo" / "depth_maps").glob("*.bin"))
    assert not (tmp_path / "w" / "fused.ply").exists()


@pytest.mark.blender
@pytest.mark.slow
def test_images_without_overlap_are_a_clear_error(sparse, tmp_path):
    model = _model_with(sparse, tmp_path, lambda names: [names[0], names[-1]])
    with pytest.raises(DesignerError, match="no two images share"):
        dense_cloud(sparse["images"], model, tmp_path / "w", origin_world=sparse["origin"],
                    log=lambda m: None)


@pytest.mark.blender
@pytest.mark.slow
def test_a_box_beside_the_survey_leaves_no_point_and_says_so(sparse, dense):
    # a box given in local instead of world coordinates: nothing lies inside
    box = (np.array([-50.0, -50.0, -50.0]), np.array([50.0, 50.0, 50.0]))
    with pytest.raises(DesignerError, match="no point inside the area-of-interest box"):
        dense_cloud(sparse["images"], sparse["model"], sparse["folder"] / "dense",
                    origin_world=sparse["origin"], bounds_world=box, log=lambda m: None)


def _one_image_model(folder, C_world) -> None:
    rec = pycolmap.Reconstruction()
    rec.add_camera_with_trivial_rig(
        pycolmap.Camera.create_from_model_name(1, "PINHOLE", 500.0, 640, 480))
    pose = pycolmap.Rigid3d(pycolmap.Rotation3d(), -np.asarray(C_world, dtype=float))
    rec.add_image_with_trivial_frame(pycolmap.Image(name="a.png", camera_id=1, image_id=1),
                                     pose)
    folder.mkdir()
    rec.write(str(folder))


def test_a_model_in_world_coordinates_is_refused_before_anything_is_written(tmp_path):
    _one_image_model(tmp_path / "world", UTM)
    (tmp_path / "images").mkdir()
    with pytest.raises(DesignerError, match=r"world coordinates.*write_local_model"):
        dense_cloud(tmp_path / "images", tmp_path / "world", tmp_path / "w",
                    origin_world=np.zeros(3), log=lambda m: None)
    assert not (tmp_path / "w").exists()
    with pytest.raises(DesignerError, match="no COLMAP model"):
        dense_cloud(tmp_path / "images", tmp_path, tmp_path / "w", origin_world=UTM)
    with pytest.raises(DesignerError, match="no such image folder"):
        dense_cloud(tmp_path / "nothing", tmp_path / "world", tmp_path / "w", origin_world=UTM)


def _utm_cloud(n=5000, seed=0) -> DenseCloud:
    rng = np.random.default_rng(seed)
    xyz = UTM + rng.uniform([-300, -300, -20], [300, 300, 20], size=(n, 3))
    rgb = rng.integers(0, 256, size=(n, 3), dtype=np.uint8)
    return DenseCloud(xyz, rgb)


def test_laz_reads_back_to_a_tenth_of_a_millimetre_at_utm_coordinates(tmp_path):
    cloud = _utm_cloud()
    path = write_las(tmp_path / "dense.laz", cloud, 32632, UTM + [0.4, -0.3, 0.2])
    with laspy.open(path) as reader:
        assert reader.header.are_points_compressed
        las = reader.read()
    xyz = np.column_stack([las.x, las.y, las.z])
    assert np.abs(xyz - cloud.points_world).max() <= 0.5e-4 + 1e-9
    assert np.allclose(las.header.offsets, np.round(UTM + [0.4, -0.3, 0.2]))
    assert np.allclose(las.header.scales, 1e-4)
    rgb = np.column_stack([las.red, las.green, las.blue]) >> 8
    assert np.array_equal(rgb, cloud.colors_rgb)
    wkt = next(v for v in las.header.vlrs if v.record_id == 2112).string
    assert rasterio.crs.CRS.from_wkt(wkt).to_epsg() == 32632
    assert las.header.global_encoding.wkt


def test_las_without_crs_and_far_points(tmp_path):
    cloud = _utm_cloud(100)
    with laspy.open(write_las(tmp_path / "a.las", cloud, None, UTM)) as reader:
        assert not reader.header.are_points_compressed
        assert not [v for v in reader.header.vlrs if v.record_id == 2112]
    with pytest.raises(DesignerError, match="214 km"):
        write_las(tmp_path / "b.laz", cloud, 32632, (0.0, 0.0, 0.0))
    assert not (tmp_path / "b.laz").exists()


def test_dense_ply_keeps_doubles_and_colours(tmp_path):
    cloud = _utm_cloud()
    v = PlyData.read(str(write_dense_ply(tmp_path / "d.ply", cloud)))["vertex"]
    assert v["x"].dtype == np.float64
    xyz = np.column_stack([v["x"], v["y"], v["z"]])
    assert np.array_equal(xyz, cloud.points_world)
    assert np.array_equal(np.column_stack([v["red"], v["green"], v["blue"]]), cloud.colors_rgb)
