"""A project's rigs as COLMAP rigs: relative orientations and the database layout."""

from __future__ import annotations

import dataclasses

import numpy as np
import pycolmap
import pytest

from designer.core.rotation import R_CV_FROM_PHOTO
from designer.project import model as m
from designer.sfm.rigs import apply_rigs, processing_rigs, rig_frames, station_of
from designer.survey.project_poses import project_images
from tests.synthetic import rig_survey


def _cam_from_world(R_cam_to_world):
    return R_CV_FROM_PHOTO @ np.asarray(R_cam_to_world).T


@pytest.mark.parametrize("tilt_deg", [45.0, 20.0])
def test_cam_from_rig_is_the_relative_orientation_of_the_rendered_poses(tilt_deg):
    """At every station of a five-camera rig (platform turned by random ω φ κ), each
    mount's COLMAP rotation is its cam_from_rig times the reference mount's."""
    project = rig_survey(n_stations=4, tilt_deg=tilt_deg)
    (rig,) = processing_rigs(project)
    assert [s.suffix for s in rig.sensors] == ["_N", "_F", "_B", "_L", "_R"]
    np.testing.assert_allclose(rig.sensors[0].R_cam_from_rig, np.eye(3), atol=1e-15)
    images = project_images(project, None)
    by_station: dict[int, dict[str, np.ndarray]] = {}
    for st, k in zip(images.stations, images.station_index, strict=True):
        suffix = st.image_name.rsplit(".", 1)[0][-2:]
        by_station.setdefault(k, {})[suffix] = _cam_from_world(st.R_cam_to_world)
    assert len(by_station) == 4
    for poses in by_station.values():
        ref = poses["_N"]
        for sensor in rig.sensors:
            np.testing.assert_allclose(sensor.R_cam_from_rig @ ref, poses[sensor.suffix],
                                       atol=1e-12)
    forward = rig.sensors[1].R_cam_from_rig  # turned by the tilt about the x axis
    assert np.degrees(np.arccos((np.trace(forward) - 1) / 2)) == pytest.approx(tilt_deg)


def test_station_of_strips_the_suffix_before_the_extension():
    assert station_of("DJI_00001_F.png", "_F") == "DJI_00001.png"
    assert station_of("DJI_00001_F.png", "_N") is None
    assert station_of("_F.png", "_F") is None  # nothing left of the station's name
    assert station_of("IMG_7_L", "_L") == "IMG_7"


def _penta_shared(n_stations=3) -> m.Project:
    """A nadir camera and one oblique camera carried by four mounts (as the
    survey-structures template's rig)."""
    project = rig_survey(n_stations=1)
    nadir, fwd = project.cameras[0], project.cameras[1]
    oblique = dataclasses.replace(fwd, id="oblique")
    (rig,) = project.trajectory.rigs
    mounts = tuple(mt if mt.camera == "nadir" else dataclasses.replace(mt, camera="oblique")
                   for mt in rig.mounts)
    return dataclasses.replace(project, cameras=(nadir, oblique), trajectory=m.Trajectory(
        rigs=(m.Rig("penta", mounts),)))


def _database(path, stations: int):
    """Cameras 1 (nadir), 2 (oblique) and 3 (another camera), one image per mount and
    station, and two images of the other camera — as feature extraction leaves it."""
    db = pycolmap.Database.open(str(path))
    camera_of = {}
    try:
        for cid, f in ((1, 250.0), (2, 220.0), (3, 300.0)):
            db.write_camera(pycolmap.Camera(model="PINHOLE", width=200, height=150,
                                            params=[f, f, 100, 75], camera_id=cid),
                            use_camera_id=True)
            rig = pycolmap.Rig()
            rig.add_ref_sensor(pycolmap.sensor_t(pycolmap.SensorType.CAMERA, cid))
            db.write_rig(rig)
        names = [(f"ST_{k:03d}{s}.png", 1 if s == "_N" else 2)
                 for k in range(stations) for s in ("_N", "_F", "_B", "_L", "_R")]
        names += [("ORBIT_00001.png", 3), ("ORBIT_00002.png", 3)]
        for name, cid in names:
            image_id = db.write_image(pycolmap.Image(name=name, camera_id=cid))
            frame = pycolmap.Frame()
            frame.rig_id = cid
            frame.add_data_id(pycolmap.data_t(
                pycolmap.sensor_t(pycolmap.SensorType.CAMERA, cid), image_id))
            db.write_frame(frame)
            camera_of[name] = {1: "nadir", 2: "oblique", 3: "drone"}[cid]
    finally:
        db.close()
    return camera_of


def test_four_mounts_of_one_camera_become_four_sensors_of_one_rig(tmp_path):
    """The oblique camera carried by four mounts: each mount gets a database camera of its
    own (same start parameters), the rig has five sensors with the project's rotations,
    each station is one frame of five images, other images keep frames of their own."""
    project = _penta_shared()
    rigs = processing_rigs(project)
    db_path = tmp_path / "database.db"
    camera_of = _database(db_path, stations=3)
    layout = apply_rigs(pycolmap, db_path, rigs, camera_of)
    assert layout.stations == 3
    assert layout.frames["penta"]["ST_001.png"] == {
        s: f"ST_001{s}.png" for s in ("_N", "_F", "_B", "_L", "_R")}
    assert layout.sensor_of["ST_002_L.png"] == "oblique _L"
    db = pycolmap.Database.open(str(db_path))
    try:
        cameras = {c.camera_id: c for c in db.read_all_cameras()}
        images = {i.name: i for i in db.read_all_images()}
        rigs_db = db.read_all_rigs()
        frames = db.read_all_frames()
    finally:
        db.close()
    assert len(cameras) == 3 + 3  # _B, _L, _R each got their own
    by_suffix = {s: {images[f"ST_{k:03d}{s}.png"].camera_id for k in range(3)}
                 for s in ("_N", "_F", "_B", "_L", "_R")}
    assert all(len(ids) == 1 for ids in by_suffix.values())
    sensor_ids = [next(iter(ids)) for ids in by_suffix.values()]
    assert len(set(sensor_ids)) == 5 and sensor_ids[:2] == [1, 2]
    for cid in sensor_ids[2:]:
        np.testing.assert_array_equal(cameras[cid].params, cameras[2].params)
    (penta,) = [r for r in rigs_db if r.num_sensors() == 5]
    assert penta.ref_sensor_id.id == 1
    for sensor, cid in zip(rigs[0].sensors, sensor_ids, strict=True):
        sid = pycolmap.sensor_t(pycolmap.SensorType.CAMERA, cid)
        R = np.eye(3) if penta.is_ref_sensor(sid) else \
            penta.sensor_from_rig(sid).rotation.matrix()
        np.testing.assert_allclose(R, sensor.R_cam_from_rig, atol=1e-12)
        if not penta.is_ref_sensor(sid):
            np.testing.assert_array_equal(penta.sensor_from_rig(sid).translation, 0.0)
    sizes = sorted(f.num_data_ids() for f in frames)
    assert sizes == [1, 1, 5, 5, 5]
    assert len(rigs_db) == 2  # the rig and the orbit camera's own


def test_a_rig_with_one_station_or_one_image_per_station_is_not_a_rig(tmp_path):
    """Frames need two images of one station, and a rig two such stations: otherwise the
    database is left as feature extraction wrote it."""
    project = _penta_shared()
    (rig,) = processing_rigs(project)
    names = ["ST_000_N.png", "ST_000_F.png", "ST_001_N.png", "ST_002_F.png"]
    camera_of = {n: "nadir" if n.endswith("_N.png") else "oblique" for n in names}
    assert list(rig_frames(rig, names, camera_of)) == ["ST_000.png"]
    db_path = tmp_path / "database.db"
    camera_of = _database(db_path, stations=1)
    layout = apply_rigs(pycolmap, db_path, [rig], camera_of)
    assert layout.stations == 0 and not layout.sensor_of
    db = pycolmap.Database.open(str(db_path))
    try:
        assert db.num_cameras() == 3 and db.num_frames() == 7 and db.num_rigs() == 3
    finally:
        db.close()


def test_images_of_an_unnamed_camera_match_the_mounts_by_suffix():
    """A one-camera survey's ground truth does not name its camera (None): the suffix
    alone puts its images in the rig's stations; a named camera must also match."""
    (rig,) = processing_rigs(_penta_shared())
    names = [f"ST_000{s}.png" for s in ("_N", "_F", "_B")] + ["ORBIT_00001.png"]
    frames = rig_frames(rig, names, dict.fromkeys(names))
    assert frames == {"ST_000.png": {"_N": "ST_000_N.png", "_F": "ST_000_F.png",
                                     "_B": "ST_000_B.png"}}
    assert rig_frames(rig, names, dict.fromkeys(names, "drone")) == {}
