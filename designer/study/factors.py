"""The named parameters a study can vary, and how each one changes a project.

Every factor reads its value from a project (:attr:`Factor.get`, for the results table)
and writes a value into one (:attr:`Factor.set`, by ``dataclasses.replace`` on the
frozen model). Values are given as text in the study file and parsed by
:attr:`Factor.parse`; a value the project's own validation rejects is refused by
:mod:`designer.study.design` before anything runs.

``stage`` says what a change of the factor re-does: ``render`` factors change the
images; ``processing`` factors only the ground-truth tables or the reconstruction, so
their levels share one render (the cache decides this from content hashes; ``stage`` is
what the documentation and the report tell the user).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, replace

from designer.project import declare
from designer.project import model as m

Value = float | int | str | bool


@dataclass(frozen=True)
class Factor:
    name: str
    doc: str
    stage: str  # "render" or "processing"
    parse: Callable[[str], Value]
    get: Callable[[m.Project], Value | None]
    set: Callable[[m.Project, Value], m.Project]
    #: what a surveyor calls it, from the declaration (its label and unit); None: the doc
    words: str | None = None


# ------------------------------------------------------------------ value parsers
def _float(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise ValueError("not a number; write a number such as 0.5") from None
    if value != value or value in (float("inf"), float("-inf")):
        raise ValueError("not a finite number")
    return value


def _int(text: str) -> int:
    try:
        return int(text)
    except ValueError:
        raise ValueError("not a whole number; write one such as 3") from None


def _bool(text: str) -> bool:
    if text in ("true", "1"):
        return True
    if text in ("false", "0"):
        return False
    raise ValueError("write true or false")


def _choice(*choices: str) -> Callable[[str], str]:
    def parse(text: str) -> str:
        if text not in choices:
            raise ValueError(f"use one of: {', '.join(choices)}")
        return text
    return parse


# ------------------------------------------------------------------ model helpers
def _plan(p: m.Project) -> m.FlightPlan:
    if p.trajectory.flight_plan is None:
        raise ValueError("the base project has no flight plan (Flight panel); flight factors "
                         "need one")
    return p.trajectory.flight_plan


def _with_plan(p: m.Project, **changes) -> m.Project:
    return replace(p, trajectory=replace(p.trajectory, flight_plan=replace(_plan(p), **changes)))


def _noise(p: m.Project) -> m.PoseNoise:
    return _plan(p).pose_noise or m.PoseNoise()


def _proc(p: m.Project) -> m.Processing:
    return p.processing or m.Processing()


def _with_proc(p: m.Project, **changes) -> m.Project:
    return replace(p, processing=replace(_proc(p), **changes))


def _with_gcps(p: m.Project, **changes) -> m.Project:
    return _with_proc(p, gcps=replace(_proc(p).gcps, **changes))


def _control(p: m.Project) -> m.ControlSelection:
    return _proc(p).gcps.control or m.ControlSelection()


def _with_control(p: m.Project, **changes) -> m.Project:
    return _with_gcps(p, control=replace(_control(p), **changes))


def _precal(p: m.Project) -> m.PreCalibrationError:
    return _proc(p).calibration.pre_calibration_error or m.PreCalibrationError()


def _with_precal(p: m.Project, **changes) -> m.Project:
    cal = _proc(p).calibration
    return _with_proc(p, calibration=replace(
        cal, pre_calibration_error=replace(_precal(p), **changes)))


def _prior(p: m.Project) -> m.PositionPrior:
    return _proc(p).position_prior


def _with_prior(p: m.Project, **changes) -> m.Project:
    return _with_proc(p, position_prior=replace(_prior(p), **changes))


def _effects(p: m.Project) -> m.Effects:
    return p.effects or m.Effects()


def _with_effects(p: m.Project, **changes) -> m.Project:
    return replace(p, effects=replace(_effects(p), **changes))


def _survey(p: m.Project) -> m.SurveyAccuracy:
    t = p.scene.targets
    if t is None or not t.targets:
        raise ValueError("the base project has no GCP targets")
    return t.survey_accuracy or m.SurveyAccuracy(m.Sigma3(0.0, 0.0, 0.0), 0)


def _with_survey(p: m.Project, survey: m.SurveyAccuracy) -> m.Project:
    targets = replace(p.scene.targets, survey_accuracy=survey)
    return replace(p, scene=replace(p.scene, targets=targets))


def _camera(p: m.Project) -> m.Camera:
    plan = p.trajectory.flight_plan
    return p.camera(plan.camera) if plan is not None else p.cameras[0]


def _with_camera(p: m.Project, **changes) -> m.Project:
    cam = _camera(p)
    new = replace(cam, **changes)
    return replace(p, cameras=tuple(new if c.id == cam.id else c for c in p.cameras))


def _brown(p: m.Project) -> m.BrownConradyDistortion:
    d = _camera(p).distortion
    if isinstance(d, m.FisheyeEquidistantDistortion):
        raise ValueError("the camera has a fisheye distortion; k1/k2 factors need "
                         "brown-conrady")
    return d or m.BrownConradyDistortion()


def _with_sun_elevation(p: m.Project, value: float) -> m.Project:
    sun = p.scene.lighting.sun
    if not isinstance(sun, m.Sun):
        raise ValueError("the base project gives the sun by date and place; varying the sun's "
                         "elevation needs the sun given by its azimuth and elevation "
                         "(Lighting panel)")
    lighting = replace(p.scene.lighting, sun=replace(sun, elevation_deg=value))
    return replace(p, scene=replace(p.scene, lighting=lighting))


def _utc(text: str) -> str:
    from designer.project.utc import EXAMPLE_UTC, parse_utc

    if parse_utc(text) is None:
        raise ValueError(f"not an ISO 8601 moment in UTC; write e.g. {EXAMPLE_UTC}")
    return text.strip()


def _time_line(p: m.Project) -> m.TimeLine:
    if p.trajectory.time_line is None:
        raise ValueError("the base project has no time line (take-off time and speed, Flight "
                         "panel); add one to vary the flight's timing")
    return p.trajectory.time_line


def _with_time_line(p: m.Project, **changes) -> m.Project:
    time_line = replace(_time_line(p), **changes)
    return replace(p, trajectory=replace(p.trajectory, time_line=time_line))


def _with_moving_speed(p: m.Project, speed_m_s: float) -> m.Project:
    if not p.scene.moving_objects:
        raise ValueError("the base project has no moving objects (Moving objects panel); add "
                         "one to vary their speed")
    moving = tuple(replace(o, speed_m_s=speed_m_s) for o in p.scene.moving_objects)
    return replace(p, scene=replace(p.scene, moving_objects=moving))


def _oblique_tilt(p: m.Project) -> float | None:
    """The tilt (deg from the platform's axis) of the first rig's most tilted mount."""
    from designer.core.rig import mount_tilt_deg

    if not p.trajectory.rigs:
        return None
    tilts = [mount_tilt_deg(mt.omega_deg, mt.phi_deg, mt.kappa_deg)
             for mt in p.trajectory.rigs[0].mounts]
    return round(max(tilts), 9)


def _with_oblique_tilt(p: m.Project, tilt_deg: float) -> m.Project:
    """Every oblique mount (not along the platform's axis) of every rig turned to look
    ``tilt_deg`` from the platform's axis, in the direction it looked before."""
    from designer.core.rig import mount_tilt_deg, retilted_mount_deg

    if not p.trajectory.rigs:
        raise ValueError("the base project flies no camera rig; add an oblique rig (Camera "
                         "panel) to vary its tilt")
    if not 0 < tilt_deg <= 90:
        raise ValueError("the oblique tilt must be greater than 0 and at most 90 degrees")
    rigs = []
    for rig in p.trajectory.rigs:
        mounts = []
        for mt in rig.mounts:
            angles = (mt.omega_deg, mt.phi_deg, mt.kappa_deg)
            if mount_tilt_deg(*angles) > 1e-6:
                angles = retilted_mount_deg(*angles, tilt_deg)
            mounts.append(replace(mt, omega_deg=angles[0], phi_deg=angles[1],
                                  kappa_deg=angles[2]))
        rigs.append(replace(rig, mounts=tuple(mounts)))
    return replace(p, trajectory=replace(p.trajectory, rigs=tuple(rigs)))


def _with_readout(p: m.Project, readout_s: float) -> m.Project:
    """The camera's rolling shutter with this readout (0: none), its direction kept."""
    if readout_s and p.trajectory.time_line is None:
        raise ValueError("the base project has no time line; a rolling shutter moves the "
                         "camera along it: give a take-off time and speed (Flight panel)")
    rs = _camera(p).rolling_shutter
    direction = rs.direction if rs is not None else "top-to-bottom"
    return _with_camera(p, rolling_shutter=m.RollingShutter(readout_s, direction)
                        if readout_s else None)


def _extruded(p: m.Project) -> list[m.Building]:
    return [b for b in p.scene.buildings if b.file is None]


def _with_eave_height(p: m.Project, eave_m: float) -> m.Project:
    """Every extruded building's walls ``eave_m`` high; a pitched roof keeps its rise."""
    if not _extruded(p):
        raise ValueError("the base project has no building with a footprint (Buildings "
                         "panel); add one to vary their height")
    buildings = tuple(b if b.file is not None else replace(
        b, eave_height_m=eave_m, ridge_height_m=None if b.ridge_height_m is None
        else b.ridge_height_m - b.eave_height_m + eave_m) for b in p.scene.buildings)
    return replace(p, scene=replace(p.scene, buildings=buildings))


def _vegetation_density(p: m.Project) -> float:
    veg = p.scene.vegetation
    return float(sum(g.density_per_m2 for g in veg.plants)) if veg is not None else 0.0


def _with_vegetation_density(p: m.Project, density_per_m2: float) -> m.Project:
    """Every group scaled so the densities add up to ``density_per_m2`` (their shares
    kept); 0 removes the vegetation; a base without one gets shrubs."""
    veg = p.scene.vegetation
    if not density_per_m2:
        return replace(p, scene=replace(p.scene, vegetation=None))
    if veg is None or not veg.plants:
        height, crown = m.PLANT_KINDS["shrub"]
        veg = m.Vegetation((m.PlantGroup(density_per_m2, "shrub", height_m=height,
                                         crown_m=crown),))
    else:
        total = _vegetation_density(p)
        veg = replace(veg, plants=tuple(
            replace(g, density_per_m2=density_per_m2 * g.density_per_m2 / total)
            for g in veg.plants))
    return replace(p, scene=replace(p.scene, vegetation=veg))


def _with_wind_amplitude(p: m.Project, amplitude_deg: float) -> m.Project:
    veg = p.scene.vegetation
    if veg is None:
        raise ValueError("the base project has no vegetation (Vegetation panel); add some to "
                         "vary the wind's sway")
    wind = replace(veg.wind or m.Wind(), amplitude_deg=amplitude_deg)
    return replace(p, scene=replace(p.scene, vegetation=replace(veg, wind=wind)))


def _texture_source(p: m.Project):
    return p.scene.texture.source


def _with_texture_source(p: m.Project, source) -> m.Project:
    return replace(p, scene=replace(p.scene, texture=replace(p.scene.texture, source=source)))


def _with_texel(p: m.Project, value: float) -> m.Project:
    src = _texture_source(p)
    if not isinstance(src, m.ProceduralTexture):
        raise ValueError("the base texture is an image file; varying its texel size needs a "
                         "procedural texture (Texture panel)")
    return _with_texture_source(p, replace(src, texel_size_m=value))


def _with_variation_strength(p: m.Project, value: float) -> m.Project:
    """Strength of the texture variation; 0 removes it (the plain tiled texture). A base
    project without one gets seed 1 and a scale of two tiles."""
    tex = p.scene.texture
    if value == 0:
        variation = None
    elif tex.variation is not None:
        variation = replace(tex.variation, strength=value)
    else:
        e = p.scene.terrain.extent
        tile_m = max(e.width_m / tex.repeat_X, e.length_m / tex.repeat_Y)
        variation = m.TextureVariation(seed=1, scale_m=2 * tile_m, strength=value)
    return replace(p, scene=replace(p.scene, texture=replace(tex, variation=variation)))


#: flight geometries of the ``flight-geometry`` factor: (crosshatch, tilt in deg)
def _block_side(p: m.Project) -> float | None:
    """The flight area's east–west side (m), None without a flight plan."""
    plan = p.trajectory.flight_plan
    if plan is None or not plan.area:
        return None
    xs = [x for x, _ in plan.area]
    return max(xs) - min(xs)


def _with_block_side(p: m.Project, side_m: float) -> m.Project:
    from designer.project.templates import block_of_side

    return block_of_side(p, side_m)


GEOMETRIES = {"nadir": (False, 0.0), "crosshatch": (True, 0.0), "tilted": (True, 20.0)}


def _geometry(p: m.Project) -> str:
    plan = _plan(p)
    for name, (cross, tilt) in GEOMETRIES.items():
        if plan.crosshatch == cross and plan.tilt_deg == tilt:
            return name
    return f"{'crosshatch' if plan.crosshatch else 'parallel lines'}, tilted {plan.tilt_deg:g}°"


def _set_geometry(p: m.Project, value: str) -> m.Project:
    cross, tilt = GEOMETRIES[value]
    return _with_plan(p, crosshatch=cross, tilt_deg=tilt)


def _F(name, doc, stage, parse, get, set_) -> Factor:
    return Factor(name, doc, stage, parse, get, set_)


#: the factors with rules of their own (the declared ones are made by _declared_factors)
_HAND_WRITTEN: list[Factor] = [
    _F("altitude-m", "flight height above the reference ground (m); replaces a GSD",
       "render", _float, lambda p: _plan(p).altitude_agl_m,
       lambda p, v: _with_plan(p, altitude_agl_m=v, gsd_m=None)),
    _F("gsd-m", "ground sample distance the flight is planned for (m/px); replaces altitude",
       "render", _float, lambda p: _plan(p).gsd_m,
       lambda p, v: _with_plan(p, gsd_m=v, altitude_agl_m=None)),
    _F("flight-geometry", "nadir (single grid), crosshatch (two grids at 90 deg, nadir) or "
       "tilted (crosshatch with the camera tilted 20 deg forward)", "render",
       _choice(*GEOMETRIES), _geometry, _set_geometry),
    _F("pose-noise-sigma-m", "sigma of the flown position about the plan, X, Y and Z (m)",
       "render", _float, lambda p: _noise(p).sigma_X_m,
       lambda p, v: _with_plan(p, pose_noise=replace(_noise(p), sigma_X_m=v, sigma_Y_m=v,
                                                       sigma_Z_m=v))),
    _F("pose-noise-sigma-deg", "sigma of the flown attitude about the plan, omega, phi and "
       "kappa (deg)", "render", _float, lambda p: _noise(p).sigma_omega_deg,
       lambda p, v: _with_plan(p, pose_noise=replace(
           _noise(p), sigma_omega_deg=v, sigma_phi_deg=v, sigma_kappa_deg=v))),
    _F("control-count", "number of GCPs used as control (the others are check points); "
       "chosen as the control spread says", "processing", _int, lambda p: _control(p).count,
       lambda p, v: _with_control(p, count=v, ids=())),
    _F("gcp-survey-sigma-m", "sigma of the simulated GCP survey, each axis (m)", "processing",
       _float, lambda p: _survey(p).sigma.X,
       lambda p, v: _with_survey(p, replace(_survey(p), sigma=m.Sigma3(v, v, v)))),
    _F("position-prior-sigma-m", "sigma of the measured camera positions, horizontal (m); "
       "vertical is 1.5 times it", "processing", _float,
       lambda p: _prior(p).sigmas_m[0],
       lambda p, v: _with_prior(p, sigma_horizontal_m=v, sigma_vertical_m=1.5 * v)),
    _F("k1", "radial distortion k1 of the camera (Brown-Conrady)", "render", _float,
       lambda p: _brown(p).k1, lambda p, v: _with_camera(p, distortion=replace(_brown(p), k1=v))),
    _F("k2", "radial distortion k2 of the camera (Brown-Conrady)", "render", _float,
       lambda p: _brown(p).k2, lambda p, v: _with_camera(p, distortion=replace(_brown(p), k2=v))),
    _F("sensor-noise-dn", "sigma of additive sensor noise (digital numbers)", "render", _float,
       lambda p: _effects(p).sensor_noise.sigma_dn if _effects(p).sensor_noise else 0.0,
       lambda p, v: _with_effects(p, sensor_noise=m.SensorNoise(
           v, _effects(p).sensor_noise.seed if _effects(p).sensor_noise else 0) if v else None)),
    _F("sun-elevation-deg", "sun elevation above the horizon (deg)", "render", _float,
       lambda p: getattr(p.scene.lighting.sun, "elevation_deg", None), _with_sun_elevation),
    _F("cloud-cover", "share of the ground in drifting cloud shadow, 0 to 1 (0: no clouds)",
       "render", _float, lambda p: p.scene.lighting.clouds.cover if _clouds_on(p) else 0.0,
       lambda p, v: _with_clouds(p, cover=v) if v else _without_clouds(p)),
    _F("takeoff-time", "moment of the first photo, ISO 8601 UTC (moves a sun over time)",
       "render", _utc, lambda p: getattr(p.trajectory.time_line, "takeoff_utc", None),
       lambda p, v: _with_time_line(p, takeoff_utc=v)),
    _F("moving-object-speed-m-s", "speed of every moving object along its path (m/s)",
       "render", _float,
       lambda p: p.scene.moving_objects[0].speed_m_s if p.scene.moving_objects else None,
       _with_moving_speed),
    _F("oblique-tilt-deg", "tilt of every oblique rig mount from the platform's axis (deg; "
       "the nadir mounts stay)", "render", _float, _oblique_tilt, _with_oblique_tilt),
    _F("rolling-shutter-readout-s", "rolling-shutter readout time of the camera per frame "
       "(s; 0: a global shutter; needs a take-off time and speed)", "render", _float,
       lambda p: _camera(p).readout_s, _with_readout),
    _F("building-eave-height-m", "wall height of every extruded building above its base "
       "(m); a gable or hip roof keeps its rise above the eaves", "render", _float,
       lambda p: _extruded(p)[0].eave_height_m if _extruded(p) else None,
       _with_eave_height),
    _F("vegetation-density-per-m2", "plants per m² over all plant groups (their shares "
       "kept); 0 removes the vegetation, a base without one gets shrubs", "render", _float,
       _vegetation_density, _with_vegetation_density),
    _F("vegetation-wind-amplitude-deg", "largest lean of the plants swaying in the wind "
       "(deg; 0: they stand still)", "render", _float,
       lambda p: (p.scene.vegetation.wind.amplitude_deg
                  if p.scene.vegetation is not None and p.scene.vegetation.wind else 0.0),
       _with_wind_amplitude),
    _F("texture-file", "ground texture image (path relative to the study file)", "render", str,
       lambda p: getattr(_texture_source(p), "file", None),
       lambda p, v: _with_texture_source(p, m.ImageTexture(v))),
    _F("texel-size-m", "texel size of the procedural ground texture (m)", "render", _float,
       lambda p: getattr(_texture_source(p), "texel_size_m", None), _with_texel),
    _F("texture-variation-strength", "brightness swing of the non-repeating texture "
       "variation, 0 to 1; 0 removes the variation (the plain tiled texture)", "render", _float,
       lambda p: p.scene.texture.variation.strength if p.scene.texture.variation else 0.0,
       _with_variation_strength),
    _F("block-side-m", "side of a square flight area about the origin (m): the terrain 15 m "
       "wider, control GCPs on a grid and check points between them, as the scale bench's "
       "blocks", "render", _float, _block_side, _with_block_side),
    _F("render-preset", "render quality preset: draft, survey or metrology", "render",
       _choice("draft", "survey", "metrology"), lambda p: p.render.preset,
       lambda p, v: replace(p, render=replace(p.render, preset=v, samples=None))),
    _F("render-samples", "Cycles samples per pixel", "render", _int,
       lambda p: p.render.effective_samples,
       lambda p, v: replace(p, render=replace(p.render, samples=v))),
]


def _declared_factors() -> list[Factor]:
    """A factor for every declared attribute with ``factor=`` of an element that has one
    place in a project (designer.project.declare): its doc and unit, its type's parser,
    get/set at its path (an absent element is switched on when a value is set)."""
    out = []
    for cls in declare.declared_elements(m.Project):
        el = declare.element_of(cls)
        if el.path is None:
            continue
        for d in declare.declared(cls):
            if d.attr.factor is None:
                continue
            if d.choices is not None:
                parse, doc = _choice(*d.choices), f"{d.attr.doc}: {', '.join(d.choices)}"
            else:
                parse = {float: _float, int: _int, bool: _bool}.get(d.base, str)
                doc = f"{d.attr.doc} ({d.range_text()})"
            unit = {"deg": "°"}.get(d.attr.unit or "", d.attr.unit)
            words = None if not d.attr.label else (
                f"{d.attr.label} ({unit})" if unit else d.attr.label)
            out.append(Factor(
                d.attr.factor, doc, el.stage, parse,
                lambda p, at=el.path, n=d.name: declare.value_at(p, at, n),
                lambda p, v, at=el.path, n=d.name: declare.with_value(p, at, n, v), words))
    return out


def _all_factors() -> dict[str, Factor]:
    factors: dict[str, Factor] = {}
    for f in [*_HAND_WRITTEN, *_declared_factors()]:
        if f.name in factors:
            raise RuntimeError(f"study factor {f.name!r} is defined twice")
        factors[f.name] = f
    return factors


FACTORS: dict[str, Factor] = _all_factors()


# ------------------------------------------------------------------ cloud shadows
def _clouds_on(p: m.Project) -> bool:
    return p.scene.lighting.clouds is not None


def _cloud(p: m.Project, name: str):
    return getattr(p.scene.lighting.clouds, name) if _clouds_on(p) else None


def _set_clouds(p: m.Project, clouds: m.CloudShadows | None) -> m.Project:
    lighting = replace(p.scene.lighting, clouds=clouds)
    return replace(p, scene=replace(p.scene, lighting=lighting))


def _with_clouds(p: m.Project, **changes) -> m.Project:
    """The project's cloud shadows with ``changes`` (the defaults when it has none)."""
    return _set_clouds(p, replace(p.scene.lighting.clouds or m.CloudShadows(), **changes))


def _without_clouds(p: m.Project) -> m.Project:
    return _set_clouds(p, None)


# ------------------------------------------------------------------ replicate draws
def _seed_selection(p: m.Project, seed: int) -> m.Project:
    if _control(p).count is None:
        return p  # control chosen by ids: nothing to re-draw
    return _with_control(p, spread="random", seed=seed)


_HAND_WRITTEN_DRAWS: dict[str, tuple[str, Callable[[m.Project, int], m.Project]]] = {
    # more than a seed: a drawn selection is a random one
    "gcp-selection": ("which GCPs are control (that many drawn at random)",
                      _seed_selection),
}


def _declared_draws() -> dict[str, tuple[str, Callable[[m.Project, int], m.Project]]]:
    """A draw of every name some seed declares with ``draw=`` (designer.project.declare):
    it sets each such seed of the elements the project has (a project without them has
    nothing to re-draw)."""
    seeds: dict[str, list[tuple[str, str, str]]] = {}
    for cls in declare.declared_elements(m.Project):
        el = declare.element_of(cls)
        for d in declare.declared(cls):
            if d.attr.draw is not None:
                if el.path is None:
                    raise RuntimeError(f"{cls.__name__}.{d.name} declares draw "
                                       f"{d.attr.draw!r} but <{el.tag}> has no path")
                # in a person's words (the Study panel's tooltip, the study schema)
                seeds.setdefault(d.attr.draw, []).append(
                    (el.path, d.name, f"{d.label} of the {el.title}"))

    def reseed(p: m.Project, seed: int, where: list[tuple[str, str, str]]) -> m.Project:
        for path, name, _ in where:
            if declare.element_at(p, path) is not None:
                p = declare.with_value(p, path, name, seed)
        return p

    return {name: ("the " + " and the ".join(w for _, _, w in where),
                   lambda p, s, where=where: reseed(p, s, where))
            for name, where in seeds.items()}


def _all_draws() -> dict[str, tuple[str, Callable[[m.Project, int], m.Project]]]:
    draws = dict(_HAND_WRITTEN_DRAWS)
    for name, draw in _declared_draws().items():
        if name in draws:
            raise RuntimeError(f"replicate draw {name!r} is defined twice")
        draws[name] = draw
    return draws


#: random draws a replicate can re-seed: name → (documentation, how to set the seed)
DRAWS: dict[str, tuple[str, Callable[[m.Project, int], m.Project]]] = _all_draws()
