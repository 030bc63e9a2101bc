"""The largest (and smallest) scene the scene builder makes: generated texture tiles,
texture-variation images and procedural terrain grids.

``designer check`` refuses a project beyond them before anything is built, and the
scene builder (``designer.scene.build``, ``designer.scene.texture_variation``) holds to
the same numbers; they live at the model's layer so both read one value.
"""

from __future__ import annotations

#: generated texture tiles have this many texels per side, at least and at most
MIN_TEXTURE_TEXELS = 16
MAX_TEXTURE_TEXELS = 8192
#: largest side of a texture variation image (px, designer.scene.texture_variation)
VARIATION_MAX_PX = 2048
#: largest procedural terrain grid (nodes)
MAX_TERRAIN_NODES = 64e6
#: relative tolerance of "the grid spacing divides the extent into whole cells"
GRID_TOL = 1e-9

#: the largest side of the varied texture's one bake (px; designer.render.texture_bake):
#: beyond it the renderer bakes it in tiles (designer.render.tiled_bake) — a 12 288² bake
#: is 1.2 GB of half floats per render worker
MAX_BAKE_PX = 12288
