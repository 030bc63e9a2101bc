"""How far the images look: the rendered terrain reaches every pixel of every image, and
``designer plan`` and ``designer check`` say when it does not."""

from __future__ import annotations

import dataclasses
import json
import subprocess
import sys
from pathlib import Path

import numpy as np

from designer.core.rotation import R_CV_FROM_PHOTO
from designer.project import model as m
from designer.project import write_project
from designer.project.interiors import render_interior
from designer.project.templates import template
from designer.scene.build import build_heightfield
from designer.survey.project_poses import project_images
from designer.survey.surroundings import image_ground


def _declared(project: m.Project):
    hf = build_heightfield(project.scene.terrain, Path("."), project.crs)
    return hf, project_images(project, hf)


def _with_surroundings(project: m.Project, mode: str) -> m.Project:
    terrain = dataclasses.replace(project.scene.terrain, surroundings=mode)
    return dataclasses.replace(project, scene=dataclasses.replace(project.scene,
                                                                  terrain=terrain))


def _independent_void(project, hf, station, k=24) -> float:
    """Share of a k × k grid of rays that miss ``hf``, by the core's half-cell march (not
    the plan's sphere tracing)."""
    interior = render_interior(project.cameras[0], project.render.resolution_scale)
    W, H = interior.image_size_px
    U, V = np.meshgrid((np.arange(k) + 0.5) * W / k, (np.arange(k) + 0.5) * H / k)
    rays = interior.rays_cv(np.column_stack([U.ravel(), V.ravel()])) @ (
        station.R_cam_to_world @ R_CV_FROM_PHOTO).T
    hits = hf.intersect_rays(np.broadcast_to(station.C_world, rays.shape), rays)
    return float(np.mean(~np.isfinite(hits[:, 0])))


def test_the_example_sees_ground_in_every_pixel_and_would_not_without_surroundings():
    project = template("survey").project
    hf, images = _declared(project)
    auto = image_ground(project, hf, images)
    assert auto.void_share.max() == 0.0
    assert auto.warning(project) is None
    x0, x1, y0, y1 = auto.rendered.extent_m
    assert x0 < 511950 - 40 and x1 > 512050 + 40 and y0 < 5405950 - 35 and y1 > 5406050 + 35
    # an independent march over the rendered terrain agrees for the corner images
    worst_without = {"DJI_00001.png", "DJI_00013.png", "DJI_00048.png", "DJI_00060.png"}
    for st in images.stations:
        if st.image_name in worst_without:
            assert _independent_void(project, auto.rendered, st) == 0.0, st.image_name
    none = _with_surroundings(project, "none")
    bare = image_ground(none, hf, images)
    assert bare.rendered is hf
    assert (bare.void_share > 0.01).sum() >= 50
    k = bare.names.index("DJI_00060.png")
    assert abs(bare.void_share[k] - _independent_void(none, hf, images.stations[k])) < 0.05
    warning = bare.warning(none)
    assert warning.startswith(f"{(bare.void_share > 0.01).sum()} of 60 images see past the "
                              "terrain")
    assert "set the terrain's surroundings mode to auto" in warning


def _dem_site(tmp_path: Path, mode: str | None) -> Path:
    """The example flown over its own heights written as an ESRI ASCII DEM."""
    project = template("survey").project
    hf = build_heightfield(project.scene.terrain, Path("."), project.crs)
    ny, nx = hf.heights_m.shape
    rows = "\n".join(" ".join(f"{z:.4f}" for z in row) for row in hf.heights_m[::-1])
    (tmp_path / "dem.asc").write_text(
        f"ncols {nx}\nnrows {ny}\nxllcenter {hf.x0_m}\nyllcenter {hf.y0_m}\n"
        f"cellsize {hf.dx_m}\n{rows}\n")
    terrain = m.Terrain(project.scene.terrain.extent, m.DemTerrain("dem.asc"), mode)
    site = dataclasses.replace(project, scene=dataclasses.replace(project.scene,
                                                                  terrain=terrain))
    path = tmp_path / f"site-{mode}.xml"
    write_project(site, path)
    return path


def _designer(*args) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "designer", *map(str, args)],
                          capture_output=True, text=True, timeout=300)


def test_check_warns_on_a_dem_site_flown_past_its_edge_without_surroundings(tmp_path):
    bare = _designer("check", _dem_site(tmp_path, None))
    assert bare.returncode == 0, bare.stderr
    (line,) = [ln for ln in bare.stderr.splitlines() if ln.startswith("warning:")]
    assert "<terrain>:" in line and "images see past the terrain" in line
    assert "DJI_00001.png" in line and "set the terrain's surroundings mode to auto" in line
    auto = _designer("check", _dem_site(tmp_path, "auto"))
    assert auto.returncode == 0 and "warning" not in auto.stderr, auto.stderr


def test_plan_json_gives_every_images_void_share(tmp_path):
    path = tmp_path / "none.xml"
    write_project(_with_surroundings(template("survey").project, "none"), path)
    out = _designer("plan", path, "--json")
    assert out.returncode == 0, out.stderr
    s = json.loads(out.stdout)
    assert len(s["void_share"]) == 60 and s["surroundings"] == "none"
    assert s["void_share"]["DJI_00060.png"] > 0.5
    assert s["images_void_over_1_percent"] == sum(v > 0.01 for v in s["void_share"].values())
    assert any("see past the terrain" in w for w in s["warnings"])
    text = _designer("plan", tmp_path / "none.xml")
    assert "pixels seeing no ground: at most" in text.stdout


def test_surroundings_that_repeat_a_plain_tile_are_warned_about():
    """Without a variation, the surroundings hold exact copies of the tile beside the
    terrain (the altitude study's 40 m flight failed its SfM on them)."""
    from designer.scene.surroundings import Growth
    from designer.survey.surroundings import repeat_warning

    project = template("survey").project
    assert repeat_warning(project, Growth((1, 1, 1, 1))) is None  # the example varies
    plain = dataclasses.replace(project, scene=dataclasses.replace(
        project.scene, texture=dataclasses.replace(project.scene.texture, variation=None)))
    warning = repeat_warning(plain, Growth((1, 1, 1, 1)))
    assert warning.startswith("the surroundings repeat the texture's 20 m tile")
    assert "scale 40 m" in warning and "surroundings mode to none" in warning
    assert repeat_warning(plain, Growth()) is None  # nothing grown: nothing repeated


def test_void_shares_skip_only_images_whose_whole_bundle_sees_the_ground(monkeypatch):
    """An image whose four corner rays come down on the rendered terrain with room to
    spare is not cast ray by ray (surely_sees_surface); the shares are the same numbers as
    every ray cast, for the example with and without surroundings and for a rig's
    obliques (which look past the terrain)."""
    import designer.survey.surroundings as surroundings
    from designer.project.templates import survey_structures

    cases = [template("survey").project,
             _with_surroundings(template("survey").project, "none"),
             _with_surroundings(survey_structures().project, "none")]
    for project in cases:
        hf, images = _declared(project)
        grown = surroundings.grown_terrain(project, hf, images)
        rc = surroundings.raycaster_of(grown.surroundings.heightfield)
        fast = surroundings.void_shares(project, images, rc)
        with monkeypatch.context() as patch:
            patch.setattr(surroundings, "_bounding_cone_cv", lambda rays: None)
            every_ray = surroundings.void_shares(project, images, rc)
        assert np.array_equal(fast, every_ray)
        assert (fast == 0.0).any()
    assert (fast > 0.01).any()  # the last case sees void


def test_the_ground_reach_of_all_images_at_once_is_each_images_own():
    """ground_reach turns each camera's border rays for all its images at once; the reach
    is what each image's rays give alone (a rig's obliques, and an image seeing the
    horizon)."""
    import math

    from designer.project.templates import survey_structures
    from designer.survey.surroundings import (
        DETAIL_REACH_HEIGHTS,
        _rays_cv,
        border_pixels,
        ground_reach,
    )

    project = survey_structures().project
    hf, images = _declared(project)
    tilted = images.stations[0]
    horizon = dataclasses.replace(tilted, R_cam_to_world=tilted.R_cam_to_world @ np.array(
        [[1.0, 0.0, 0.0], [0.0, math.cos(1.4), -math.sin(1.4)],
         [0.0, math.sin(1.4), math.cos(1.4)]]))
    images = dataclasses.replace(images, stations=(horizon, *images.stations[1:]))
    low = float(hf.heights_m.min()) - 2.0
    points, seen_horizon = [], False
    for st, c in zip(images.stations, images.camera_ids, strict=True):
        interior = render_interior(project.camera(c), project.render.resolution_scale)
        d = _rays_cv(interior, border_pixels(interior)) @ (st.R_cam_to_world
                                                           @ R_CV_FROM_PHOTO).T
        reach = DETAIL_REACH_HEIGHTS * max(st.C_world[2] - low, 1.0)
        with np.errstate(divide="ignore", invalid="ignore"):
            t = np.where(d[:, 2] < 0, (low - st.C_world[2]) / d[:, 2], np.inf)
        far = ~(t <= reach)
        seen_horizon |= bool(far.any())
        flat = d[:, :2] / np.maximum(np.linalg.norm(d[:, :2], axis=1), 1e-12)[:, None]
        points.append(np.where(far[:, None], st.C_world[:2] + reach * flat,
                               st.C_world[:2] + t[:, None] * d[:, :2]))
    xy = np.concatenate(points)
    got = ground_reach(project, images, low)
    assert seen_horizon and got.horizon
    assert got.extent_m == (xy[:, 0].min(), xy[:, 0].max(), xy[:, 1].min(), xy[:, 1].max())
