"""How far the images of a project look: the growth of the rendered terrain
(:mod:`designer.scene.surroundings`) and each image's share of pixels that see no ground.

Every image's border rays (:data:`BORDER_SAMPLES` per side) are cut with the plane of the
lowest ground the surroundings can have; the rendered terrain covers those points plus a
margin. A ray that meets that plane farther than :data:`DETAIL_REACH_HEIGHTS` times the
camera's height above it (an oblique near the horizon) extends the terrain only that far
and sets ``horizon``.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from designer.core.heightfield import Heightfield
from designer.core.raycast import TerrainRaycaster, raycaster_of
from designer.core.rotation import R_CV_FROM_PHOTO
from designer.project import model as m
from designer.project.interiors import render_interior
from designer.scene.surroundings import (
    Growth,
    Surroundings,
    grow_terrain,
    grown_extent,
    growth_step_m,
    surroundings_mode,
)

#: the grid spacing flat ground's margin counts in (m)
FLAT_MARGIN_SPACING_M = 0.5
#: rays per image side whose ground points bound the surroundings
BORDER_SAMPLES = 24
#: a ray meeting the ground farther than this many camera heights is near the horizon:
#: the detailed terrain stops there and the far ground continues to the horizon
DETAIL_REACH_HEIGHTS = 12.0


@dataclass(frozen=True)
class Reach:
    """Where the images' border rays meet the lowest ground: (x_min, x_max, y_min, y_max)
    in world metres, and whether any ray looks farther than the detailed reach."""

    extent_m: tuple[float, float, float, float]
    horizon: bool


def border_pixels(interior) -> np.ndarray:
    """(4·(n − 1), 2) pixel positions around the image border, corners included."""
    W, H = interior.image_size_px
    n = BORDER_SAMPLES
    t = np.linspace(0.0, 1.0, n)[:-1]
    top = np.column_stack([t * W, np.zeros_like(t)])
    right = np.column_stack([np.full_like(t, W), t * H])
    bottom = np.column_stack([W - t * W, np.full_like(t, H)])
    left = np.column_stack([np.zeros_like(t), H - t * H])
    return np.concatenate([top, right, bottom, left])


def _rays_cv(interior, uv: np.ndarray) -> np.ndarray:
    """The CV-frame rays of pixels ``uv``; a distortion that cannot be inverted at the
    border: its pinhole's."""
    try:
        return interior.rays_cv(uv)
    except Exception:
        return replace(interior, distortion=None).rays_cv(uv)


def ground_reach(project: m.Project, images, ground_low_m: float) -> Reach:
    """Where the border rays of every image meet the plane Z = ``ground_low_m`` (the lowest
    ground around), capped at the detailed reach."""
    interiors = {c: render_interior(project.camera(c), project.render.resolution_scale)
                 for c in images.camera_order()}
    # each camera's border rays in its own frame, once (pixel_rays_world's steps)
    rays_cv = {c: _rays_cv(i, border_pixels(i)) for c, i in interiors.items()}
    points, horizon = [], False
    # the images of each camera at once (each image's rays turned by its own rotation)
    for c in images.camera_order():
        k = [i for i, cam in enumerate(images.camera_ids) if cam == c]
        R = np.array([images.stations[i].R_cam_to_world for i in k], float).reshape(-1, 3, 3)
        C = np.array([images.stations[i].C_world for i in k], float).reshape(-1, 3)
        d = np.matmul(rays_cv[c], np.swapaxes(R @ R_CV_FROM_PHOTO, 1, 2))  # (n, S, 3)
        height = np.maximum(C[:, 2] - ground_low_m, 1.0)
        reach = (DETAIL_REACH_HEIGHTS * height)[:, None]
        with np.errstate(divide="ignore", invalid="ignore"):
            t = np.where(d[..., 2] < 0, (ground_low_m - C[:, 2:3]) / d[..., 2], np.inf)
        far = ~(t <= reach)
        horizon |= bool(far.any())
        # a ray near the horizon: its horizontal direction out to the detailed reach
        horizontal = d[..., :2] / np.maximum(np.linalg.norm(d[..., :2], axis=2),
                                             1e-12)[..., None]
        xy = np.where(far[..., None], C[:, None, :2] + reach[..., None] * horizontal,
                      C[:, None, :2] + t[..., None] * d[..., :2])
        points.append(xy.reshape(-1, 2))
    xy = np.concatenate(points) if points else np.zeros((0, 2))
    if not len(xy):
        return Reach((math.inf, -math.inf, math.inf, -math.inf), False)
    return Reach((float(xy[:, 0].min()), float(xy[:, 0].max()),
                  float(xy[:, 1].min()), float(xy[:, 1].max())), horizon)


def terrain_growth(project: m.Project, declared: Heightfield, images) -> Growth:
    """How far to grow the declared terrain so every image of ``images`` (the project's,
    :func:`designer.survey.project_poses.project_images` over ``declared``) sees ground
    to its border; no growth with surroundings "none"."""
    src = project.scene.terrain.source
    if (surroundings_mode(project.scene.terrain) == "none" or not len(images.stations)
            or isinstance(src, m.MeshTerrain)):
        return Growth()
    ground_low = float(declared.heights_m.min())
    if isinstance(src, m.ProceduralTerrain):
        ground_low = min(ground_low, src.min_height_m)
    reach = ground_reach(project, images, ground_low)
    step = growth_step_m(project, declared)
    # the margin's floor: a few grid spacings (flat ground has no grid: 0.5 m)
    spacing = (FLAT_MARGIN_SPACING_M if isinstance(src, m.FlatTerrain)
               else min(declared.dx_m, declared.dy_m))
    return Growth(grown_extent(declared.extent_m, reach.extent_m, step[0], step[1], spacing),
                  reach.horizon)


def project_surroundings(project: m.Project, base_dir: Path) -> tuple[Growth, Heightfield | None]:
    """The growth of ``project``'s terrain and its declared height field (None for a
    mesh terrain), planned as the renderer plans it."""
    from designer.scene.build import build_heightfield
    from designer.survey.project_poses import project_images

    declared = build_heightfield(project.scene.terrain, Path(base_dir), project.crs)
    if declared is None:
        return Growth(), None
    return terrain_growth(project, declared, project_images(project, declared)), declared


@dataclass(frozen=True, eq=False)
class GrownTerrain:
    """The declared terrain grown for a project's images: how far (``growth``) and the
    height field the renderer draws (``surroundings``). Growing a procedural terrain
    computes its hills over the whole grown extent, so a caller that needs it twice
    for the same images (the window's stations and plan figures) passes this on."""

    growth: Growth
    surroundings: Surroundings


def grown_terrain(project: m.Project, declared: Heightfield | None, images) -> GrownTerrain:
    """``declared`` grown as far as ``images`` see (:func:`terrain_growth`)."""
    growth = terrain_growth(project, declared, images)
    return GrownTerrain(growth, grow_terrain(project, declared, growth))


def rendered_terrain(project: m.Project, declared: Heightfield, images) -> Surroundings:
    """The height field the renderer draws: ``declared`` grown as far as ``images`` see."""
    return grown_terrain(project, declared, images).surroundings


#: rays along an image's longer side (and in proportion along the shorter) that measure
#: the share of its pixels that see no ground
VOID_SAMPLES = 64
#: an image with more than this share of its pixels seeing no ground is warned about
VOID_WARN = 0.01


def void_shares(project: m.Project, images, raycaster, far_ground: bool = False,
                check: Callable[[], None] | None = None) -> np.ndarray:
    """(M,) share of each image's pixels (a grid of pixel-centre rays) whose ray meets no
    terrain of ``raycaster`` (a :class:`~designer.core.raycast.TerrainRaycaster` over
    the rendered terrain): what renders as background. With ``far_ground`` (the
    renderer's ring of ground to the horizon, and a sky) no ray sees the background: one
    pointing down meets the far ground, one pointing up the sky. ``check`` is called
    between groups of :data:`VOID_CHUNK` images (it may raise to stop the work)."""
    out = np.zeros(len(images.stations))
    if far_ground:
        return out
    for camera_id in images.camera_order():
        interior = render_interior(project.camera(camera_id), project.render.resolution_scale)
        W, H = interior.image_size_px
        ku = VOID_SAMPLES if W >= H else max(2, round(VOID_SAMPLES * W / H))
        kv = VOID_SAMPLES if H > W else max(2, round(VOID_SAMPLES * H / W))
        U, V = np.meshgrid((np.arange(ku) + 0.5) * W / ku, (np.arange(kv) + 0.5) * H / kv)
        uv = np.column_stack([U.ravel(), V.ravel()])
        rays_cv = _rays_cv(interior, uv)
        k = [i for i, c in enumerate(images.camera_ids) if c == camera_id]
        C = np.array([images.stations[i].C_world for i in k], float).reshape(-1, 3)
        R = np.array([images.stations[i].R_cam_to_world for i in k]).reshape(-1, 3, 3)
        cone = _bounding_cone_cv(rays_cv)
        if cone is not None:
            # an image whose whole bundle of rays surely comes down on the terrain
            # shows no void: its rays need not be tested one by one (the same share, 0)
            corners = np.einsum("mij,sj->msi", R @ R_CV_FROM_PHOTO, cone)
            keep = ~raycaster.surely_sees_surface(C, corners)
            k = [i for i, kept in zip(k, keep, strict=True) if kept]
            C, R = C[keep], R[keep]
        rays = np.einsum("mij,sj->msi", R @ R_CV_FROM_PHOTO, rays_cv)
        for a in range(0, len(k), VOID_CHUNK):
            if check is not None:
                check()
            part = slice(a, a + VOID_CHUNK)
            origins = np.repeat(C[part], len(uv), axis=0)
            # the rendered surface has no sides: a ray entering one below it sees no ground
            ground = raycaster.sees_surface(origins, rays[part].reshape(-1, 3))
            out[k[part]] = 1.0 - ground.reshape(-1, len(uv)).mean(axis=1)
    return out


#: images whose void rays are cast together (between two calls of ``check``)
VOID_CHUNK = 64


def _bounding_cone_cv(rays_cv: np.ndarray) -> np.ndarray | None:
    """Four CV-frame directions (4, 3) whose convex cone holds every ray of ``rays_cv``
    (the rectangle the rays span on the image plane z = 1), or None when a ray does not
    point forward (a fisheye's past 90°): there is no such rectangle."""
    z = rays_cv[:, 2]
    if not np.all(z > 0) or not np.all(np.isfinite(rays_cv)):
        return None
    x, y = rays_cv[:, 0] / z, rays_cv[:, 1] / z
    # a little wider than the rays span, so rounding keeps every ray inside the cone
    pad = 1e-9 * (1.0 + np.abs(x).max() + np.abs(y).max())
    x0, x1, y0, y1 = x.min() - pad, x.max() + pad, y.min() - pad, y.max() + pad
    return np.array([[x0, y0, 1.0], [x1, y0, 1.0], [x1, y1, 1.0], [x0, y1, 1.0]])


@dataclass(frozen=True)
class VoidImages:
    """The images that see past the rendered terrain: more than :data:`VOID_WARN` of
    their pixels show no ground. ``count`` of ``total`` images; the worst, ``worst_name``,
    with ``worst_share`` (0..1) of its pixels; ``surroundings``: the terrain's mode
    ("none" or "auto"), which decides the fix."""

    count: int
    total: int
    worst_name: str
    worst_share: float
    surroundings: str

    def warning(self, fix: str) -> str:
        """The warning with ``fix`` (in the words of where it is read: the project file's
        element for the command line, a panel's control for the GUI) as its end."""
        see = "sees" if self.count == 1 else "see"
        return (f"{self.count} of {self.total} images {see} past the terrain (more than "
                f"{100 * VOID_WARN:g} % of the picture shows no ground; worst "
                f"{self.worst_name}: {100 * self.worst_share:.1f} %): {fix}")


def void_images(names, shares: np.ndarray, surroundings: str) -> VoidImages | None:
    """The images whose share of void pixels (``shares``, 0..1, one per name) exceeds
    :data:`VOID_WARN`, or None when there are none."""
    shares = np.asarray(shares, float)
    off = np.flatnonzero(shares > VOID_WARN)
    if not off.size:
        return None
    worst = off[np.argmax(shares[off])]
    return VoidImages(int(off.size), len(shares), names[worst], float(shares[worst]),
                      surroundings)


def void_warning(names, shares: np.ndarray, surroundings: str) -> str | None:
    """The plan's warning about images that see past the rendered terrain, or None."""
    void = void_images(names, shares, surroundings)
    if void is None:
        return None
    return void.warning("set the terrain's surroundings mode to auto or enlarge the "
                        "terrain" if void.surroundings == "none" else "enlarge the terrain")


@dataclass(frozen=True)
class ImageGround:
    """Each image's share of pixels that see no ground, over the rendered terrain
    (``rendered``, with its ray caster)."""

    names: tuple[str, ...]
    void_share: np.ndarray
    rendered: Heightfield
    growth: Growth
    raycaster: TerrainRaycaster

    def warning(self, project: m.Project) -> str | None:
        return void_warning(self.names, self.void_share,
                            surroundings_mode(project.scene.terrain))


def image_ground(project: m.Project, declared: Heightfield, images,
                 grown: GrownTerrain | None = None,
                 check: Callable[[], None] | None = None) -> ImageGround:
    """Grow the declared terrain as the renderer does and measure each image's void
    share: the one function behind ``designer plan`` (text and JSON), the window's plan
    figures and ``designer check``. ``grown``: the terrain already grown for ``images``
    (:func:`grown_terrain`), when the caller has it; ``check``: called between parts of
    the work (it may raise to stop it)."""
    if grown is None:
        grown = grown_terrain(project, declared, images)
    growth, rendered = grown.growth, grown.surroundings.heightfield
    raycaster = raycaster_of(rendered)
    shares = void_shares(project, images, raycaster, growth.horizon, check)
    return ImageGround(tuple(s.image_name for s in images.stations), shares, rendered, growth,
                       raycaster)


def surroundings_warning(project: m.Project, base_dir: Path) -> str | None:
    """``designer check``'s warning when images of the project would see past the
    rendered terrain (more than VOID_WARN of their pixels), naming them and the fix;
    None when every image sees ground (or the terrain is a mesh, which is not analysed)."""
    from designer.scene.build import build_heightfield
    from designer.survey.project_poses import project_images

    declared = build_heightfield(project.scene.terrain, Path(base_dir), project.crs)
    if declared is None:
        return None
    images = project_images(project, declared)
    if not len(images.stations):
        return None
    ground = image_ground(project, declared, images)
    repeat = repeat_warning(project, ground.growth)
    off = [n for n, v in zip(ground.names, ground.void_share, strict=True) if v > VOID_WARN]
    if not off:
        return repeat
    shown = ", ".join(off[:5]) + (f" and {len(off) - 5} more" if len(off) > 5 else "")
    void = f"{ground.warning(project)} [{shown}]"
    return void if repeat is None else f"{void}; {repeat}"


def repeat_warning(project: m.Project, growth: Growth) -> str | None:
    """A warning when the surroundings continue a tiled texture that has no variation:
    the tile's exact copies then lie beside the terrain, where images near its edge see
    them, and feature matching pairs copies of the same ground (measured: the altitude
    study's 40 m flight over a 60 m tile failed its SfM, 15 m check error, and
    reconstructed to 2 cm with a variation). None otherwise."""
    texture = project.scene.texture
    if (not any(growth.steps) or texture.variation is not None
            or isinstance(texture.source, m.OrthophotoTexture)):
        return None
    e = project.scene.terrain.extent
    period = min(e.width_m / texture.repeat_X, e.length_m / texture.repeat_Y)
    return (f"the surroundings repeat the texture's {period:g} m tile beside the terrain: "
            "images near its edge see copies of the terrain's ground, which feature "
            "matching pairs; give the texture a variation (e.g. seed 1, scale "
            f"{2 * period:g} m, strength 0.35; docs/world.md) or set the terrain's "
            "surroundings mode to none")
