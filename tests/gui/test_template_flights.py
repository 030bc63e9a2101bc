"""Every shipped template opened in the window: the Flight panel's "look beyond the
terrain" warning counts the images the project renders (every camera of a rig), names
one of them, and its count is the one an independent ray march over the height field
finds."""

from __future__ import annotations

import re

import numpy as np
import pytest

from designer.project.templates import TEMPLATE_NAMES
from tests.gui.helpers import open_panel, wait_idle

pytestmark = pytest.mark.gui

#: as the warning's rule: more than this share of the picture off the terrain
OFF_SHARE = 0.2
#: rays per image side, as the warning samples them
K = 9
#: a ray passing this close above the surface may count either way (the window's ray
#: casting stops 1 mm above the ground; the march here steps 10 cm along the ray)
GRAZE_M = 0.02


def _off_terrain_shares(hf, C: np.ndarray, dirs: np.ndarray, step_m: float = 0.1
                        ) -> tuple[float, float]:
    """Share of the rays from C (dirs: (n, 3)) that leave the height field's extent (or
    point upwards out of it) before they reach its surface: a plain march in small steps,
    none of the window's ray casting. Rays that pass within GRAZE_M of the surface without
    crossing it are counted neither way: (share sure to be off, share perhaps off)."""
    x0, x1, y0, y1 = hf.extent_m
    z_lo = float(hf.heights_m.min())
    off = grazing = 0
    for d in dirs / np.linalg.norm(dirs, axis=1, keepdims=True):
        t_end = 5000.0 if d[2] >= 0 else (C[2] - z_lo) / -d[2] + step_m
        # ... and just before each crossing of the extent's sides (a ray that reaches the
        # ground in the last millimetres before it leaves is on the terrain)
        with np.errstate(divide="ignore"):
            sides = np.concatenate([(np.array([x0, x1]) - C[0]) / d[0],
                                    (np.array([y0, y1]) - C[1]) / d[1]])
        sides = sides[np.isfinite(sides) & (sides > 0) & (sides < t_end)]
        t = np.concatenate([np.arange(0.0, t_end, step_m), sides * (1 - 1e-9)])
        P = C + t[:, None] * d
        inside = (P[:, 0] >= x0) & (P[:, 0] <= x1) & (P[:, 1] >= y0) & (P[:, 1] <= y1)
        gap = P[inside, 2] - hf.height_at(P[inside, 0], P[inside, 1])
        if not gap.size or gap.min() > GRAZE_M:
            off += 1
        elif gap.min() > 0:
            grazing += 1
    return off / len(dirs), (off + grazing) / len(dirs)


def _independent_count(project, hf) -> tuple[int, int, int, set[str]]:
    """(images sure to be more than OFF_SHARE off the terrain, images perhaps so, images
    rendered, their names)."""
    from designer.core.rotation import R_CV_FROM_PHOTO
    from designer.project.interiors import render_interior
    from designer.survey.project_poses import project_images

    images = project_images(project, hf)
    n_sure = n_perhaps = 0
    for st, camera_id in zip(images.stations, images.camera_ids, strict=True):
        interior = render_interior(project.camera(camera_id), project.render.resolution_scale)
        W, H = interior.image_size_px
        U, V = np.meshgrid(np.linspace(0.5, W - 0.5, K), np.linspace(0.5, H - 0.5, K))
        rays_cv = interior.rays_cv(np.column_stack([U.ravel(), V.ravel()]))
        dirs = rays_cv @ (st.R_cam_to_world @ R_CV_FROM_PHOTO).T
        sure, perhaps = _off_terrain_shares(hf, np.asarray(st.C_world), dirs)
        n_sure += sure > OFF_SHARE
        n_perhaps += perhaps > OFF_SHARE
    return (n_sure, n_perhaps, len(images.stations),
            {s.image_name for s in images.stations})


def test_each_templates_beyond_the_terrain_warning_counts_its_rendered_images(qtbot, window):
    w = window
    for name in TEMPLATE_NAMES:
        assert w.file_actions.new(name)
        wait_idle(qtbot, w)
        flight = open_panel(w, "Flight")
        assert w.sync.plan is not None, name
        n_sure, n_perhaps, n_images, names = _independent_count(
            w.document.project, w.sync.terrain.heightfield)
        assert flight.images_label.text() == str(n_images), name
        seen = re.match(r"\d+ of (\d+)( stations?)?", flight.real_images.text())
        # the figures over the terrain are per station: said so where they are not images
        assert seen is not None and (int(seen[1]) == n_images or seen[2]), name
        text = flight.warnings_label.text()
        found = re.search(r"(\d+) of (\d+) images? looks? beyond the terrain .*worst "
                          r"(\S+):", text)
        if n_perhaps == 0:
            assert found is None, f"{name}: {text}"
            continue
        assert found is not None, f"{name}: {n_sure} images off the terrain, no warning"
        assert n_sure <= int(found[1]) <= n_perhaps, f"{name}: {text} ({n_sure}–{n_perhaps})"
        assert int(found[2]) == n_images, f"{name}: {text}"
        assert found[3] in names, f"{name}: {text}"
