"""Real Cycles renders of the sample site: the orthophoto lands exactly where it belongs.

The sample orthophoto (designer.scene.sample_site) has survey crosses painted at known
world coordinates. Nadir-ish photos over two of them are rendered; each cross's
centroid in the image is compared with the projection of its world point through the
exact camera (designer.core.projection, the code behind the ground truth). The scene
crosses two coordinate grids (the DEM's 0.5 m cells and the orthophoto's 3 cm pixels,
with a corner off the DEM grid) and the origin is UTM-sized, so a half-texel slip in the
geotransform convention (1.5 px here) or a float32 origin would show.
"""

from __future__ import annotations

import dataclasses

import cv2
import numpy as np
import pytest

from designer.core.heightfield import Heightfield
from designer.core.projection import project_points
from designer.project import model as m
from designer.project import write_project
from designer.render.pipeline import render_project
from designer.scene import sample_site as site
from designer.survey.site_project import site_project

pytestmark = [pytest.mark.blender, pytest.mark.slow]

#: (cross index, camera offset from the cross (m), omega, phi, kappa (deg))
SHOTS = ((0, (0.12, -0.08), 0.5, -0.4, 17.0), (1, (-0.10, 0.14), -0.3, 0.6, -32.0))
ALTITUDE_M = 9.0
#: a 50 mm lens on a 13.2 mm sensor at 240 px: 1 cm GSD from 9 m (3 px per orthophoto texel)
CAMERA = m.Camera(id="cam", focal_length_mm=50.0, sensor_width_mm=13.2, sensor_height_mm=9.9,
                  image_width_px=240, image_height_px=180)


def cross_centroid_px(gray: np.ndarray, start_uv: np.ndarray) -> np.ndarray:
    """Centroid (designer pixel convention) of the bright cross inside its black square.

    Only a disc of 70 px around the estimate is used — inside the 160 px black square,
    where the background is uniformly dark — and refined three times. Each pixel counts
    by how far it is from dark to half-bright, saturating above: the arms' interiors weigh
    the same whatever the sun's shading across them, and each arm's two edges blur alike,
    so the centroid is the arms' centre lines' crossing.
    """
    img = gray.astype(np.float64)
    v, u = np.mgrid[0:img.shape[0], 0:img.shape[1]] + 0.5
    centre = np.asarray(start_uv, dtype=float)
    for _ in range(3):
        disc = (u - centre[0]) ** 2 + (v - centre[1]) ** 2 < 70.0 ** 2
        dark, bright = np.percentile(img[disc], [20, 98])
        w = np.where(disc, np.clip((img - dark) / (0.5 * (bright - dark)), 0.0, 1.0), 0.0)
        centre = np.array([(w * u).sum() / w.sum(), (w * v).sum() / w.sum()])
    return centre


def projected_cross_centroid_px(E, N, ground, pose, interior) -> np.ndarray:
    """Image-area centroid of the white cross at (E, N) draped on the terrain, through the
    exact camera: ground samples every 2 mm over the arms, each weighted by the image
    area it covers (the Jacobian of the projection). On sloped ground seen in
    perspective this differs from the projected centre by a fraction of a pixel."""
    a, w = site.CROSS_ARM_M / 2, site.CROSS_WIDTH_M / 2
    step = 0.002
    s_long = np.arange(-a + step / 2, a, step)
    s_short = np.arange(-w + step / 2, w, step)
    horizontal = np.array(np.meshgrid(s_long, s_short)).reshape(2, -1).T
    vertical = horizontal[:, ::-1]
    vertical = vertical[np.abs(vertical[:, 1]) > w]  # the centre square once
    xy = np.vstack([horizontal, vertical]) + [E, N]

    def project(dE, dN):
        X, Y = xy[:, 0] + dE, xy[:, 1] + dN
        P = np.column_stack([X, Y, ground.height_at(X, Y)])
        return project_points(P, pose.C_world, pose.R_cam_to_world, interior).uv_px[0]

    uv, d = project(0.0, 0.0), 1e-3
    du, dv = (project(d, 0.0) - uv) / d, (project(0.0, d) - uv) / d
    jacobian = np.abs(du[:, 0] * dv[:, 1] - du[:, 1] * dv[:, 0])
    return (uv * jacobian[:, None]).sum(axis=0) / jacobian.sum()


@pytest.fixture(scope="module")
def rendered(sample_site, tmp_path_factory):
    folder = tmp_path_factory.mktemp("ortho-render")
    path = folder / "site.xml"
    base = site_project(sample_site["dem"], sample_site["orthophoto"], path)
    extent = m.Extent(533036.0, 5213007.0, 533074.0, 5213020.0)
    ground = Heightfield(site.DEM_WEST + 0.25, site.DEM_NORTH - 89.75, 0.5, 0.5,
                         site.dem_heights()[::-1])
    photos = []
    for k, (i, (dx, dy), omega, phi, kappa) in enumerate(SHOTS):
        E, N = site.CROSSES_EN[i]
        photos.append(m.ExteriorOrientation(
            f"CROSS_{k}.png", CAMERA.id, E + dx, N + dy,
            float(ground.height_at(E, N)) + ALTITUDE_M, omega, phi, kappa))
    project = dataclasses.replace(
        base, cameras=(CAMERA,), effects=None,
        scene=dataclasses.replace(base.scene, terrain=dataclasses.replace(
            base.scene.terrain, extent=extent), targets=None),
        trajectory=m.Trajectory(exterior_orientations=tuple(photos)),
        render=m.Render(preset="survey", resolution_scale=1.0, workers=1),
        outputs=m.Outputs("output", ("odm", "metashape", "opk")))
    write_project(project, path)
    summary = render_project(path, folder / "out", workers=1)
    return summary, ground


def test_orthophoto_crosses_land_on_their_projection(rendered):
    summary, ground = rendered
    prepared = summary.prepared
    errors = []
    for pose, (i, *_rest) in zip(prepared.poses, SHOTS, strict=True):
        E, N = site.CROSSES_EN[i]
        P = np.array([[E, N, float(ground.height_at(E, N))]])
        uv = project_points(P, pose.C_world, pose.R_cam_to_world, prepared.interior).uv_px[0, 0]
        gray = cv2.imread(str(summary.out_dir / pose.image_name), cv2.IMREAD_GRAYSCALE)
        found = cross_centroid_px(gray, uv)
        area_centroid = projected_cross_centroid_px(E, N, ground, pose, prepared.interior)
        errors.append(found - area_centroid)
        print(f"{pose.image_name}: cross {i} centre projected at {uv.round(3)}, its image "
              f"area centroid at {area_centroid.round(3)}, found at {found.round(3)}: "
              f"error {np.round(found - area_centroid, 3)} px")
    errors = np.array(errors)
    # One orthophoto texel is 3 px here: a half-texel (pixel corner vs centre) slip is
    # 1.5 px, a texel 3 px.
    assert np.all(np.abs(errors) < 0.25), errors


def test_the_site_crs_reaches_the_ground_truth_and_the_manifest(rendered):
    import json

    summary, _ = rendered
    truth = summary.ground_truth
    assert (truth["odm_geo"].read_text().splitlines()[0]) == "EPSG:32633"
    for key in ("metashape_cameras", "opk"):
        header = [line for line in truth[key].read_text().splitlines() if line.startswith("#")]
        assert any("CRS EPSG:32633;" in line for line in header), (key, header)
    manifest = json.loads(summary.manifest.read_text())
    assert manifest["crs"] == "EPSG:32633 (WGS 84 / UTM zone 33N)"
    assert manifest["origin_world"][0] == pytest.approx(533075.0)
