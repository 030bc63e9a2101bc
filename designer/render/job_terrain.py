"""The terrain of a render job: its ground texture as the renderer draws it (one bake,
a detail and a coarse bake, tiles, or Cycles' node graph), its mesh with the far ground
ring and the bakes' files, the light map folded in where the sun is static."""

from __future__ import annotations

import hashlib
from dataclasses import dataclass, replace
from pathlib import Path

import cv2
import numpy as np

from designer.atomic import write_text_atomic
from designer.project import model as m
from designer.render.job_files import save_npz, write_png
from designer.render.job_spec import TEXTURE_UV_MAP, MaterialSpec, TiledTextureSpec
from designer.render.job_tiles import TiledTexture, needs_tiles
from designer.render.terrain_bake import (
    FAR_TEXTURE,
    TwoLevelBake,
    far_ground_arrays,
    far_tile,
    needs_two_levels,
    sample_light_rect,
    two_level_bake,
)
from designer.render.texture_bake import bake_size_px, bake_varied_texture, can_bake
from designer.scene.build import BuiltScene
from designer.scene.texture_variation import GAIN_ENCODING

#: the job's file of the varied ground texture baked into one image
BAKED_TEXTURE = "texture_varied.png"
#: … times the light map, for a static sun (one light map for every frame)
BAKED_LIT_TEXTURE = "texture_lit.png"
#: the job's file of the coarse bake over wide surroundings (render.terrain_bake)
BAKED_COARSE_TEXTURE = "texture_coarse.png"
#: a bake larger than this a side is written as an uncompressed TIFF (the terrain with
#: its surroundings: PNG encoding took 14 s for 8800², TIFF 0.2 s); smaller ones stay PNG
PNG_BAKE_MAX_PX = 4096


def bake_file(name: str, shape: tuple[int, ...]) -> str:
    """The job's file name of a bake of ``shape``: ``name`` (a .png), or its .tif twin."""
    return name if max(shape[:2]) <= PNG_BAKE_MAX_PX else name.rsplit(".", 1)[0] + ".tif"


@dataclass(frozen=True)
class TerrainTexture:
    """How the terrain's ground texture is drawn: its material(s), and at most one of a
    bake into one image, a detail and a coarse bake, or a bake in tiles (each written
    once the light maps are known, :func:`finish_terrain`)."""

    material: MaterialSpec | tuple[MaterialSpec, ...]
    baked: VariedBake | None = None
    two: TwoLevelBake | None = None
    tiled: TiledTexture | None = None


def terrain_texture(project: m.Project, scene: BuiltScene, job_dir: Path, poses,
                    frame_cameras, bake_texture: bool) -> TerrainTexture:
    """Write the texture tile (and, for the node graph, the variation's images) and
    choose how the ground texture is drawn. ``poses``: the images' CameraPose,
    ``frame_cameras`` each image's rendered interior (for the tiles each frame sees)."""
    write_png(job_dir / "texture.png", cv2.cvtColor(scene.texture_rgb, cv2.COLOR_RGB2BGR))
    material = MaterialSpec(texture="texture.png",
                            uv_tiles=tuple(float(t) for t in scene.texture_tiles),
                            interpolation=scene.interpolation.capitalize())
    repeat = (project.scene.texture.repeat_X, project.scene.texture.repeat_Y)
    if (bake_texture and scene.variation is not None
            and can_bake(scene.texture_rgb.shape, scene.texture_tiles)):
        # the blend of the three lookups baked into one image: one lookup per sample
        # (baked when written, unless the job folder holds it from the same inputs)
        baked = VariedBake(scene.texture_rgb, scene.texture_tiles, scene.variation,
                           scene.interpolation)
        return TerrainTexture(MaterialSpec(texture=bake_file(BAKED_TEXTURE, baked.shape),
                                           uv_tiles=(1.0, 1.0),
                                           interpolation="Linear", extension="EXTEND",
                                           texture_colorspace="Non-Color",
                                           strength=material.strength * GAIN_ENCODING),
                              baked=baked)
    if bake_texture and needs_two_levels(scene, repeat):
        two = two_level_bake(scene, repeat, project.scene.texture.variation)
        baked_material = MaterialSpec(texture=bake_file(BAKED_TEXTURE, two.inner.shape),
                                      uv_tiles=(1.0, 1.0), interpolation="Linear",
                                      extension="EXTEND", texture_colorspace="Non-Color",
                                      strength=material.strength * GAIN_ENCODING)
        return TerrainTexture((replace(baked_material, uv_map=TEXTURE_UV_MAP),
                               replace(baked_material, texture=BAKED_COARSE_TEXTURE)),
                              two=two)
    if bake_texture and needs_tiles(scene):
        # too wide for one bake: tiles of the same bake, each frame loading those it sees
        tiled = TiledTexture(scene, job_dir, material.strength, poses, frame_cameras)
        return TerrainTexture(tiled.materials(), tiled=tiled)
    if scene.variation is not None:
        var = scene.variation
        write_png(job_dir / "variation.png", cv2.cvtColor(var.shading, cv2.COLOR_RGB2BGR))
        write_png(job_dir / "variation_warp.png", cv2.cvtColor(var.warp, cv2.COLOR_RGB2BGR))
        # the image stores gain / GAIN_ENCODING; the emission strength scales it back
        material = replace(material, variation="variation.png",
                           variation_warp="variation_warp.png",
                           variation_warp_uv=var.warp_bound_uv,
                           strength=material.strength * GAIN_ENCODING)
    return TerrainTexture(material)


def write_terrain(scene: BuiltScene, texture: TerrainTexture, origin: np.ndarray,
                  job_dir: Path) -> MaterialSpec | tuple[MaterialSpec, ...]:
    """Write the terrain's mesh (local: world − ``origin``; with the far ground ring where
    images look towards the horizon) and return its material(s), by face."""
    terrain_material = texture.material
    terrain_uv = {}
    if texture.two is not None:
        terrain_uv = {"uv_texture": texture.two.inner_uv,
                      "material_index": texture.two.material_index}
    if texture.tiled is not None:
        terrain_uv = {"material_index": texture.tiled.face_slot}
    if scene.texture_uv is not None:
        # An orthophoto: its own texture coordinates (from its geotransform), no tiling,
        # edge texels held beyond the image; the light map keeps the terrain's uv.
        terrain_material = replace(terrain_material, uv_tiles=(1.0, 1.0),
                                   uv_map=TEXTURE_UV_MAP, extension="EXTEND")
        terrain_uv = {"uv_texture": scene.texture_uv}
    arrays = {"vertices_world": scene.terrain.vertices_world, "faces": scene.terrain.faces,
              "uv": scene.terrain.uv, **terrain_uv}
    if scene.growth.horizon and scene.heightfield is not None:
        # images look towards the horizon: a far ground ring out to it, a sky above it
        materials = terrain_material if isinstance(terrain_material, tuple) else (
            terrain_material,)
        write_png(job_dir / FAR_TEXTURE, cv2.cvtColor(far_tile(scene.texture_rgb),
                                                      cv2.COLOR_RGB2BGR))
        far = MaterialSpec(texture=FAR_TEXTURE,
                           uv_tiles=tuple(float(t) for t in scene.texture_tiles),
                           interpolation="Linear")
        if scene.texture_uv is not None:  # an orthophoto's edge colours
            far = materials[0]
        arrays = far_ground_arrays(scene, arrays, len(materials))
        terrain_material = (*materials, far)
    world = arrays.pop("vertices_world")
    save_npz(job_dir / "terrain.npz", vertices_local=world - origin, **arrays)
    return terrain_material


def finish_terrain(texture: TerrainTexture, scene: BuiltScene, objects: list,
                   job_dir: Path, lit: bool, contexts: list[dict]
                   ) -> tuple[list, TiledTextureSpec | None]:
    """Write the bakes, with ``lit`` (one sun for every frame) the terrain's light map
    folded in: (the objects with the terrain's materials as written, the tiles' spec or
    None). A tiled bake names each frame's tiles in its context (``contexts``, one dict
    per frame, filled in)."""
    if texture.baked is not None:
        objects = _write_bake(texture.baked, objects, job_dir, lit=lit)
    if texture.two is not None:
        objects = _write_two_bakes(texture.two, scene.heightfield.extent_m, objects,
                                   job_dir, lit=lit)
    tiled_spec = None
    if texture.tiled is not None:
        # with a sun over time the light steps' materials keep their light maps
        objects, tiled_spec = texture.tiled.finish(objects, lit=lit)
        for i, tiles in enumerate(texture.tiled.seen):
            contexts[i]["texture_tiles"] = tiles
    return objects, tiled_spec


class VariedBake:
    """The varied texture's bake (:func:`bake_varied_texture`), computed when first
    asked for; ``key`` digests everything it depends on (the inputs and the code)."""

    def __init__(self, texture_rgb: np.ndarray, tiles, variation, interpolation: str) -> None:
        self.args = (texture_rgb, tiles, variation, interpolation)
        W, H = bake_size_px(texture_rgb.shape, tiles)
        self.shape = (H, W, 3)
        self._image: np.ndarray | None = None
        h = hashlib.sha256()
        for part in (texture_rgb, variation.shading, variation.warp):
            a = np.ascontiguousarray(part)
            h.update(f"{a.dtype}{a.shape}".encode() + a.tobytes())
        h.update(repr((tuple(float(t) for t in tiles), float(variation.warp_bound_uv),
                       interpolation)).encode())
        for module in ("texture_bake.py", "_bake_kernel.py", "job_terrain.py"):
            h.update((Path(__file__).parent / module).read_bytes())
        self.key = h.hexdigest()

    @property
    def image(self) -> np.ndarray:
        if self._image is None:
            self._image = bake_varied_texture(*self.args)
        return self._image


def _kept(path: Path, key: str) -> bool:
    """True if ``path`` was written from inputs of digest ``key`` (its ``.key`` file)."""
    key_path = path.with_name(path.name + ".key")
    return path.is_file() and key_path.is_file() and key_path.read_text() == key


def _write_keyed(path: Path, image: np.ndarray, key: str) -> None:
    """Write a bake (BGR) and then its key: a bake without its key is written again."""
    key_path = path.with_name(path.name + ".key")
    key_path.unlink(missing_ok=True)
    write_png(path, image, fast=True)
    write_text_atomic(key_path, key)


def _write_bake(bake: VariedBake, objects: list, job_dir: Path, lit: bool) -> list:
    """Write the baked varied texture; with ``lit`` (one sun for every frame) the
    terrain's light map is multiplied in, so Cycles makes one texture lookup per sample
    instead of two. The light map is sampled at the bake's texel centres as the renderer
    samples it (bilinear, edge texels extended over the same UV square). A file the job
    folder holds from the same inputs (the bake's key, and the light map's bytes) is kept:
    a resumed render does not bake again."""
    terrain = next((o for o in objects if o.name == "terrain"), None)
    material = terrain.materials[0] if terrain is not None else None
    if not lit or material is None or material.lightmap is None:
        path = job_dir / bake_file(BAKED_TEXTURE, bake.shape)
        if not _kept(path, bake.key):
            _write_keyed(path, cv2.cvtColor(bake.image, cv2.COLOR_RGB2BGR), bake.key)
        return objects
    light_bytes = (job_dir / material.lightmap).read_bytes()
    lit_file = bake_file(BAKED_LIT_TEXTURE, bake.shape)
    key = hashlib.sha256(bake.key.encode() + light_bytes).hexdigest()
    if not _kept(job_dir / lit_file, key):
        baked = bake.image
        light = cv2.imdecode(np.frombuffer(light_bytes, np.uint8), cv2.IMREAD_UNCHANGED)
        H, W = baked.shape[:2]
        # cv2's linear resize samples the source at (x + 0.5) · scale − 0.5, edges
        # replicated: Blender's texel-centre convention with EXTEND
        light = cv2.resize(light.astype(np.float32) / np.float32(65535.0), (W, H),
                           interpolation=cv2.INTER_LINEAR)
        from designer.render._bake_kernel import fold_light_bgr

        lit_bgr = np.empty_like(baked)
        fold_light_bgr(baked, np.ascontiguousarray(light, np.float32), lit_bgr)
        _write_keyed(job_dir / lit_file, lit_bgr, key)
    folded = replace(material, texture=lit_file, lightmap=None)
    return [replace(o, materials=(folded, *o.materials[1:])) if o is terrain else o
            for o in objects]


def _write_two_bakes(two, extent_m, objects: list, job_dir: Path, lit: bool) -> list:
    """Write the detail and coarse bakes (render.terrain_bake); with ``lit`` the light map
    is folded into each, sampled over the part of the terrain each covers."""
    terrain = next(o for o in objects if o.name == "terrain")
    rects = (two.inner_rect_uv(extent_m), (0.0, 1.0, 0.0, 1.0))
    light = None
    if lit and terrain.materials[0].lightmap is not None:
        light = cv2.imread(str(job_dir / terrain.materials[0].lightmap),
                           cv2.IMREAD_UNCHANGED).astype(np.float32) / np.float32(65535.0)
    from designer.render._bake_kernel import fold_light_bgr

    folded = []
    for material, bake, rect in zip(terrain.materials[:2], (two.inner, two.coarse), rects,
                                    strict=True):
        if light is None:
            write_png(job_dir / material.texture, cv2.cvtColor(bake, cv2.COLOR_RGB2BGR),
                      fast=True)
            folded.append(material)
            continue
        H, W = bake.shape[:2]
        lit_bgr = np.empty_like(bake)
        for r in range(0, H, 256):  # bands of rows: the light's float copy stays small
            r1 = min(r + 256, H)
            top = rect[3] - r / H * (rect[3] - rect[2])
            bottom = rect[3] - r1 / H * (rect[3] - rect[2])
            band = sample_light_rect(light, (r1 - r, W), (rect[0], rect[1], bottom, top))
            fold_light_bgr(bake[r:r1], np.ascontiguousarray(band, np.float32),
                           lit_bgr[r:r1])
        name = material.texture.replace("texture_", "texture_lit_", 1)
        write_png(job_dir / name, lit_bgr, fast=True)
        folded.append(replace(material, texture=name, lightmap=None))
    folded += terrain.materials[2:]  # the far ground keeps its own texture and light map
    return [replace(o, materials=tuple(folded)) if o is terrain else o for o in objects]
