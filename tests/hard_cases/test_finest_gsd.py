"""The finest GSD designer check and the window weigh the texture against: each
camera's rays found once, the same figure as each image's rays found on their own."""

from __future__ import annotations

import math

import numpy as np
import pytest

from designer.checks.hard_cases import finest_gsd_m
from designer.core.projection import ground_sample_distance_m, pixel_rays_world
from designer.core.raycast import TerrainRaycaster
from designer.project import template
from designer.project.interiors import render_interior
from designer.scene.build import build_heightfield
from designer.survey.project_poses import project_images


def test_finest_gsd_is_each_images_own_rays_minimum(tmp_path):
    p = template("survey-structures").project  # three cameras, distortion-free and not
    hf = build_heightfield(p.scene.terrain, tmp_path, p.crs)
    images = project_images(p, hf)
    rc = TerrainRaycaster(hf)
    best = math.inf
    for station, camera_id in zip(images.stations, images.camera_ids, strict=True):
        io = render_interior(p.camera(camera_id), p.render.resolution_scale)
        W, H = io.image_size_px
        g = np.linspace(0.05, 0.95, 3)
        uv = np.stack(np.meshgrid(g * W, g * H), axis=-1).reshape(-1, 2)
        rays = pixel_rays_world(uv, station.R_cam_to_world, io)
        C = np.repeat(np.asarray(station.C_world, float)[None], len(uv), axis=0)
        hits = rc.surface_hit(C, rays, tol_m=1e-6)
        depth = (hits - C) @ -np.asarray(station.R_cam_to_world)[:, 2]
        gsd = depth * ground_sample_distance_m(io, 1.0)
        gsd = gsd[np.isfinite(gsd) & (gsd > 0)]
        if gsd.size:
            best = min(best, float(gsd.min()))
    assert finest_gsd_m(p, hf, images, rc) == pytest.approx(best, rel=1e-12)
