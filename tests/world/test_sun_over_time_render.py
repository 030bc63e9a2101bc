"""The sun over time on real Cycles renders: shadows move with each photo's time, a frame
lit by a light step equals a render of a fixed sun, the times reach EXIF and the ground
truth, and a project without these elements renders byte for byte as before."""

from __future__ import annotations

import datetime as _dt
import math
import shutil
from dataclasses import replace
from pathlib import Path

import cv2
import numpy as np
import pytest
from astral import Observer
from astral.sun import azimuth, elevation
from pyproj import CRS, Proj, Transformer

from designer.export.tables import OPK_COLUMNS, read_image_times_csv
from designer.project import model as m
from designer.render.exif import read_time
from designer.render.pipeline import render_project
from tests.synthetic import write_project_file
from tests.world.helpers import ORIGIN, TAKEOFF, timed_survey

BLOCK_M, BLOCK_HEIGHT_M, CELL_M = 2.0, 3.0, 0.1


def _block_dem(folder: Path) -> str:
    """A flat 40 x 40 m DEM at H0 with a 2 x 2 m, 3 m tall block at the origin."""
    E0, N0, H0 = ORIGIN
    n = int(40 / CELL_M)
    centres = -20 + (np.arange(n) + 0.5) * CELL_M
    X, Y = np.meshgrid(centres, centres[::-1])
    Z = np.where((abs(X) <= BLOCK_M / 2) & (abs(Y) <= BLOCK_M / 2), H0 + BLOCK_HEIGHT_M, H0)
    lines = [f"ncols {n}", f"nrows {n}", f"xllcorner {E0 - 20}", f"yllcorner {N0 - 20}",
             f"cellsize {CELL_M}", "NODATA_value -9999"]
    lines += [" ".join(f"{z:g}" for z in row) for row in Z]
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "block.asc").write_text("\n".join(lines) + "\n")
    return "block.asc"


def _block_project(folder: Path, times_s) -> m.Project:
    p = timed_survey(times_s)
    E0, N0, H0 = ORIGIN
    terrain = m.Terrain(m.Extent(E0 - 19.9, N0 - 19.9, E0 + 19.9, N0 + 19.9),
                        m.DemTerrain(_block_dem(folder)))
    texture = m.Texture(m.ProceduralTexture("noise", seed=2, texel_size_m=0.02), 4, 4, "linear")
    photos = tuple(replace(eo, Z=H0 + 50.0) for eo in p.trajectory.exterior_orientations)
    return replace(p, scene=replace(p.scene, terrain=terrain, texture=texture, targets=None),
                   trajectory=replace(p.trajectory, exterior_orientations=photos),
                   render=replace(p.render, samples=4),
                   cameras=(replace(p.cameras[0], image_width_px=320, image_height_px=320,
                                    sensor_width_mm=3.2, sensor_height_mm=3.2),))


def _astral_grid_sun(moment: _dt.datetime) -> tuple[float, float]:
    """The sun at the project origin straight from astral, turned to grid north."""
    crs = CRS.from_user_input("EPSG:32632")
    lon, lat = Transformer.from_crs(crs, "EPSG:4326", always_xy=True).transform(*ORIGIN[:2])
    gamma = Proj(crs).get_factors(lon, lat).meridian_convergence
    obs = Observer(latitude=lat, longitude=lon)
    return (azimuth(obs, moment) - gamma) % 360, elevation(obs, moment)


def _shadow(image: np.ndarray) -> tuple[float, float]:
    """(grid azimuth deg, area px) of the dark patch's centroid seen from the image centre
    (nadir, kappa 0: image up = north, right = east)."""
    grey = cv2.GaussianBlur(image.astype(np.float32).mean(axis=2), (5, 5), 0)
    dark = (grey < 0.6 * np.median(grey)).astype(np.uint8)
    _, _, stats, centroids = cv2.connectedComponentsWithStats(dark)
    largest = 1 + int(np.argmax(stats[1:, cv2.CC_STAT_AREA]))  # the shadow; not texture
    h, w = grey.shape
    du, dv = centroids[largest] + 0.5 - np.array([w / 2, h / 2])
    return math.degrees(math.atan2(du, -dv)) % 360, float(stats[largest, cv2.CC_STAT_AREA])


def _header(path: Path) -> str:
    return next(line for line in path.read_text().splitlines() if not line.startswith("#"))


@pytest.fixture(scope="module")
def rendered(tmp_path_factory):
    folder = tmp_path_factory.mktemp("block")
    project = _block_project(folder, (0.0, 4 * 3600.0))
    path = write_project_file(project, folder)
    return folder, render_project(path, folder / "out")


def test_shadows_move_with_the_sun_of_each_photos_time(rendered):
    folder, _ = rendered
    takeoff = _dt.datetime.fromisoformat(TAKEOFF)
    shadows = []
    for k, t in enumerate((0.0, 4 * 3600.0)):
        az, el = _astral_grid_sun(takeoff + _dt.timedelta(seconds=t))
        image = cv2.imread(str(folder / "out" / "images" / f"IMG_{k:03d}.png"))[:, :, ::-1]
        direction, area = _shadow(image)
        # the shadow falls away from the sun
        assert abs((direction - (az + 180) + 180) % 360 - 180) < 8, (direction, az)
        shadows.append((direction, area, el))
    (d0, a0, e0), (d1, a1, e1) = shadows
    assert abs((d1 - d0 + 180) % 360 - 180) > 40  # the sun went round by ~60° in 4 h
    assert e1 > e0 and a1 < a0  # a higher sun casts a shorter shadow


def test_the_ground_truth_lists_each_images_time_and_the_sun_astral_gives(rendered):
    folder, _ = rendered
    times = read_image_times_csv(folder / "out" / "ground-truth" / "image_times.csv")
    assert [t.time_s for t in times] == [0.0, 14400.0]
    for t in times:
        moment = _dt.datetime.fromisoformat(t.time_utc)
        assert moment == _dt.datetime.fromisoformat(TAKEOFF) + _dt.timedelta(seconds=t.time_s)
        az, el = _astral_grid_sun(moment)
        assert t.sun_azimuth_deg == pytest.approx(az, abs=1e-9)
        assert t.sun_elevation_deg == pytest.approx(el, abs=1e-9)
    header = _header(folder / "out" / "ground-truth" / "camera_poses_opk.csv")
    assert header.split(",") == [*OPK_COLUMNS, "time"]


def test_a_frame_of_a_light_step_equals_a_render_under_its_sun_fixed(rendered, tmp_path):
    folder, summary = rendered
    frame = summary.prepared.job.frames[1]
    project = _block_project(tmp_path, (0.0, 4 * 3600.0))
    fixed = replace(project, scene=replace(project.scene, lighting=m.Lighting(
        m.Sun(frame.sun_azimuth_deg, frame.sun_elevation_deg))),
        trajectory=replace(project.trajectory, time_line=None, exterior_orientations=tuple(
            replace(eo, time_s=None) for eo in project.trajectory.exterior_orientations)))
    render_project(write_project_file(fixed, tmp_path), tmp_path / "out", frames="1")
    a = cv2.imread(str(folder / "out" / "images" / "IMG_001.png"))
    b = cv2.imread(str(tmp_path / "out" / "images" / "IMG_001.png"))
    assert np.array_equal(a, b)


def test_resume_renders_again_the_images_whose_time_changed(rendered, tmp_path):
    # a copy of the module's rendered folder (its project, DEM and output), resumed with
    # the second photo's time changed
    folder = tmp_path / "block"
    shutil.copytree(rendered[0], folder)
    project = _block_project(folder, (0.0, 4 * 3600.0))
    later = replace(project, trajectory=replace(project.trajectory, exterior_orientations=(
        project.trajectory.exterior_orientations[0],
        replace(project.trajectory.exterior_orientations[1], time_s=5 * 3600.0))))
    summary = render_project(write_project_file(later, folder), folder / "out", resume=True)
    assert summary.report.skipped == [0]
    assert set(summary.stale) == {1} and "scene" in summary.stale[1]


@pytest.mark.parametrize("fmt", ["jpeg", "tiff"])
def test_exif_carries_each_photos_time(tmp_path, fmt):
    project = timed_survey((0.0, 12.345678), sun_over_time=False)
    effects = m.Effects(jpeg=m.Jpeg(90)) if fmt == "jpeg" else None
    suffix = ".jpg" if fmt == "jpeg" else ".tif"
    photos = tuple(replace(eo, name=eo.name.replace(".png", suffix))
                   for eo in project.trajectory.exterior_orientations)
    project = replace(project, effects=effects,
                      render=replace(project.render, output_format=fmt, image_metadata="exif"),
                      trajectory=replace(project.trajectory, exterior_orientations=photos))
    render_project(write_project_file(project, tmp_path), tmp_path / "out")
    takeoff = _dt.datetime.fromisoformat(TAKEOFF)
    for k, t in enumerate((0.0, 12.345678)):
        moment = read_time(tmp_path / "out" / "images" / f"IMG_{k:03d}{suffix}")
        assert moment == takeoff + _dt.timedelta(seconds=t)
        assert moment.utcoffset() == _dt.timedelta(0)


def test_without_metadata_the_images_carry_no_time(tmp_path):
    project = timed_survey((0.0, 3.0), sun_over_time=False)
    photos = tuple(replace(eo, name=eo.name.replace(".png", ".tif"))
                   for eo in project.trajectory.exterior_orientations)
    project = replace(project, render=replace(project.render, output_format="tiff"),
                      trajectory=replace(project.trajectory, exterior_orientations=photos))
    render_project(write_project_file(project, tmp_path), tmp_path / "out", frames="0")
    assert read_time(tmp_path / "out" / "images" / "IMG_000.tif") is None


def test_the_static_ideal_renders_byte_for_byte_as_without_the_new_elements(tmp_path):
    """A time line with a static sun changes no pixel; without a time line no ground-truth
    file gains a column or a file."""
    static = timed_survey((0.0, 600.0), sun_over_time=False)
    bare = replace(static, trajectory=replace(static.trajectory, time_line=None,
                                              exterior_orientations=tuple(
        replace(eo, time_s=None) for eo in static.trajectory.exterior_orientations)))
    render_project(write_project_file(bare, tmp_path / "a"), tmp_path / "a" / "out")
    render_project(write_project_file(static, tmp_path / "b"), tmp_path / "b" / "out")
    for k in range(2):
        name = f"IMG_{k:03d}.png"
        assert (tmp_path / "a/out/images" / name).read_bytes() == \
            (tmp_path / "b/out/images" / name).read_bytes()
    truth = tmp_path / "a/out/ground-truth"
    assert not (truth / "image_times.csv").exists()
    assert (tmp_path / "b/out/ground-truth/image_times.csv").exists()
    assert _header(truth / "camera_poses_opk.csv").split(",") == list(OPK_COLUMNS)
