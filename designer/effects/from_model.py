"""The project model's ``Effects`` → an ``EffectChain`` (the only module here that knows
the model, so the model can grow without touching the effects)."""

from __future__ import annotations

from designer.core.interior import InteriorOrientation
from designer.effects.chain import EffectChain
from designer.effects.distortion_render import DistortionWarp, LensDistortion, pinhole_render_camera
from designer.effects.jpeg import JpegCompression
from designer.effects.motion import LinearMotionBlur
from designer.effects.optics import GaussianBlur, RadialVignetting, ThinLensDefocus
from designer.effects.sensor import GaussianNoiseDN, SensorModel
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
    given to the chain are then renders of ``chain.warp.render_interior``.
    Vignetting gives gain [cos⁴ θ] × (1 − corner_falloff ρ² + rho4 ρ⁴ + rho6 ρ⁶) (ρ = 1 at
    the farthest image corner); ``sigma_dn`` is in 8-bit digital numbers; motion blur
    needs the frame's GSD and flight direction in the FrameContext, defocus its distance
    to the ground (unless the project fixes one).
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
    if effects.vignetting is not None:
        v = effects.vignetting
        chain.append(RadialVignetting(interior, (-v.corner_falloff, v.rho4, v.rho6),
                                      natural_cos4=v.natural_cos4))
    if effects.defocus is not None:
        d = effects.defocus
        chain.append(ThinLensDefocus(interior, d.f_number, d.focus_distance_m,
                                     d.object_distance_m))
    if effects.blur is not None:
        chain.append(GaussianBlur(effects.blur.sigma_px))
    if effects.motion_blur is not None:
        scale = 1.0 if warp is None else float(warp.oversample)
        chain.append(LinearMotionBlur(effects.motion_blur.exposure_time_s,
                                      effects.motion_blur.speed_m_s, scale))
    if effects.sensor_noise is not None:
        chain.append(GaussianNoiseDN(effects.sensor_noise.sigma_dn, effects.sensor_noise.seed))
    if effects.sensor is not None:
        s = effects.sensor
        chain.append(SensorModel(full_well_e=s.full_well_e, exposure_scale=s.exposure_scale,
                                 read_noise_e=s.read_noise_e,
                                 dark_current_e_per_s=s.dark_current_e_per_s,
                                 exposure_time_s=s.exposure_time_s, adc_bits=s.adc_bits,
                                 shot_noise=True, seed=s.seed))
    if effects.exposure_variation is not None:
        from designer.effects.exposure import ExposureWhiteBalance

        x = effects.exposure_variation
        chain.append(ExposureWhiteBalance(x.exposure_sigma_ev, x.white_balance_sigma_k,
                                          x.reference_k, x.seed))
    if effects.jpeg is not None:
        chain.append(JpegCompression(effects.jpeg.quality))
    return EffectChain(chain)
