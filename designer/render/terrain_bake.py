"""Two bakes for a varied ground texture over wide surroundings: detail near, coarse far.

The varied texture is baked into one image at the detail texture's texel
(:mod:`designer.render.texture_bake`) when that image fits :data:`MAX_BAKE_PX` a side.
Surroundings seen by obliques can make the rendered terrain hundreds of metres wide
(the rig of the structures template looks 180 m past its terrain): a bake of that at
2.5 cm texels would be 20 000 px a side, and the node graph the renderer falls back to
costs 3.5 times the render time. Instead the terrain gets two materials:

* the **detail bake** over the declared extent grown by as many whole texture tiles of
  the surroundings as fit :data:`MAX_BAKE_PX` (the ground the nadir images see), looked
  up through a second UV layer over that rectangle; the faces inside it use it;
* the **coarse bake** over the whole rendered terrain at most :data:`COARSE_BAKE_PX` a
  side, from the detail texture averaged down (``cv2.INTER_AREA``) to the coarse texel,
  for the faces beyond — ground that the images see from far away and at a slant.

Both are the same blend of the same world-fixed variation, so the seam between them is a
change of sharpness, not of colour or place; the geometry is one mesh (no crack).
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np

from designer.render import texture_bake
from designer.render.texture_bake import bake_varied_texture
from designer.scene.build import BuiltScene
from designer.scene.texture_variation import variation_images

#: the largest side of the coarse bake over the whole rendered terrain (px)
COARSE_BAKE_PX = 4096


@dataclass(frozen=True)
class TwoLevelBake:
    """The detail bake over ``inner_extent_m`` (x0, x1, y0, y1; its texture coordinates
    per terrain vertex in ``inner_uv``), the coarse bake over the whole terrain, and each
    terrain face's material (0 detail, 1 coarse)."""

    inner: np.ndarray
    inner_extent_m: tuple[float, float, float, float]
    inner_uv: np.ndarray
    coarse: np.ndarray
    material_index: np.ndarray

    def inner_rect_uv(self, extent_m: tuple[float, float, float, float]
                      ) -> tuple[float, float, float, float]:
        """The detail bake's rectangle (u0, u1, v0, v1) in the terrain's UV square."""
        x0, x1, y0, y1 = extent_m
        a0, a1, b0, b1 = self.inner_extent_m
        return ((a0 - x0) / (x1 - x0), (a1 - x0) / (x1 - x0),
                (b0 - y0) / (y1 - y0), (b1 - y0) / (y1 - y0))


def inner_tiles(scene: BuiltScene, repeat: tuple[int, int]) -> tuple[int, int, int, int]:
    """Whole tiles (west, east, south, north) of the surroundings the detail bake covers:
    the growth, trimmed on its widest side until the bake fits MAX_BAKE_PX."""
    h, w = scene.texture_rgb.shape[:2]
    grow = list(scene.growth.steps)
    limit = texture_bake.MAX_BAKE_PX
    while (repeat[0] + grow[0] + grow[1]) * w > limit and grow[0] + grow[1] > 0:
        grow[0 if grow[0] >= grow[1] else 1] -= 1
    while (repeat[1] + grow[2] + grow[3]) * h > limit and grow[2] + grow[3] > 0:
        grow[2 if grow[2] >= grow[3] else 3] -= 1
    return tuple(grow)


def needs_two_levels(scene: BuiltScene, repeat: tuple[int, int]) -> bool:
    """True when the whole terrain's bake exceeds MAX_BAKE_PX but the declared extent's
    fits: the terrain gets a detail and a coarse bake."""
    h, w = scene.texture_rgb.shape[:2]
    tx, ty = scene.texture_tiles
    limit = texture_bake.MAX_BAKE_PX
    whole = max(tx * w, ty * h) > limit
    declared = max(repeat[0] * w, repeat[1] * h) <= limit
    return scene.variation is not None and any(scene.growth.steps) and whole and declared


def two_level_bake(scene: BuiltScene, repeat: tuple[int, int],
                   variation_model) -> TwoLevelBake:
    """Bake the detail and the coarse texture of ``scene`` (see the module docstring);
    ``repeat`` are the declared texture repeats, ``variation_model`` the project's
    :class:`~designer.project.model.TextureVariation`."""
    hf = scene.heightfield
    x0, x1, y0, y1 = hf.extent_m
    tx, ty = scene.texture_tiles
    tile_x, tile_y = (x1 - x0) / tx, (y1 - y0) / ty
    grow_w, grow_e, grow_s, grow_n = scene.growth.steps
    w, e, s, n = inner_tiles(scene, repeat)
    # the declared extent sits grow_* tiles in from the terrain's edges
    ix0, ix1 = x0 + (grow_w - w) * tile_x, x1 - (grow_e - e) * tile_x
    iy0, iy1 = y0 + (grow_s - s) * tile_y, y1 - (grow_n - n) * tile_y
    inner_extent = (ix0, ix1, iy0, iy1)
    inner_count = (repeat[0] + w + e, repeat[1] + s + n)
    inner = bake_varied_texture(scene.texture_rgb, inner_count,
                                variation_images(variation_model, inner_extent),
                                scene.interpolation)
    # the coarse bake: the tile averaged down so the whole terrain fits COARSE_BAKE_PX
    h_px, w_px = scene.texture_rgb.shape[:2]
    factor = min(1.0, COARSE_BAKE_PX / max(tx * w_px, ty * h_px))
    small = (max(2, round(w_px * factor)), max(2, round(h_px * factor)))
    tile = cv2.resize(scene.texture_rgb, small, interpolation=cv2.INTER_AREA)
    coarse = bake_varied_texture(tile, (tx, ty), scene.variation, scene.interpolation)
    v = scene.terrain.vertices_world
    uv = np.column_stack([(v[:, 0] - ix0) / (ix1 - ix0), (v[:, 1] - iy0) / (iy1 - iy0)])
    eps = 1e-6
    inside = (uv[:, 0] >= -eps) & (uv[:, 0] <= 1 + eps) & (uv[:, 1] >= -eps) & (uv[:, 1] <= 1 + eps)
    material = np.where(inside[scene.terrain.faces].all(axis=1), 0, 1).astype(np.int32)
    return TwoLevelBake(inner, inner_extent, uv, coarse, material)


def sample_light_rect(light: np.ndarray, shape: tuple[int, int],
                      rect_uv: tuple[float, float, float, float]) -> np.ndarray:
    """The light map ``light`` (Lh, Lw) float32 over the UV square (row 0 north), read
    bilinearly with edge texels extended, as Blender reads it, at the texel centres of an
    image of ``shape`` (H, W) covering ``rect_uv`` (u0, u1, v0, v1): (H, W) float32."""
    H, W = shape
    Lh, Lw = light.shape
    u0, u1, v0, v1 = rect_uv
    u = u0 + (np.arange(W) + 0.5) / W * (u1 - u0)
    v = v1 - (np.arange(H) + 0.5) / H * (v1 - v0)
    px = np.clip(u * Lw - 0.5, 0, Lw - 1)
    py = np.clip((1.0 - v) * Lh - 0.5, 0, Lh - 1)
    jx = np.minimum(px.astype(int), Lw - 2) if Lw > 1 else np.zeros(W, int)
    iy = np.minimum(py.astype(int), Lh - 2) if Lh > 1 else np.zeros(H, int)
    wx = (px - jx).astype(np.float32)
    wy = (py - iy).astype(np.float32)[:, None]
    rows = light[:, jx] * (1 - wx) + light[:, np.minimum(jx + 1, Lw - 1)] * wx  # (Lh, W)
    return rows[iy] * (1 - wy) + rows[np.minimum(iy + 1, Lh - 1)] * wy


#: the far ground's tile is the detail tile averaged down by this factor a side: at the
#: distances it is seen from, a finer tile would alias into noise (Cycles does not
#: mip-map on the CPU)
FAR_TILE_REDUCTION = 16
#: the job's file of the far ground's tile
FAR_TEXTURE = "texture_far.png"


def far_ground_arrays(scene: BuiltScene, arrays: dict, n_materials: int) -> dict:
    """The terrain mesh's arrays (``vertices_world``, ``faces``, ``uv`` and, when present,
    ``uv_texture`` and ``material_index``) with the far ground ring
    (:func:`designer.scene.surroundings.far_ground`) appended as material ``n_materials``.
    The ring's UVs continue the terrain's (its tiles repeat); an orthophoto's texture
    coordinates hold the edge colours outwards."""
    from designer.scene.surroundings import far_ground

    hf = scene.heightfield
    outer, ring = far_ground(hf)
    x0, x1, y0, y1 = hf.extent_m
    n_inner = len(arrays["vertices_world"])
    uv_outer = np.column_stack([(outer[:, 0] - x0) / (x1 - x0), (outer[:, 1] - y0) / (y1 - y0)])
    out = dict(arrays)
    out["vertices_world"] = np.concatenate([arrays["vertices_world"], outer])
    out["faces"] = np.concatenate([arrays["faces"], ring])
    out["uv"] = np.concatenate([arrays["uv"], uv_outer])
    if "uv_texture" in arrays:
        # each outer vertex takes the texture coordinate of the edge node it lies beyond
        edge = ring[0::2, 0]
        out["uv_texture"] = np.concatenate([arrays["uv_texture"], arrays["uv_texture"][edge]])
    index = arrays.get("material_index", np.zeros(len(arrays["faces"]), np.int32))
    out["material_index"] = np.concatenate(
        [index, np.full(len(ring), n_materials, np.int32)]).astype(np.int32)
    assert len(out["uv"]) == n_inner + len(outer)
    return out


def far_tile(texture_rgb: np.ndarray) -> np.ndarray:
    """The far ground's tile: the detail tile averaged down FAR_TILE_REDUCTION times."""
    h, w = texture_rgb.shape[:2]
    size = (max(2, w // FAR_TILE_REDUCTION), max(2, h // FAR_TILE_REDUCTION))
    return cv2.resize(texture_rgb, size, interpolation=cv2.INTER_AREA)
