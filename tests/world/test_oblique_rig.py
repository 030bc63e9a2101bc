"""Oblique capture: a nadir + four 45° oblique rig, each camera with its own interior.

Checked on a real Cycles render of tiny images (160-200 px wide, three sizes and three
focal lengths in one job): every exported format reprojects every GCP in every camera
(pycolmap on the COLMAP model, Metashape's own projection formula on its sensors and
reference angles, ODM's pixel shift and camera models), the rendered target centres sit
at the exported pixels within the project's exact-render tolerance, and COLMAP 3.8's
command line reads the multi-camera model. Bad rigs give located one-line errors.
"""

from __future__ import annotations

import json
import re
import shutil
import subprocess
from dataclasses import replace
from pathlib import Path

import cv2
import numpy as np
import pytest
from lxml import etree

from designer.core.rotation import rotation_from_opk
from designer.export.colmap_read import model_offset_world
from designer.export.tables import (
    read_gcp_observations_csv,
    read_gcp_truth_csv,
    read_image_cameras_csv,
    read_opk_csv,
)
from designer.project import load_project
from designer.project import model as m
from designer.render.job_spec import RenderJob
from designer.render.pipeline import render_project
from designer.survey.project_poses import project_images, project_stations
from tests.render.helpers import detect_centres
from tests.synthetic import (
    PENTA_MOUNTS,
    assert_located_error,
    rig_survey,
    small_survey,
    write_project_file,
)

CAMERAS = {c[0]: c for c in PENTA_MOUNTS}
N_STATIONS = 12


# ------------------------------------------------------------------ model, no render
def test_each_station_yields_one_image_per_mount_with_the_composed_rotation():
    project = rig_survey()
    images = project_images(project, None)
    stations = project.trajectory.exterior_orientations
    assert len(images.stations) == len(stations) * len(PENTA_MOUNTS)
    for k, st in enumerate(images.stations):
        eo = stations[images.station_index[k]]
        cam_id, suffix, omega, phi, kappa, *_ = PENTA_MOUNTS[k % len(PENTA_MOUNTS)]
        assert st.image_name == eo.name.replace(".png", f"{suffix}.png")
        assert images.camera_ids[k] == cam_id
        R_platform = rotation_from_opk(*np.radians([eo.omega_deg, eo.phi_deg, eo.kappa_deg]))
        R_mount = rotation_from_opk(*np.radians([omega, phi, kappa]))
        assert np.allclose(st.R_cam_to_world, R_platform @ R_mount, atol=1e-15)
        assert np.array_equal(st.C_world, [eo.X, eo.Y, eo.Z])
    # an oblique mount looks 45° off the platform's axis, the nadir one along it
    axes = [st.R_cam_to_world[:, 2] for st in images.stations[:5]]
    platform_axis = images.platform[0].R_cam_to_world[:, 2]
    tilts = [np.degrees(np.arccos(np.clip(a @ platform_axis, -1, 1))) for a in axes]
    assert np.allclose(tilts, [0, 45, 45, 45, 45], atol=1e-6)  # arccos near 1


def test_a_flight_plan_flown_with_a_rig_names_every_mount(tmp_path):
    project = rig_survey()
    plan = m.FlightPlan(camera="penta", image_prefix="R_", altitude_agl_m=12.0,
                        altitude_reference=250.0,
                        area=((499990.0, 4999990.0), (500010.0, 4999990.0),
                              (500010.0, 5000010.0), (499990.0, 5000010.0)))
    project = replace(project, trajectory=replace(project.trajectory, flight_plan=plan,
                                                  exterior_orientations=()))
    path = write_project_file(project, tmp_path)
    loaded = load_project(path)
    assert loaded == project
    platform, camera_id = project_stations(loaded, None)
    assert camera_id == "nadir"  # the plan's spacing is the nadir camera's
    images = project_images(loaded, None)
    assert len(images.stations) == 5 * len(platform)
    assert images.stations[1].image_name == "R_00001_F.png"


def test_a_project_without_a_rig_has_exactly_its_stations_and_no_frame_cameras(tmp_path):
    from designer.render.job import prepare_job

    project = small_survey(n_photos=3)
    images = project_images(project, None)
    stations, camera_id = project_stations(project, None)
    assert [s.image_name for s in images.stations] == [s.image_name for s in stations]
    assert set(images.camera_ids) == {camera_id} and not images.is_multi_camera
    prepared = prepare_job(project, tmp_path, tmp_path / "out")
    text = prepared.job_path.read_text()
    assert '"camera": {' in text and text.count('"lens_mm"') == 1  # the job's camera only
    assert prepared.cameras is None


@pytest.mark.parametrize(("edit", "needle", "words"), [
    (lambda t: t.replace('camera="fwd" suffix', 'camera="tele" suffix'), 'camera="tele"',
     "camera 'tele' of rig 'penta' is not defined"),
    (lambda t: t.replace('suffix="_B"', 'suffix="_F"'), 'camera="back"',
     "suffix '_F' is used by 2 mounts"),
    (lambda t: re.sub(r'(camera="left" suffix="_L" omega=")[^"]*"', r'\g<1>200"', t),
     'camera="left"', "omega"),
    (lambda t: re.sub(r'(camera="left" suffix="_L" omega=")[^"]*"', r'\g<1>120"', t),
     'camera="left"', "degrees away from the platform's axis"),
    (lambda t: t.replace('<rig name="penta"', '<rig name="nadir"'), '<rig name="nadir"',
     "rig name 'nadir' is also a camera id"),
    (lambda t: t.replace('camera="penta"', 'camera="pent"', 1), 'camera="pent"',
     "use the id of a camera or rig"),
])
def test_bad_rigs_are_located_one_line_errors(tmp_path, edit, needle, words):
    assert_located_error(rig_survey(), tmp_path, edit, needle, words)


# ------------------------------------------------------------------ real render
@pytest.fixture(scope="module")
def rendered(tmp_path_factory):
    folder = tmp_path_factory.mktemp("rig")
    # 12 stations x 5 mounts: ~40 target centres away from the borders (~25 s)
    path = write_project_file(rig_survey(n_stations=N_STATIONS), folder)
    return render_project(path, folder / "out", workers=1)




def _observations_by_camera(summary):
    cameras = read_image_cameras_csv(summary.ground_truth["opk"])
    obs = read_gcp_observations_csv(summary.ground_truth["gcp_observations"])
    by_camera: dict[str, list] = {}
    for o in obs:
        by_camera.setdefault(cameras[o.image_name], []).append(o)
    return cameras, by_camera


@pytest.mark.blender
@pytest.mark.slow
def test_every_image_is_rendered_with_its_mounts_camera(rendered):
    cameras = read_image_cameras_csv(rendered.ground_truth["opk"])
    assert len(cameras) == N_STATIONS * 5 and set(cameras.values()) == set(CAMERAS)
    for name, cam_id in cameras.items():
        image = cv2.imread(str(rendered.images_dir / name))
        assert image.shape[1::-1] == CAMERAS[cam_id][5], name
    job = RenderJob.read(rendered.prepared.job_path)
    assert len({f.camera.lens_mm for f in job.frames}) == 3


@pytest.mark.blender
@pytest.mark.slow
def test_colmap_model_reprojects_every_gcp_in_every_camera(rendered):
    pycolmap = pytest.importorskip("pycolmap")
    folder = rendered.ground_truth["colmap"]
    rec = pycolmap.Reconstruction(str(folder))
    assert len(rec.cameras) == len(PENTA_MOUNTS)
    offset = model_offset_world(folder)
    truth = {g.gcp_id: g.true_xyz - offset
             for g in read_gcp_truth_csv(rendered.ground_truth["gcp_truth"])}
    _, by_camera = _observations_by_camera(rendered)
    assert set(by_camera) == set(CAMERAS), "every camera sees a GCP"
    worst = 0.0
    for cam_id, rows in by_camera.items():
        for o in rows:
            image = rec.find_image_with_name(o.image_name)
            camera = rec.cameras[image.camera_id]
            assert (camera.width, camera.height) == CAMERAS[cam_id][5]
            worst = max(worst, float(np.abs(image.project_point(truth[o.gcp_id])
                                            - o.uv_px).max()))
    assert worst < 1e-6, worst


def _metashape_project(sensor: etree._Element, R: np.ndarray, C: np.ndarray,
                       X: np.ndarray) -> np.ndarray:
    """Metashape's frame projection (no distortion): CV frame, u = W/2 + cx + x f."""
    calib = sensor.find("calibration")
    W, H = (int(calib.find("resolution").get(k)) for k in ("width", "height"))
    f, cx, cy = (float(calib.find(k).text) for k in ("f", "cx", "cy"))
    x_cv = np.diag([1.0, -1.0, -1.0]) @ R.T @ (X - C)
    return np.array([W / 2 + cx + f * x_cv[0] / x_cv[2], H / 2 + cy + f * x_cv[1] / x_cv[2]])


@pytest.mark.blender
@pytest.mark.slow
def test_metashape_and_odm_carry_every_camera(rendered):
    gt = rendered.ground_truth
    cameras, by_camera = _observations_by_camera(rendered)
    doc = etree.parse(str(gt["metashape_markers_xml"]))
    sensors = {s.get("id"): s for s in doc.iter("sensor")}
    assert sorted(s.get("label") for s in sensors.values()) == sorted(CAMERAS)
    image_sensor = {c.get("label"): sensors[c.get("sensor_id")] for c in doc.iter("camera")}
    poses = {p.image_name: p for p in read_opk_csv(gt["opk"])}
    truth = {g.gcp_id: g.true_xyz for g in read_gcp_truth_csv(gt["gcp_truth"])}
    for rows in by_camera.values():
        for o in rows:
            sensor = image_sensor[Path(o.image_name).stem]  # Metashape's camera label
            assert sensor.get("label") == cameras[o.image_name]
            pose = poses[o.image_name]
            uv = _metashape_project(sensor, pose.R_cam_to_world, pose.C_world,
                                    truth[o.gcp_id])
            assert np.abs(uv - o.uv_px).max() < 1e-6
    for cam_id in CAMERAS:  # each sensor's calibration file, as Metashape loads it
        calib = etree.parse(str(gt[f"metashape_calibration_{cam_id}"])).getroot()
        assert (int(calib.find("width").text), int(calib.find("height").text)) == \
            CAMERAS[cam_id][5]
    models = json.loads(gt["odm_cameras"].read_text())
    for cam_id, (_, _, _, _, _, (W, H), f_mm, (x0, _)) in CAMERAS.items():
        model = models[cam_id]
        assert (model["width"], model["height"]) == (W, H)
        assert model["focal_x"] * max(W, H) == pytest.approx(f_mm / 0.01)
        assert model["c_x"] * max(W, H) == pytest.approx(x0 / 0.01)
    readme = (rendered.out_dir / "README.txt").read_text()
    assert "5 cameras (nadir 200 x 150 px, fwd 160 x 120 px" in readme
    assert "ground-truth/odm/cameras.json" in readme.split("Agisoft")[0]
    for cam_id in CAMERAS:
        assert f"calibration {cam_id}:" in readme.split("Tables")[0]
    obs = {(o.gcp_id, o.image_name): o.uv_px
           for o in read_gcp_observations_csv(gt["gcp_observations"])}
    for line in gt["odm_gcp_list"].read_text().splitlines()[1:]:
        _, _, _, u, v, image_name, gcp_id = line.split()[:7]
        assert np.allclose(obs[gcp_id, image_name], [float(u) + 0.5, float(v) + 0.5],
                           atol=1e-9)


@pytest.mark.blender
@pytest.mark.slow
def test_rendered_targets_sit_at_the_exported_pixels_in_every_camera(rendered):
    _, by_camera = _observations_by_camera(rendered)
    rng = np.random.default_rng(0)
    pooled = []
    for cam_id, rows in sorted(by_camera.items()):
        W, H = CAMERAS[cam_id][5]
        errors = []
        for o in rows:
            u, v = o.uv_px
            if not (12 < u < W - 12 and 12 < v < H - 12):
                continue
            gray = cv2.imread(str(rendered.images_dir / o.image_name), cv2.IMREAD_GRAYSCALE)
            errors.append(detect_centres(gray, np.array([o.uv_px]), rng)[0] - o.uv_px)
        d = np.array(errors)
        assert len(d) >= 5, f"{cam_id}: only {len(d)} targets away from the border"
        mean, rms = d.mean(axis=0), np.sqrt((d ** 2).mean(axis=0))
        print(f"{cam_id}: {len(d)} centres, mean {mean} px, RMS {rms} px")
        # a wrong interior or mounting rotation moves every centre by >= 0.5 px; with
        # 5-10 centres of ~0.07 px scatter, 0.06 px is twice the mean's standard error
        assert np.all(np.abs(mean) <= 0.06) and np.all(rms <= 0.15), (cam_id, mean, rms)
        pooled.append(d)
    d = np.concatenate(pooled)
    mean, rms = d.mean(axis=0), np.sqrt((d ** 2).mean(axis=0))
    print(f"all cameras: {len(d)} centres, mean {mean} px, RMS {rms} px")
    # the exact-render tolerance of tests/render/test_render_accuracy.py: mean 0.02 px,
    # RMS 0.1 px over >= 12 centres
    assert len(d) >= 30 and np.all(np.abs(mean) <= 0.02) and np.all(rms <= 0.1), (mean, rms)


@pytest.mark.blender
@pytest.mark.slow
@pytest.mark.skipif(shutil.which("colmap") is None,
                    reason="the colmap command line is not installed (Debian package colmap)")
def test_colmap_command_line_reads_the_multi_camera_model(rendered):
    run = subprocess.run(["colmap", "model_analyzer", "--path",
                          str(rendered.ground_truth["colmap"])],
                         capture_output=True, text=True, timeout=300,
                         env={"GLOG_logtostderr": "1", "PATH": "/usr/bin:/bin",
                              "QT_QPA_PLATFORM": "offscreen"})
    output = run.stdout + run.stderr
    assert run.returncode == 0, output
    assert re.search(r"Cameras:\s*5\b", output), output
    assert re.search(rf"Images:\s*{N_STATIONS * 5}\b", output), output


@pytest.mark.blender
@pytest.mark.slow
def test_a_rig_with_lens_distortion_and_effects_warps_each_camera_by_its_own_lens(tmp_path):
    pycolmap = pytest.importorskip("pycolmap")
    project = rig_survey(n_stations=5)
    distorted = {"fwd": m.BrownConradyDistortion(k1=-0.15, k2=0.02),
                 "left": m.BrownConradyDistortion(k1=0.1, p1=0.002)}
    project = replace(project, cameras=tuple(
        replace(c, distortion=distorted.get(c.id)) for c in project.cameras),
        effects=m.Effects(vignetting=m.Vignetting(corner_falloff=0.2)))
    # only the distorted cameras' images are measured: only they are rendered (the job,
    # its warps and the ground truth are the whole rig's)
    frames = ",".join(str(k) for k, cam_id in enumerate(project_images(project, None)
                                                        .camera_ids) if cam_id in distorted)
    summary = render_project(write_project_file(project, tmp_path), tmp_path / "out",
                             workers=1, frames=frames)
    job = RenderJob.read(summary.prepared.job_path)
    assert sorted(c for c, w in job.effects.cameras.items() if w.warp) == sorted(distorted)
    _, by_camera = _observations_by_camera(summary)
    rec = pycolmap.Reconstruction(str(summary.ground_truth["colmap"]))
    offset = model_offset_world(summary.ground_truth["colmap"])
    truth = {g.gcp_id: g.true_xyz
             for g in read_gcp_truth_csv(summary.ground_truth["gcp_truth"])}
    rng = np.random.default_rng(1)
    for cam_id in distorted:
        assert rec.cameras[rec.find_image_with_name(by_camera[cam_id][0].image_name)
                           .camera_id].model.name == "OPENCV"
        errors = []
        for o in by_camera[cam_id]:
            image = rec.find_image_with_name(o.image_name)
            assert np.abs(image.project_point(truth[o.gcp_id] - offset) - o.uv_px).max() < 1e-6
            W, H = CAMERAS[cam_id][5]
            if 12 < o.uv_px[0] < W - 12 and 12 < o.uv_px[1] < H - 12:
                gray = cv2.imread(str(summary.images_dir / o.image_name), cv2.IMREAD_GRAYSCALE)
                assert gray.shape[::-1] == (W, H)
                errors.append(detect_centres(gray, np.array([o.uv_px]), rng)[0] - o.uv_px)
        # an undistorted render, or another camera's warp, misplaces them by pixels
        assert errors and np.abs(errors).max() < 0.3, (cam_id, errors)


@pytest.mark.blender
@pytest.mark.slow
def test_a_rendered_rig_folder_is_up_to_date_and_a_turned_mount_makes_its_images_stale(
        rendered, tmp_path):
    from designer.render.check_output import check_output

    project_path = rendered.out_dir.parent / "project.xml"
    status = check_output(rendered.out_dir, project_path)
    assert status.ok, status.summary()
    assert len(status.up_to_date) == N_STATIONS * 5
    project = load_project(project_path)
    rig = project.trajectory.rigs[0]
    turned = replace(rig, mounts=tuple(replace(mt, phi_deg=40.0) if mt.suffix == "_L" else mt
                                       for mt in rig.mounts))
    changed = replace(project, trajectory=replace(project.trajectory, rigs=(turned,)))
    status = check_output(rendered.out_dir, project_path, project=changed)
    # the turned mount's images are stale by their pose; the others only where the turn
    # grew the surroundings (the scene: terrain, bake and light map reach further), never
    # by their pose
    left = sorted(n for n in status.stale if n.endswith("_L.png"))
    assert len(left) == N_STATIONS and all("pose" in status.stale[n] for n in left)
    assert all("pose" not in parts for n, parts in status.stale.items()
               if not n.endswith("_L.png")), status.stale
    assert status.ground_truth.startswith("out of date")
