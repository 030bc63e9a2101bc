"""The render job's part of a ground texture baked in tiles (:mod:`designer.render.
tiled_bake`): the terrain's materials and face indices, each frame's tiles, the coarse
bake and the job's :class:`~designer.render.job_spec.TiledTextureSpec`. The tiles
themselves are baked by the workers, as their frames need them."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import cv2
import numpy as np

from designer.render.job_files import write_png
from designer.render.job_spec import MaterialSpec, TiledTextureSpec
from designer.render.terrain_bake import COARSE_BAKE_PX
from designer.render.texture_bake import bake_size_px, bake_varied_texture, can_bake
from designer.render.tiled_bake import (
    TileGrid,
    face_tiles,
    frame_tiles,
    light_window,
    remove_stale_tiles,
    slot_of,
    slot_shape,
    tile_grid,
    tiles_digest,
)
from designer.scene.build import BuiltScene
from designer.scene.texture_variation import GAIN_ENCODING

#: the job's file of the coarse bake the tiles' materials show where no tile is loaded
TILED_COARSE_TEXTURE = "texture_tiled_coarse.tif"
VARIATION = "variation.png"
VARIATION_WARP = "variation_warp.png"


#: a terrain whose faces are wider than this share of a tile is not tiled (a flat
#: terrain's two triangles would make every tile hold the whole bake): the node graph
MAX_FACE_SHARE = 0.25


def needs_tiles(scene: BuiltScene) -> bool:
    """True when a varied texture over a height-field terrain of small faces is too wide
    for one bake: the render bakes it in tiles (where it used to keep Cycles' node
    graph)."""
    if (scene.variation is None or scene.heightfield is None or scene.texture_uv is not None
            or can_bake(scene.texture_rgb.shape, scene.texture_tiles)):
        return False
    W, H = bake_size_px(scene.texture_rgb.shape, scene.texture_tiles)
    grid = tile_grid((W, H), scene.terrain.uv, scene.terrain.faces)
    return grid.pad_px <= MAX_FACE_SHARE * grid.core_px


class TiledTexture:
    """A tiled bake being prepared: :meth:`materials` for the terrain, then
    :meth:`finish` once the light maps are known."""

    def __init__(self, scene: BuiltScene, job_dir: Path, strength: float, poses,
                 interiors) -> None:
        """``poses``: the images' CameraPose, ``interiors`` their rendered cameras."""
        self.scene = scene
        self.job_dir = Path(job_dir)
        W, H = bake_size_px(scene.texture_rgb.shape, scene.texture_tiles)
        terrain = scene.terrain
        self.grid: TileGrid = tile_grid((W, H), terrain.uv, terrain.faces)
        hf = scene.heightfield
        #: per image, the tiles it sees
        self.seen = frame_tiles(self.grid, hf.extent_m, hf,
                                np.array([p.C_world for p in poses]).reshape(-1, 3),
                                np.array([p.R_cam_to_world for p in poses]).reshape(-1, 3, 3),
                                interiors)
        self.slots = slot_shape(self.grid, self.seen)
        #: each terrain face's material: the slot of its tile
        self.face_slot = slot_of(self.grid, self.slots,
                                 face_tiles(self.grid, terrain.uv, terrain.faces))
        var = scene.variation
        write_png(self.job_dir / VARIATION, cv2.cvtColor(var.shading, cv2.COLOR_RGB2BGR))
        write_png(self.job_dir / VARIATION_WARP, cv2.cvtColor(var.warp, cv2.COLOR_RGB2BGR))
        # the tiles' materials start on the coarse bake; the worker swaps tiles in
        self.material = MaterialSpec(texture=TILED_COARSE_TEXTURE, uv_tiles=(1.0, 1.0),
                                     interpolation="Linear", extension="EXTEND",
                                     texture_colorspace="Non-Color",
                                     strength=strength * GAIN_ENCODING)

    def materials(self) -> tuple[MaterialSpec, ...]:
        """One material per slot (slot s is material s)."""
        return (self.material,) * (self.slots[0] * self.slots[1])

    def finish(self, objects: list, lit: bool) -> tuple[list, TiledTextureSpec]:
        """Write the coarse bake (with the light map folded in when ``lit``: one sun for
        every frame) and return the objects with the tiles' materials as the worker
        builds them, and the job's spec of the tiles."""
        scene = self.scene
        terrain = next(o for o in objects if o.name == "terrain")
        n = self.slots[0] * self.slots[1]
        lightmap = terrain.materials[0].lightmap if lit else None
        light = None
        if lightmap is not None:
            light = cv2.imread(str(self.job_dir / lightmap), cv2.IMREAD_UNCHANGED)
        coarse = self._coarse(light)
        write_png(self.job_dir / TILED_COARSE_TEXTURE, cv2.cvtColor(coarse, cv2.COLOR_RGB2BGR),
                  fast=True)
        var = scene.variation
        digest = tiles_digest(scene.texture_rgb, var.shading, var.warp, var.warp_bound_uv,
                              tuple(float(t) for t in scene.texture_tiles),
                              scene.interpolation, self.grid, light)
        remove_stale_tiles(self.job_dir, digest)
        spec = TiledTextureSpec(
            texture="texture.png", uv_tiles=tuple(float(t) for t in scene.texture_tiles),
            interpolation=scene.interpolation, variation=VARIATION,
            variation_warp=VARIATION_WARP, variation_warp_uv=float(var.warp_bound_uv),
            full_px=self.grid.full_px, core_px=self.grid.core_px, pad_px=self.grid.pad_px,
            slots=self.slots, digest=digest, coarse=TILED_COARSE_TEXTURE, lightmap=lightmap)
        if lightmap is not None:
            folded = tuple(replace(m, lightmap=None) for m in terrain.materials[:n])
            terrain = replace(terrain, materials=(*folded, *terrain.materials[n:]))
            objects = [terrain if o.name == "terrain" else o for o in objects]
        return objects, spec

    def _coarse(self, light: np.ndarray | None) -> np.ndarray:
        """The bake over the whole terrain from the detail tile averaged down to fit
        COARSE_BAKE_PX a side (render.terrain_bake's coarse bake), lit when ``light``."""
        scene = self.scene
        h, w = scene.texture_rgb.shape[:2]
        tx, ty = scene.texture_tiles
        factor = min(1.0, COARSE_BAKE_PX / max(tx * w, ty * h))
        small = (max(2, round(w * factor)), max(2, round(h * factor)))
        tile = cv2.resize(scene.texture_rgb, small, interpolation=cv2.INTER_AREA)
        coarse = bake_varied_texture(tile, (tx, ty), scene.variation, scene.interpolation)
        if light is None:
            return coarse
        H, W = coarse.shape[:2]
        band = light_window(light.astype(np.float32) / np.float32(65535.0), (W, H),
                            (0, 0, H, W))
        return np.clip(np.rint(coarse.astype(np.float32) * band[:, :, None]), 0,
                       65535).astype(np.uint16)
