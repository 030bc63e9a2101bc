"""Compile the render path's numba kernels once, at installation (``designer warmup``).

numba compiles a kernel on its first call and caches the machine code beside the
module; without this, the first render on a new machine pays the compilation in every
worker at once (about 7 s per worker for the example's camera effects, measured with
``designer render --progress json``: the first frame's ``effects_seconds``). This runs
the texture bake and the example survey's effect chain (lens warp, vignetting, sensor,
motion blur, JPEG) on tiny images: the same kernels, the same argument types.
"""

from __future__ import annotations

import dataclasses

import numpy as np


def warm_up() -> None:
    """Run the bake and the example's effect chain once on tiny inputs."""
    from designer.effects.base import FrameContext
    from designer.effects.distortion_render import pinhole_render_camera
    from designer.effects.from_model import effects_from_model
    from designer.project import template
    from designer.project.interiors import render_interior
    from designer.render.texture_bake import bake_varied_texture
    from designer.scene.texture_variation import VariationImages

    rng = np.random.default_rng(0)
    texture = rng.integers(0, 256, (8, 8, 3), dtype=np.uint8)
    planes = np.full((4, 4, 3), 32768, np.uint16)
    baked = bake_varied_texture(texture, (2, 2), VariationImages(planes, planes, 0.01))
    from designer.render._bake_kernel import fold_light_bgr

    fold_light_bgr(baked, np.ones(baked.shape[:2], np.float32), np.empty_like(baked))
    project = template("survey").project
    camera = project.cameras[0]
    # the example camera at 1/48 of its size: 114 × 76 px, its lens and effects
    small = dataclasses.replace(camera, image_width_px=camera.image_width_px // 48,
                                image_height_px=camera.image_height_px // 48)
    interior = render_interior(small)
    render, warp = pinhole_render_camera(interior)
    chain = effects_from_model(project.effects, interior, warp=warp)
    image = rng.integers(0, 256, (render.image_height_px, render.image_width_px, 3),
                         dtype=np.uint8)
    context = FrameContext(gsd_m=0.05, flight_direction_uv=(0.0, 1.0), distance_m=50.0)
    chain.encode(image, 0, ".png", context)
    chain.encode(image, 0, ".jpg", context)
