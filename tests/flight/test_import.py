"""Flown surveys in: images with DJI-style metadata, geo.txt and reference CSVs replay
the true poses (≤ 1 cm, ≤ 0.01°); bad input gives one clean error and no output."""

import math
from pathlib import Path

import numpy as np
import pytest

from designer.cli.main import main
from designer.core.rotation import rotation_from_opk
from designer.export.metashape import metashape_cameras_csv
from designer.export.odm import odm_geo_text, odm_ypr_deg_from_rotation
from designer.flight.geodesy import Georef
from designer.project import load_project, write_project
from designer.scene.build import build_heightfield
from tests import synthetic
from tests.flight.helpers import (
    EXAMPLE,
    dji_angles_deg,
    grid_azimuth_of_true_north_deg,
    rotation_error_deg,
    true_poses,
    write_dji_image,
)

SMALL_CAMERA = {"make": "Acme", "model": "Survey 5", "focal_mm": 5.0, "size_px": (640, 480)}


def small_base(tmp_path, E0):
    """The small flight survey (not a preset camera) at easting E0, written to disk."""
    project = synthetic.small_flight_survey(origin=(E0, 5_000_000.0, 250.0))
    path = tmp_path / "base" / "project.xml"
    path.parent.mkdir()
    write_project(project, path)
    return path


def compare(new_path, poses, rename=lambda n: n):
    project = load_project(new_path)  # the written project is valid
    eos = {e.name: e for e in project.trajectory.exterior_orientations}
    assert len(eos) == len(poses)
    dC = dR = 0.0
    for pose in poses:
        eo = eos[rename(pose.image_name)]
        R = rotation_from_opk(*(math.radians(a) for a in (eo.omega_deg, eo.phi_deg,
                                                          eo.kappa_deg)))
        dC = max(dC, float(np.abs(np.array([eo.X, eo.Y, eo.Z]) - pose.C_world).max()))
        dR = max(dR, rotation_error_deg(R, pose.R_cam_to_world))
    return project, dC, dR


def jpg(name):
    return Path(name).with_suffix(".jpg").name


@pytest.mark.parametrize("where", ["example, east of the meridian", "small, west of it"])
def test_dji_images_replay_the_true_poses(tmp_path, where):
    if where.startswith("example"):
        base, camera = EXAMPLE, {}
    else:
        base, camera = small_base(tmp_path, 440_000.0), SMALL_CAMERA
    project = load_project(base)
    poses = true_poses(project, base.parent)
    X, Y = poses[0].C_world[:2]
    north = float(Georef(project.crs).true_north_azimuth_deg(X, Y))
    assert abs(north) > 0.1 and (north < 0) == (X > 500_000)  # convergence matters here
    images = tmp_path / "images"
    images.mkdir()
    for pose in poses:
        write_dji_image(images / jpg(pose.image_name), pose, project.crs, **camera)
    out = tmp_path / "flown.xml"
    assert main(["import-flight", str(images), "--base", str(base), "-o", str(out)]) == 0
    new, dC, dR = compare(out, poses, jpg)
    assert dC <= 0.01 and dR <= 0.01, (dC, dR)
    assert new.render.output_format == "jpeg"
    assert new.scene == load_project(base).scene
    used = {e.camera for e in new.trajectory.exterior_orientations}
    assert used == {project.cameras[0].id}  # the base camera (its calibration kept)


def test_relative_altitude_plus_takeoff_height(tmp_path):
    base = small_base(tmp_path, 530_000.0)
    project = load_project(base)
    poses = true_poses(project, base.parent)
    hf = build_heightfield(project.scene.terrain, base.parent)
    takeoff = float(hf.height_at_clamped(*poses[0].C_world[:2]))
    images = tmp_path / "images"
    images.mkdir()
    for pose in poses:
        write_dji_image(images / jpg(pose.image_name), pose, project.crs,
                        takeoff_Z=takeoff, absolute_error_m=30.0, **SMALL_CAMERA)
    out = tmp_path / "flown.xml"
    assert main(["import-flight", str(images), "--base", str(base), "-o", str(out),
                 "--altitude", "relative"]) == 0
    _, dC, dR = compare(out, poses, jpg)
    assert dC <= 0.01 and dR <= 0.01
    absolute = tmp_path / "absolute.xml"  # the drifted absolute heights, less 30 m
    assert main(["import-flight", str(images), "--base", str(base), "-o", str(absolute),
                 "--height-offset-m", "-30"]) == 0
    _, dC, _ = compare(absolute, poses, jpg)
    assert dC <= 0.01
    shifted = tmp_path / "shifted.xml"  # --height: the former name, kept for scripts
    assert main(["import-flight", str(images), "--base", str(base), "-o", str(shifted),
                 "--height", "relative", "--takeoff-height-m", str(takeoff + 2.0)]) == 0
    eos = load_project(shifted).trajectory.exterior_orientations
    assert eos[0].Z == pytest.approx(poses[0].C_world[2] + 2.0, abs=0.01)


def test_a_preset_camera_named_by_the_metadata_replaces_the_base_camera(tmp_path):
    base = small_base(tmp_path, 470_000.0)
    project = load_project(base)
    poses = true_poses(project, base.parent)[:3]
    images = tmp_path / "images"
    images.mkdir()
    for pose in poses:
        write_dji_image(images / jpg(pose.image_name), pose, project.crs, model="M3E",
                        focal_mm=12.29, size_px=(5280, 3956))
    out = tmp_path / "flown.xml"
    assert main(["import-flight", str(images), "--base", str(base), "-o", str(out)]) == 0
    new, dC, dR = compare(out, poses, jpg)
    assert dC <= 0.01 and dR <= 0.01
    cam = new.camera(new.trajectory.exterior_orientations[0].camera)
    assert (cam.id, cam.focal_length_mm, cam.image_width_px) == ("m3e", 12.29, 5280)


def test_geo_txt_replays_the_poses(tmp_path):
    base = small_base(tmp_path, 560_000.0)
    project = load_project(base)
    poses = true_poses(project, base.parent)
    geo = tmp_path / "geo.txt"
    geo.write_text(odm_geo_text(poses, project.crs))
    out = tmp_path / "flown.xml"
    assert main(["import-flight", str(geo), "--base", str(base), "-o", str(out)]) == 0
    _, dC, dR = compare(out, poses)
    assert dC <= 1e-6 and dR <= 1e-6  # same CRS, exact numbers: only rounding


def test_geo_txt_in_wgs84_with_true_north_angles(tmp_path):
    base = small_base(tmp_path, 440_000.0)
    project = load_project(base)
    poses = true_poses(project, base.parent)
    from pyproj import Transformer

    to_ll = Transformer.from_crs(project.crs, "EPSG:4326", always_xy=True)
    rows = ["EPSG:4326"]
    for pose in poses:
        X, Y, Z = pose.C_world
        lon, lat = to_ll.transform(X, Y)
        # ODM's angles from true north: the pose turned into a true-north frame, written
        # by the project's own geo.txt convention
        a = math.radians(grid_azimuth_of_true_north_deg(project.crs, X, Y))
        Rz = np.array([[math.cos(a), -math.sin(a), 0], [math.sin(a), math.cos(a), 0],
                       [0, 0, 1]])
        yaw, pitch, roll = odm_ypr_deg_from_rotation(Rz @ pose.R_cam_to_world)
        rows.append(f"{pose.image_name} {lon!r} {lat!r} {Z!r} {yaw!r} {pitch!r} {roll!r}")
    geo = tmp_path / "geo.txt"
    geo.write_text("\n".join(rows) + "\n")
    out = tmp_path / "flown.xml"
    assert main(["import-flight", str(geo), "--base", str(base), "-o", str(out)]) == 0
    _, dC, dR = compare(out, poses)
    assert dC <= 0.01 and dR <= 0.01


def test_metashape_csv_and_a_lonlat_gimbal_csv(tmp_path):
    base = small_base(tmp_path, 440_000.0)
    project = load_project(base)
    poses = true_poses(project, base.parent)
    csv_path = tmp_path / "cameras.csv"
    csv_path.write_text(metashape_cameras_csv(poses, project.crs))
    out = tmp_path / "a.xml"
    assert main(["import-flight", str(csv_path), "--base", str(base), "-o", str(out)]) == 0
    _, dC, dR = compare(out, poses)
    assert dC <= 1e-6 and dR <= 1e-6

    from pyproj import Transformer

    to_ll = Transformer.from_crs(project.crs, "EPSG:4326", always_xy=True)
    rows = ["Name;Latitude;Longitude;Altitude;GimbalYawDegree;GimbalPitchDegree;"
            "GimbalRollDegree"]
    for pose in poses:
        X, Y, Z = pose.C_world
        lon, lat = to_ll.transform(X, Y)
        yaw, pitch, roll = dji_angles_deg(pose.R_cam_to_world, project.crs, X, Y)
        rows.append(";".join(str(v) for v in (pose.image_name, lat, lon, Z, yaw, pitch, roll)))
    semi = tmp_path / "gimbal.csv"
    semi.write_text("\n".join(rows) + "\n")
    out2 = tmp_path / "b.xml"
    assert main(["import-flight", str(semi), "--base", str(base), "-o", str(out2)]) == 0
    _, dC, dR = compare(out2, poses)
    assert dC <= 0.01 and dR <= 0.01


def test_a_projected_csv_in_another_zone(tmp_path):
    base = small_base(tmp_path, 700_000.0)  # far east in zone 32: zone 33 differs a lot
    project = load_project(base)
    poses = true_poses(project, base.parent)
    from pyproj import Transformer

    from designer.core.truth import CameraPose

    t = Transformer.from_crs(project.crs, "EPSG:32633", always_xy=True)
    moved = []
    for pose in poses:
        X, Y, Z = pose.C_world
        x, y = t.transform(X, Y)
        # the same camera seen in zone 33's grid: azimuths grow by the convergence
        # difference, a clockwise turn
        d = -math.radians(float(Georef("EPSG:32633").true_north_azimuth_deg(x, y))
                         - float(Georef(project.crs).true_north_azimuth_deg(X, Y)))
        Rz = np.array([[math.cos(d), -math.sin(d), 0], [math.sin(d), math.cos(d), 0],
                       [0, 0, 1]])
        moved.append(CameraPose(pose.image_name, np.array([x, y, Z]), Rz @ pose.R_cam_to_world))
    csv_path = tmp_path / "z33.csv"
    csv_path.write_text(metashape_cameras_csv(moved, "EPSG:32633"))
    out = tmp_path / "z33.xml"
    assert main(["import-flight", str(csv_path), "--base", str(base), "-o", str(out),
                 "--csv-crs", "EPSG:32633"]) == 0
    _, dC, dR = compare(out, poses)
    assert dC <= 0.01 and dR <= 0.01


# ------------------------------------------------------------------------- bad input
def _one_pose_images(tmp_path, **options):
    base = small_base(tmp_path, 440_000.0)
    project = load_project(base)
    pose = true_poses(project, base.parent)[0]
    images = tmp_path / "images"
    images.mkdir()
    write_dji_image(images / "A.jpg", pose, project.crs, **{**SMALL_CAMERA, **options})
    return base, images


@pytest.mark.parametrize(("options", "fragments"), [
    ({"gps": False}, ["A.jpg", "GPSLatitude", "geo.txt"]),
    ({"gimbal": False}, ["A.jpg", "GimbalYawDegree"]),
    ({"model": "Mystery 9", "focal_mm": 24.0, "size_px": (4000, 3000)},
     ["unknown camera", "Mystery 9", "24 mm", "4000 x 3000"]),
])
def test_bad_images_give_one_clean_error(tmp_path, capsys, options, fragments):
    base, images = _one_pose_images(tmp_path, **options)
    out = tmp_path / "new.xml"
    assert main(["import-flight", str(images), "--base", str(base), "-o", str(out)]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and all(f in err for f in fragments), err
    assert not out.exists()


@pytest.mark.parametrize(("text", "fragments"), [
    ("Label,X,Y,Omega,Phi,Kappa\nA,1,2,0,0,0\n", ["bad.csv:1", "Z/Altitude", "no column for z"]),
    ("Label,X,Y,Z\nA,1,2,3\n", ["camera angles"]),
    ("Label,X,Y,Z,Omega,Phi,Kappa\nA,1,two,3,0,0,0\n", ["bad.csv:2", "'two'"]),
])
def test_bad_csv_gives_one_clean_error(tmp_path, capsys, text, fragments):
    base = small_base(tmp_path, 440_000.0)
    bad = tmp_path / "bad.csv"
    bad.write_text(text)
    out = tmp_path / "new.xml"
    assert main(["import-flight", str(bad), "--base", str(base), "-o", str(out)]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and all(f in err for f in fragments), err
    assert not out.exists()


def test_bad_geo_txt_names_the_line(tmp_path, capsys):
    base = small_base(tmp_path, 440_000.0)
    geo = tmp_path / "geo.txt"
    geo.write_text("EPSG:32632\nA.jpg 440000 5000000 280 0 0 0\nB.jpg 440010 5000000\n")
    out = tmp_path / "new.xml"
    assert main(["import-flight", str(geo), "--base", str(base), "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert "geo.txt:3" in err and "yaw pitch roll" in err
    assert not out.exists()
