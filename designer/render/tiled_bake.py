"""A varied ground texture too wide for one bake: a grid of baked tiles, each frame
loading only the tiles it sees.

The varied texture is baked into one image (:mod:`designer.render.texture_bake`) when
that fits :data:`~designer.render.texture_bake.MAX_BAKE_PX` a side. Wider terrains (a
500 m terrain at 2.5 cm texels is 20 000 px a side; 4 GB as half floats) used to fall
back to Cycles' node graph, three to six times the render time of the bake. Here the
same bake — the same texel grid over the terrain's UV square, the same values — is cut
into tiles of :data:`TILE_CORE_PX` a side:

* each tile is a window of the whole bake grown by ``pad_px`` texels on every side (the
  texels of its neighbours, or the edge texels held past the terrain's edge), so a
  bilinear lookup anywhere in a face assigned to the tile reads the same four texels as
  in the whole bake: no seam in colour or place;
* each terrain face looks up the tile its centre lies in, through a material "slot"
  shared by tiles far apart (:func:`slot_shape`); before each frame the worker gives
  each slot the tile of it that frame sees (:func:`frame_tiles`, from rays of its
  image's border and inside to the ground), with the scale and offset that map the
  terrain's UV onto it, or the coarse bake over the whole terrain where it sees none;
* a tile is baked by the first worker that needs it (:func:`ensure_tile`) into the job
  folder, its name carrying a digest of everything it depends on.

Only geometry (which tile a face and a frame use) lives here besides the bake of a tile:
no bpy.
"""

from __future__ import annotations

import hashlib
import math
import os
from dataclasses import dataclass
from pathlib import Path

import cv2
import numpy as np

#: the side of a tile's own texels (px): 51 m at 2.5 cm; a frame of the example survey
#: (about 75 × 50 m on the ground) sees about six of them
TILE_CORE_PX = 2048
#: the job's file names of the tiles: texture_tile_{digest}_{k}.tif
TILE_PREFIX = "texture_tile_"
#: rays per image side (the border) and per row and column inside, to find what a frame
#: sees
BORDER_RAYS = 16
INNER_RAYS = 6
#: the seen ground is grown by this share of its own size (and at least MARGIN_M) before
#: the tiles it touches are chosen: the ground between rays and the camera's motion
MARGIN_SHARE = 0.05
MARGIN_M = 1.0
#: slot rows and columns beyond the most one frame sees: the slots a frame leaves free
#: take the tiles its worker's next frames will want (:func:`slots_to_show`), so a line
#: of frames crosses two tile rows per swap instead of one (at 1.2 km, 4,935 frames in
#: one worker: 279 frames swap, against 989 with no spare slots)
SPARE_SLOTS = 2
#: the worker's next frames whose tiles a swap loads into the free slots
LOOK_AHEAD_FRAMES = 20


@dataclass(frozen=True)
class TileGrid:
    """Tiles of a bake of ``full_px`` (W, H) texels over the UV square: ``columns`` ×
    ``rows`` tiles of ``core_px`` texels a side (the last ones shorter), each stored with
    ``pad_px`` texels more on every side. Tile k = row · columns + column, row 0 north."""

    full_px: tuple[int, int]
    core_px: int
    pad_px: int

    @property
    def columns(self) -> int:
        return math.ceil(self.full_px[0] / self.core_px)

    @property
    def rows(self) -> int:
        return math.ceil(self.full_px[1] / self.core_px)

    @property
    def count(self) -> int:
        return self.columns * self.rows

    def window(self, k: int) -> tuple[int, int, int, int]:
        """(first row, first column, rows, columns) of tile k's stored image in the whole
        bake's texels (row 0 north; may reach past the bake's edges)."""
        row, col = divmod(k, self.columns)
        W, H = self.full_px
        c0, r0 = col * self.core_px, row * self.core_px
        c1, r1 = min(W, c0 + self.core_px), min(H, r0 + self.core_px)
        p = self.pad_px
        return r0 - p, c0 - p, r1 - r0 + 2 * p, c1 - c0 + 2 * p

    def uv_transform(self, k: int) -> tuple[tuple[float, float], tuple[float, float]]:
        """(scale, offset): tile k's own texture coordinates are uv · scale + offset."""
        r0, c0, h, w = self.window(k)
        W, H = self.full_px
        return (W / w, H / h), (-c0 / w, 1.0 - (H - r0) / h)

    def tile_of_uv(self, u: np.ndarray, v: np.ndarray) -> np.ndarray:
        """The tile (int) whose core holds each UV point (points outside: the nearest)."""
        W, H = self.full_px
        col = np.clip(np.floor(np.asarray(u) * W / self.core_px), 0, self.columns - 1)
        row = np.clip(np.floor((1.0 - np.asarray(v)) * H / self.core_px), 0, self.rows - 1)
        return (row * self.columns + col).astype(np.int32)

    def tiles_in(self, u0: float, u1: float, v0: float, v1: float) -> tuple[int, ...]:
        """Every tile whose core meets the UV rectangle [u0, u1] × [v0, v1]."""
        W, H = self.full_px
        c0, c1 = (int(np.clip(math.floor(u * W / self.core_px), 0, self.columns - 1))
                  for u in (u0, u1))
        r0, r1 = (int(np.clip(math.floor((1.0 - v) * H / self.core_px), 0, self.rows - 1))
                  for v in (v1, v0))
        return tuple(r * self.columns + c for r in range(r0, r1 + 1) for c in range(c0, c1 + 1))


def tile_grid(full_px: tuple[int, int], uv: np.ndarray, faces: np.ndarray,
              core_px: int | None = None) -> TileGrid:
    """The tiles of a bake of ``full_px`` (W, H) for a mesh of per-vertex ``uv`` (N, 2)
    and ``faces`` (F, k): padded by the widest face (in texels) and two texels, so every
    face lies within the stored image of the tile its centre is in; ``core_px`` defaults
    to TILE_CORE_PX."""
    W, H = full_px
    core_px = core_px or TILE_CORE_PX
    corners = uv[faces]
    span = np.ptp(corners, axis=1) * np.array([W, H])
    pad = math.ceil(float(span.max(initial=0.0))) + 2
    return TileGrid((int(W), int(H)), int(core_px), pad)


def face_tiles(grid: TileGrid, uv: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """(F,) the tile of each face: the one its centre (mean UV of its corners) is in."""
    centre = uv[faces].mean(axis=1)
    return grid.tile_of_uv(centre[:, 0], centre[:, 1])


def frame_tiles(grid: TileGrid, extent_m: tuple[float, float, float, float], heightfield,
                C_world: np.ndarray, R_cam_to_world: np.ndarray, interiors) -> list[tuple]:
    """Per image, the tiles it sees: those under the ground its rays reach (its border and
    inside, the rendered interior ``interiors[i]``), grown by MARGIN_SHARE of that ground's
    size and MARGIN_M. Rays that miss the terrain add nothing (that ground, seen towards
    the horizon, shows the coarse bake). ``C_world`` (N, 3) m, ``R_cam_to_world`` (N, 3, 3)."""
    from designer.core.projection import pixel_rays_world
    from designer.core.raycast import raycaster_of

    x0, x1, y0, y1 = extent_m
    caster = raycaster_of(heightfield)
    out: list[tuple] = []
    rays_of: dict[int, np.ndarray] = {}
    for C, R, interior in zip(C_world, R_cam_to_world, interiors, strict=True):
        key = id(interior)
        if key not in rays_of:
            rays_of[key] = pixel_rays_world(_probe_pixels(interior), np.eye(3), interior)
        rays = rays_of[key] @ np.asarray(R).T
        hit = caster.first_hit(np.repeat(np.asarray(C)[None], len(rays), axis=0), rays)
        hit = hit[np.isfinite(hit[:, 0])]
        if not len(hit):
            out.append(())
            continue
        lo, hi = hit[:, :2].min(axis=0), hit[:, :2].max(axis=0)
        grow = np.maximum(MARGIN_M, MARGIN_SHARE * (hi - lo))
        lo, hi = lo - grow, hi + grow
        u0, u1 = (lo[0] - x0) / (x1 - x0), (hi[0] - x0) / (x1 - x0)
        v0, v1 = (lo[1] - y0) / (y1 - y0), (hi[1] - y0) / (y1 - y0)
        if u1 < 0 or u0 > 1 or v1 < 0 or v0 > 1:
            out.append(())
            continue
        out.append(grid.tiles_in(u0, u1, v0, v1))
    return out


def _probe_pixels(interior) -> np.ndarray:
    """Pixel positions (M, 2) on an image's border and a grid inside it."""
    from designer.core.projection import edge_pixels

    W, H = interior.image_size_px
    border = edge_pixels(interior, BORDER_RAYS)
    g = (np.arange(INNER_RAYS) + 0.5) / INNER_RAYS
    inner = np.column_stack([np.tile(g * W, INNER_RAYS), np.repeat(g * H, INNER_RAYS)])
    return np.concatenate([border, inner])


def slot_shape(grid: TileGrid, seen, spare: int = SPARE_SLOTS) -> tuple[int, int]:
    """(rows, columns) of the material slots: the most tile rows and columns any one
    frame sees (``seen``: each frame's tiles) and ``spare`` more, so the tiles one frame
    sees all have slots of their own and some are left for the next frames' tiles. Tile
    (r, c) is shown by slot (r mod rows, c mod columns): Cycles compiles every
    material's shader whenever one changes, so a few slots cost a few shaders where a
    material per tile cost hundreds (0.8 s a frame at 1.2 km)."""
    rows = columns = 1
    for tiles in seen:
        if tiles:
            r, c = np.divmod(np.asarray(tiles), grid.columns)
            rows, columns = max(rows, int(np.ptp(r)) + 1), max(columns, int(np.ptp(c)) + 1)
    return min(rows + spare, grid.rows), min(columns + spare, grid.columns)


def slots_to_show(grid: TileGrid, slots: tuple[int, int], shown: dict[int, int], tiles,
                  upcoming=()) -> dict[int, int]:
    """The tile each slot is to show for a frame that sees ``tiles``: slot → tile, for
    the slots that change from ``shown`` (slot → tile shown now). When the frame changes
    any slot, the slots it does not see take the tiles of the ``upcoming`` frames (each
    a tuple of tiles, in the order the worker renders them; the first frame to want a
    slot has it): every change of a slot is a Cycles scene update of the whole terrain
    (its mesh and BVH, about 10 CPU s at 1.2 km, whether one slot changes or many), so
    the changes a line of frames needs are made in as few frames as the slots allow. A
    slot no frame wants keeps its tile."""
    wanted = dict(zip(slot_of(grid, slots, list(tiles or ())).tolist(), tiles or (),
                      strict=True))
    if not any(shown.get(slot) != k for slot, k in wanted.items()):
        return {}
    for later in upcoming:
        later = list(later or ())
        for slot, k in zip(slot_of(grid, slots, later).tolist(), later, strict=True):
            wanted.setdefault(slot, k)
    return {slot: k for slot, k in wanted.items() if shown.get(slot) != k}


def slot_of(grid: TileGrid, slots: tuple[int, int], tiles) -> np.ndarray:
    """The slot (material) of each tile: (r mod rows) · columns + (c mod columns)."""
    r, c = np.divmod(np.asarray(tiles), grid.columns)
    return ((r % slots[0]) * slots[1] + c % slots[1]).astype(np.int32)


def swap_frames(grid: TileGrid, slots: tuple[int, int], seen,
                look_ahead: int = LOOK_AHEAD_FRAMES) -> int:
    """How many of the frames one worker renders in the order of ``seen`` (each frame's
    tiles) change any slot (:func:`slots_to_show`, with ``look_ahead`` next frames)."""
    seen = list(seen)
    shown: dict[int, int] = {}
    count = 0
    for i, tiles in enumerate(seen):
        change = slots_to_show(grid, slots, shown, tiles, seen[i + 1:i + 1 + look_ahead])
        count += bool(change)
        shown.update(change)
    return count


def tiles_digest(*parts) -> str:
    """A digest of the inputs of a tiled bake (arrays, bytes, reprs) and of the code."""
    h = hashlib.sha256()
    for part in parts:
        if isinstance(part, np.ndarray):
            a = np.ascontiguousarray(part)
            h.update(f"{a.dtype}{a.shape}".encode() + a.tobytes())
        elif isinstance(part, bytes):
            h.update(part)
        else:
            h.update(repr(part).encode())
    here = Path(__file__).parent
    for module in ("tiled_bake.py", "texture_bake.py", "_bake_kernel.py"):
        h.update((here / module).read_bytes())
    return h.hexdigest()[:16]


def tile_file(digest: str, k: int) -> str:
    """The job's file name of tile k of the bake of ``digest``."""
    return f"{TILE_PREFIX}{digest}_{k}.tif"


def bake_tile(spec, grid: TileGrid, k: int, base: Path) -> np.ndarray:
    """Tile k (rows, columns, 3) uint16 RGB: the window of the whole bake (and the light
    map folded in when ``spec.lightmap``), from the job's files of ``spec``
    (:class:`~designer.render.job_spec.TiledTextureSpec`)."""
    from designer.render.texture_bake import bake_varied_texture
    from designer.scene.texture_variation import VariationImages

    texture = cv2.cvtColor(cv2.imread(str(base / spec.texture), cv2.IMREAD_COLOR),
                           cv2.COLOR_BGR2RGB)

    def rgb16(name):
        return cv2.cvtColor(cv2.imread(str(base / name), cv2.IMREAD_UNCHANGED),
                            cv2.COLOR_BGR2RGB)

    variation = VariationImages(rgb16(spec.variation), rgb16(spec.variation_warp),
                                spec.variation_warp_uv)
    window = grid.window(k)
    tile = bake_varied_texture(texture, tuple(spec.uv_tiles), variation,
                               spec.interpolation, window)
    if spec.lightmap is None:
        return tile
    light = cv2.imread(str(base / spec.lightmap), cv2.IMREAD_UNCHANGED)
    band = light_window(light.astype(np.float32) / np.float32(65535.0), grid.full_px, window)
    return np.clip(np.rint(tile.astype(np.float32) * band[:, :, None]), 0,
                   65535).astype(np.uint16)


def light_window(light: np.ndarray, full_px: tuple[int, int],
                 window: tuple[int, int, int, int]) -> np.ndarray:
    """The light map (Lh, Lw) float32 over the UV square read bilinearly (edge texels
    held, as Blender reads it) at the centres of a window (row, column, rows, columns) of
    a bake of ``full_px`` (W, H) texels: each texel from its place in the whole bake, so
    tiles agree where they overlap."""
    W, H = full_px
    r0, c0, rows, cols = window
    Lh, Lw = light.shape
    j = np.clip(np.arange(c0, c0 + cols), 0, W - 1)
    i = np.clip(np.arange(r0, r0 + rows), 0, H - 1)
    px = np.clip((j + 0.5) * Lw / W - 0.5, 0, Lw - 1)
    py = np.clip((i + 0.5) * Lh / H - 0.5, 0, Lh - 1)
    jx = np.minimum(px.astype(int), max(Lw - 2, 0))
    iy = np.minimum(py.astype(int), max(Lh - 2, 0))
    wx = (px - jx).astype(np.float32)
    wy = (py - iy).astype(np.float32)[:, None]
    jn, inn = np.minimum(jx + 1, Lw - 1), np.minimum(iy + 1, Lh - 1)
    rows_ = light[:, jx] * (1 - wx) + light[:, jn] * wx
    return rows_[iy] * (1 - wy) + rows_[inn] * wy


def ensure_tile(spec, k: int, base: Path) -> Path:
    """The path of tile k in the job folder ``base``, baked and written first if absent
    (written under a temporary name and renamed: workers that bake the same tile at once
    each write whole files)."""
    path = base / tile_file(spec.digest, k)
    if path.is_file():
        return path
    grid = TileGrid(tuple(spec.full_px), spec.core_px, spec.pad_px)
    tile = bake_tile(spec, grid, k, base)
    tmp = path.with_name(f".{path.stem}.{os.getpid()}.tif")
    if not cv2.imwrite(str(tmp), cv2.cvtColor(tile, cv2.COLOR_RGB2BGR),
                       [cv2.IMWRITE_TIFF_COMPRESSION, 1]):
        raise OSError(f"could not write {tmp}")
    os.replace(tmp, path)
    return path


def remove_stale_tiles(job_dir: Path, digest: str) -> None:
    """Delete tiles of other bakes (an earlier preparation of this job folder)."""
    for path in job_dir.glob(f"{TILE_PREFIX}*.tif"):
        if not path.name.startswith(f"{TILE_PREFIX}{digest}_"):
            path.unlink(missing_ok=True)
