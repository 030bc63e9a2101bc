"""Every shipped template opened in the window: with the terrain's surroundings every
image sees ground, so no flight is warned about images that see past the terrain, and an
independent ray march over the rendered terrain (the declared one and its surroundings)
finds no image with more than 1 % of its rays off it. Without surroundings the Flight
panel's warning counts the rendered images (every camera of a rig) the march finds, and
names one of them.

The march knows nothing of the window's ray casting: plain steps along each ray over the
bilinear height field."""

from __future__ import annotations

import re

import numpy as np
import pytest

from designer.project.templates import TEMPLATE_NAMES
from tests.gui.helpers import open_panel, wait_idle

pytestmark = pytest.mark.gui

#: as the warning's rule: more than this share of the picture sees no ground
OFF_SHARE = 0.01
#: rays along an image's longer side (the shorter in proportion), as the warning samples
#: the picture: the shares compared are of the same pixels
SAMPLES = 64
#: a ray passing this close above the surface may count either way (the window's ray
#: casting and the renderer's triangles differ from the bilinear surface marched here by
#: millimetres; the march steps 10 cm along the ray)
GRAZE_M = 0.02
#: validation templates that keep their background on purpose (no surroundings)
BACKGROUND = ("validation-cube", "psf", "texture")
#: the fix it names, in the window's terms: the Terrain panel's control
FIX = "choose surroundings “auto” in the Terrain panel, or enlarge the terrain"
#: what the warning says (designer.survey.surroundings.void_warning)
WARNING = re.compile(r"(\d+) of (\d+) images? sees? past the terrain \(more than 1 % of the "
                     r"picture shows no ground; worst (\S+): ([\d.]+) %\)")


def _off_terrain(hf, C: np.ndarray, dirs: np.ndarray, step_m: float = 0.1
                 ) -> tuple[np.ndarray, np.ndarray]:
    """Which rays from C (dirs: (n, 3)) leave the height field's extent (or point up out
    of it) before they reach its surface: (sure to be off, perhaps off) as (n,) bools.
    A ray that passes within GRAZE_M above the surface without crossing it is perhaps off.

    Only the stretch of each ray over the extent and between the lowest and the highest
    ground can meet the surface; a ray still over the extent where it sinks below the
    lowest ground has met it (the cameras are above the ground). The rest is marched in
    ``step_m`` steps, with one more sample just before the ray leaves the extent (a ray
    that reaches the ground in the last millimetres before it leaves is on the terrain)."""
    x0, x1, y0, y1 = hf.extent_m
    z_lo, z_hi = float(hf.heights_m.min()), float(hf.heights_m.max())
    d = dirs / np.linalg.norm(dirs, axis=1, keepdims=True)
    n = len(d)
    with np.errstate(divide="ignore", invalid="ignore"):
        # where each ray is over the extent: [t_in, t_out] (slabs of X and Y)
        ends = []
        for lo, hi, c, dk in ((x0, x1, C[0], d[:, 0]), (y0, y1, C[1], d[:, 1])):
            a, b = (lo - c) / dk, (hi - c) / dk
            parallel = dk == 0
            inside = lo <= c <= hi
            a = np.where(parallel, -np.inf if inside else np.inf, a)
            b = np.where(parallel, np.inf if inside else -np.inf, b)
            ends.append((np.minimum(a, b), np.maximum(a, b)))
        t_in = np.maximum(np.maximum(ends[0][0], ends[1][0]), 0.0)
        t_out = np.minimum(ends[0][1], ends[1][1])
        down = d[:, 2] < 0
        t_lo = np.where(down, (C[2] - z_lo) / -d[:, 2], np.inf)
        t_hi = np.where(C[2] <= z_hi, 0.0,
                        np.where(down, (C[2] - z_hi) / -d[:, 2], np.inf))
    sure_on = (t_in <= t_lo) & (t_lo <= t_out)
    t0 = np.maximum(t_in, t_hi)
    t1 = np.minimum(t_out, t_lo) * (1 - 1e-9)
    march = np.flatnonzero(~sure_on & (t0 <= t1))
    gap_min = np.full(n, np.inf)
    for part in np.array_split(march, max(1, len(march) // 200)):
        if not len(part):
            continue
        k_steps = np.ceil((t1[part] - t0[part]) / step_m).astype(int) + 1
        ray = np.repeat(part, k_steps)
        k = np.arange(k_steps.sum()) - np.repeat(np.cumsum(k_steps) - k_steps, k_steps)
        t = np.minimum(t0[ray] + k * step_m, t1[ray])
        P = C + t[:, None] * d[ray]
        gap = P[:, 2] - hf.height_at(P[:, 0], P[:, 1])
        gap = np.where(np.isnan(gap), np.inf, gap)
        gap_min[part] = np.minimum.reduceat(gap, np.cumsum(k_steps) - k_steps)
    on = sure_on | (gap_min <= 0)
    # the rendered surface has no sides: a ray from beside the terrain that enters its
    # extent below the surface passes under it and sees the background
    entering = np.flatnonzero((t_in > 0) & (t_in <= t_out) & np.isfinite(t_in))
    if len(entering):
        P = C + t_in[entering, None] * d[entering]
        under = P[:, 2] < hf.height_at_clamped(P[:, 0], P[:, 1]) - 1e-6
        on[entering[under]] = False
        gap_min[entering[under]] = np.inf
    return ~on & (gap_min > GRAZE_M), ~on


def _independent_shares(project, hf):
    """Each rendered image's share of rays off the rendered terrain: (sure, perhaps)
    (M,) each, the images' names, whether an image looks towards the horizon and (M,)
    whether each camera is over the rendered terrain's extent."""
    from designer.core.rotation import R_CV_FROM_PHOTO
    from designer.project.interiors import render_interior
    from designer.survey.project_poses import project_images
    from designer.survey.surroundings import image_ground

    images = project_images(project, hf)
    ground = image_ground(project, hf, images)
    rendered = ground.rendered
    sure, perhaps = np.zeros(len(images.stations)), np.zeros(len(images.stations))
    for i, (st, camera_id) in enumerate(zip(images.stations, images.camera_ids, strict=True)):
        interior = render_interior(project.camera(camera_id), project.render.resolution_scale)
        W, H = interior.image_size_px
        ku = SAMPLES if W >= H else max(2, round(SAMPLES * W / H))
        kv = SAMPLES if H > W else max(2, round(SAMPLES * H / W))
        U, V = np.meshgrid((np.arange(ku) + 0.5) * W / ku, (np.arange(kv) + 0.5) * H / kv)
        rays_cv = interior.rays_cv(np.column_stack([U.ravel(), V.ravel()]))
        dirs = rays_cv @ (st.R_cam_to_world @ R_CV_FROM_PHOTO).T
        off, maybe = _off_terrain(rendered, np.asarray(st.C_world, float), dirs)
        sure[i], perhaps[i] = off.mean(), maybe.mean()
    x0, x1, y0, y1 = rendered.extent_m
    over = np.array([x0 <= s.C_world[0] <= x1 and y0 <= s.C_world[1] <= y1
                     for s in images.stations], bool)
    return (sure, perhaps, tuple(s.image_name for s in images.stations),
            ground.growth.horizon, over)


def _open(qtbot, w, name: str):
    assert w.file_actions.new(name)
    wait_idle(qtbot, w)
    flight = open_panel(w, "Flight")
    assert w.sync.plan is not None, name
    return flight


def _set_surroundings(qtbot, w, mode: str) -> None:
    """Choose ``mode`` in the Terrain panel's surroundings box."""
    terrain = open_panel(w, "Terrain")
    terrain.surroundings.setCurrentIndex(terrain.surroundings.findData(mode))
    wait_idle(qtbot, w)
    assert w.document.project.scene.terrain.surroundings == mode
    open_panel(w, "Flight")


def _check_warning(name: str, flight, sure, perhaps, names, over) -> None:
    """The Flight panel's warning counts the images the march finds more than OFF_SHARE
    off the terrain (between those sure to be and those perhaps so) and names one; its
    share is the march's. ``over``: (M,) whether each camera is over the terrain."""
    n_sure, n_perhaps = int((sure > OFF_SHARE).sum()), int((perhaps > OFF_SHARE).sum())
    text = flight.warnings_label.text()
    found = WARNING.search(text)
    assert n_perhaps > 0, f"{name}: the march finds no image off the terrain"
    assert found is not None, f"{name}: {n_sure} images off the terrain, no warning: {text}"
    assert n_sure <= int(found[1]) <= n_perhaps, f"{name}: {text} ({n_sure}–{n_perhaps})"
    assert int(found[2]) == len(names), f"{name}: {text}"
    worst = found[3]
    assert worst in names, f"{name}: {text}"
    k = names.index(worst)
    assert perhaps[k] > OFF_SHARE, f"{name}: {text}: the march finds {worst} on the terrain"
    # the worst share, as the march measures the same pixels (± a grazing ray or two);
    # from a camera beside the terrain, a ray entering its side below the surface sees
    # the background in both (the rendered surface has no sides)
    share = float(found[4]) / 100
    assert share <= perhaps[k] + 0.01, f"{name}: {text} (march {100 * perhaps[k]:.1f} %)"
    assert share >= sure[k] - 0.01, f"{name}: {text} (march {100 * sure[k]:.1f} %)"


def test_no_templates_flight_sees_past_its_rendered_terrain(qtbot, window):
    w = window
    for name in TEMPLATE_NAMES:
        flight = _open(qtbot, w, name)
        if name in BACKGROUND:
            # a validation experiment keeps its background: the warning says which images
            # see it; the fix it names (auto surroundings) covers them
            assert w.document.project.scene.terrain.surroundings == "none", name
            sure, perhaps, names, _, over = _independent_shares(
                w.document.project, w.sync.terrain.heightfield)
            _check_warning(name, flight, sure, perhaps, names, over)
            assert FIX in flight.warnings_label.text(), name
            _set_surroundings(qtbot, w, "auto")
        sure, perhaps, names, horizon, _ = _independent_shares(
            w.document.project, w.sync.terrain.heightfield)
        # the march has no far ground to the horizon: no template looks that far
        assert not horizon, name
        assert flight.images_label.text() == str(len(names)), name
        seen = re.match(r"\d+ of (\d+)( stations?)?", flight.real_images.text())
        # the figures over the terrain are per station: said so where they are not images
        assert seen is not None and (int(seen[1]) == len(names) or seen[2]), name
        text = flight.warnings_label.text()
        assert "past the terrain" not in text, f"{name}: {text}"
        worst = int(np.argmax(perhaps))
        assert perhaps[worst] <= OFF_SHARE, \
            f"{name}: {names[worst]} has {100 * perhaps[worst]:.1f} % of its rays off the terrain"


def test_the_example_without_surroundings_warns_of_the_images_the_march_finds(qtbot, window):
    w = window
    _open(qtbot, w, "survey")
    assert "past the terrain" not in w.panels["Flight"].warnings_label.text()
    _set_surroundings(qtbot, w, "none")
    flight = w.panels["Flight"]
    sure, perhaps, names, _, over = _independent_shares(w.document.project,
                                                        w.sync.terrain.heightfield)
    _check_warning("survey", flight, sure, perhaps, names, over)
    assert FIX in flight.warnings_label.text()
    assert "<surroundings" not in flight.warnings_label.text()
