"""Which images of a project see each GCP: every image rendered (each camera of a rig
with its own pose and lens, in render order), not only the stations' planning camera.

One count for ``designer plan`` and the GUI's GCP table: a rig's obliques see GCPs the
nadir camera does not, and a GCP is measured in every image it is marked in.
"""

from __future__ import annotations

import numpy as np

from designer.core.raycast import TerrainRaycaster
from designer.project import model as m
from designer.project.interiors import render_interior
from designer.survey.coverage import GcpVisibility, gcp_visibility
from designer.survey.project_poses import ProjectImages


def project_gcp_visibility(project: m.Project, images: ProjectImages, gcp_xyz: np.ndarray,
                           raycaster: TerrainRaycaster, tol_m: float = 0.01
                           ) -> GcpVisibility:
    """For each GCP (G, 3, world m): how many of ``images`` see it inside the picture and
    unhidden by the terrain (the sight line meets it no closer than the GCP − tol_m),
    which (indices into ``images.stations``, ascending) and where (px of that image at
    the project's render resolution: u right, v down from the top-left corner)."""
    P = np.asarray(gcp_xyz, dtype=float).reshape(-1, 3)
    found: list[list[tuple[np.ndarray, np.ndarray]]] = [[] for _ in range(len(P))]
    camera_ids = np.array(images.camera_ids)
    for camera_id in images.camera_order():
        k = np.flatnonzero(camera_ids == camera_id)
        members = [images.stations[i] for i in k]
        interior = render_interior(project.camera(camera_id), project.render.resolution_scale)
        vis = gcp_visibility(P, np.array([s.C_world for s in members]),
                             np.array([s.R_cam_to_world for s in members]), interior,
                             raycaster, tol_m)
        for g in range(len(P)):
            found[g].append((k[vis.images[g]], vis.uv_px[g]))
    index, uv = [], []
    for parts in found:
        image = np.concatenate([p[0] for p in parts] or [np.zeros(0)]).astype(int)
        order = np.argsort(image, kind="stable")
        index.append(image[order])
        uv.append(np.concatenate([p[1].reshape(-1, 2) for p in parts]
                                 or [np.zeros((0, 2))])[order])
    return GcpVisibility(np.array([len(i) for i in index], dtype=int), tuple(index),
                         tuple(uv))
