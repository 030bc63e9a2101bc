"""``designer new PROJECT.xml --site DEM.tif --orthophoto ORTHO.tif``: a project for a real
site, its CRS, origin and extent taken from the files."""

import os
import re
from pathlib import Path

import numpy as np
import pytest

from designer.cli.main import main
from designer.project import load_project
from designer.scene import sample_site as site
from designer.scene.build import build_scene

UTM33 = "EPSG:32633 (WGS 84 / UTM zone 33N)"


def test_site_project_takes_crs_origin_and_extent_from_the_files(sample_site, tmp_path, capsys):
    path = tmp_path / "sub" / "site.xml"
    assert main(["new", str(path), "--site", str(sample_site["dem"]),
                 "--orthophoto", str(sample_site["orthophoto"])]) == 0
    assert "EPSG:32633" in capsys.readouterr().out
    project = load_project(path)  # schema + semantic checks, files included
    assert project.crs == UTM33
    e = project.scene.terrain.extent
    # The overlap: west and north edges from the orthophoto, east and south from the DEM's
    # nodes (cell centres, half a cell inside its outer edge), rounded inwards to 0.1 m.
    dem_east = site.DEM_WEST + (site.DEM_COLS - 0.5) * site.DEM_CELL_M
    dem_south = site.DEM_NORTH - (site.DEM_ROWS - 0.5) * site.DEM_CELL_M
    assert (e.min_X, e.max_Y) == (np.ceil(site.ORTHO_WEST * 10) / 10,
                                  np.floor(site.ORTHO_NORTH * 10) / 10)
    assert (e.max_X, e.min_Y) == (np.floor(dem_east * 10) / 10, np.ceil(dem_south * 10) / 10)
    assert project.origin.E0 == round((e.min_X + e.max_X) / 2)
    assert project.origin.N0 == round((e.min_Y + e.max_Y) / 2)
    # H0: the median DEM height over the extent.
    E, N = np.meshgrid(np.arange(e.min_X, e.max_X, 0.5), np.arange(e.min_Y, e.max_Y, 0.5))
    assert abs(project.origin.H0 - np.median(site.height_m(E, N))) < 0.1
    # Files are referenced relative to the project's folder.
    assert project.scene.terrain.source.file == Path(
        os.path.relpath(sample_site["dem"], path.parent)).as_posix()
    assert not Path(project.scene.terrain.source.file).is_absolute()
    assert all(e.contains(t.true.X, t.true.Y) for t in project.targets)
    plan = project.trajectory.flight_plan
    assert plan.gsd_m == pytest.approx(2 * site.ORTHO_PIXEL_M * project.render.resolution_scale)
    assert all(e.contains(x, y) for x, y in plan.area)


def test_site_from_a_geographic_dem_goes_to_its_utm_zone(sample_site, tmp_path):
    path = tmp_path / "geo.xml"
    assert main(["new", "-o", str(path), "--site", str(sample_site["dem_wgs84"])]) == 0
    project = load_project(path)
    assert project.crs == UTM33
    scene = build_scene(project, tmp_path)
    # The reprojected terrain is the sample terrain, in UTM metres.
    X, Y, Z = scene.terrain.vertices_world[::997].T
    ground = site.height_m(X, Y)
    smooth = np.abs(np.abs(site.road_offset_m(X, Y)) - 5.25) > 2.5
    assert np.median(np.abs(Z - ground)[smooth]) < 0.01


def test_site_orthophoto_uv_follows_its_geotransform(sample_site, tmp_path):
    path = tmp_path / "site.xml"
    main(["new", str(path), "--site", str(sample_site["dem"]),
          "--orthophoto", str(sample_site["orthophoto"])])
    scene = build_scene(load_project(path), tmp_path)
    H, W = scene.texture_rgb.shape[:2]
    uv = scene.texture_uv
    XY = scene.terrain.vertices_world[:, :2]
    # Moving 3 cm (one orthophoto pixel) east moves u by one texel, whatever the DEM grid.
    k = np.argsort(XY[:, 0])[[0, -1]]
    du_per_m = (uv[k[1], 0] - uv[k[0], 0]) / (XY[k[1], 0] - XY[k[0], 0])
    assert du_per_m * W * site.ORTHO_PIXEL_M == pytest.approx(1.0, abs=1e-9)
    # Each cross's texel, looked up through the vertex uv interpolation, is bright.
    for E, N in site.CROSSES_EN:
        i = np.argmin(np.hypot(XY[:, 0] - E, XY[:, 1] - N))
        u = uv[i, 0] + (E - XY[i, 0]) * du_per_m
        v = uv[i, 1] + (N - XY[i, 1]) * du_per_m * W / H
        assert scene.texture_rgb[int((1 - v) * H), int(u * W)].mean() > 200


@pytest.mark.parametrize(("args", "message"), [
    (["--orthophoto", "ORTHO"], "--orthophoto needs --site"),
    (["--template", "survey", "--site", "DEM"], "either --template or --site"),
    (["-o", "B", "--site", "DEM"], "give the project file once"),
    (["--site", "NOPE"], r"nope\.tif does not exist"),
])
def test_site_errors(sample_site, tmp_path, capsys, args, message):
    names = {"ORTHO": str(sample_site["orthophoto"]), "DEM": str(sample_site["dem"]),
             "B": str(tmp_path / "b.xml"), "NOPE": str(tmp_path / "nope.tif")}
    assert main(["new", str(tmp_path / "a.xml"), *[names.get(a, a) for a in args]]) == 2
    err = capsys.readouterr().err
    assert re.search(message, err) and err.count("\n") == 1, err
    assert not (tmp_path / "a.xml").exists() and not (tmp_path / "b.xml").exists()
