"""The project model's ``Effects`` → an ``EffectChain``: each element the project asks for
is built by the effect registered for its model class (``designer.effects.registry``), so
a new effect is its model class and its own module."""

from __future__ import annotations

import dataclasses

from designer.core.interior import InteriorOrientation
from designer.effects.base import CameraContext
from designer.effects.chain import EffectChain
from designer.effects.distortion_render import DistortionWarp, LensDistortion, pinhole_render_camera
from designer.effects.registry import registered_effects
from designer.project import model as m


def effects_from_model(
    effects: m.Effects | None,
    interior: InteriorOrientation,
    *,
    warp: DistortionWarp | None = None,
    oversample: int = 1,
) -> EffectChain:
    """The chain for a camera ``interior`` (with its distortion) and the project's effects.

    Distortion comes from the camera: if ``interior`` has any, the chain starts with the
    warp from the pinhole render (``warp``, e.g. loaded from a cache, must have been made
    for ``interior``; otherwise it is computed here with ``oversample``). The images
    given to the chain are then renders of ``chain.warp.render_interior``. Every other
    element of ``effects`` that is not None becomes the registered effect's
    ``from_model(element, CameraContext(interior, warp's oversample or 1))``; the chain
    orders them (``designer.effects.base.EFFECT_ORDER``).
    """
    chain = []
    if warp is None:
        _, warp = pinhole_render_camera(interior, oversample)
    elif not warp.matches(interior):
        raise ValueError("the distortion warp was made for another camera")
    if warp is not None:
        chain.append(LensDistortion(warp))
    if effects is None:
        return EffectChain(chain)
    camera = CameraContext(interior, 1.0 if warp is None else float(warp.oversample))
    registry = registered_effects()
    for field in dataclasses.fields(effects):
        element = getattr(effects, field.name)
        if element is not None:
            chain.append(registry[type(element)].from_model(element, camera))
    return EffectChain(chain)
