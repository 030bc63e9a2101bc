"""How long a render takes on this machine: the one model behind every render estimate
(``designer plan``, the GUI's Flight, Render and Study panels, a study's summary).

Model, for a finished image of W × H pixels at s samples per pixel, a fraction f of
whose pixels see the terrain (the rest see the empty background):

    Cycles CPU-seconds = W·H/10⁶ · s · (background + f · (terrain − background))
    seconds outside Cycles (Blender's file, camera effects, encoding) = W·H/10⁶ · post

and the whole render stage of N images with w workers on c cores

    wall = fixed + Σ Cycles CPU-seconds / c + Σ seconds outside Cycles / w

(every core path-traces; each worker does its own file and effects work while the other
workers render); ``fixed`` is the preparation and the workers' start (scene, texture
bake, lens warp, Blender start-up). Most of the preparation of a varied ground texture
is its bake, so ``fixed`` grows with the bake's megapixels B (:func:`project_bake_mp`):
a fixed part measured at B₀ counts as ``fixed + bake · (B − B₀)`` for a render baking B
(at least :data:`MIN_FIXED_S`; ``bake`` is :data:`BAKE_S_PER_MP` s per megapixel).

The coefficients are this machine's (:class:`RenderSpeed`), measured by ``designer
warmup`` (run by ``make setup``: a short probe render of the example survey) and by every
``designer render`` (from its own frames: the manifest's per-stage seconds). Each render
adds one record to ``render-speed.json`` in designer's cache folder
(``$DESIGNER_CACHE_DIR``, else ``$XDG_CACHE_HOME/designer``, else
``~/.cache/designer``), filed under what drives its cost (:func:`cost_key`): the scene's
kind (terrain alone, or with buildings, plants, moving objects, objects), the samples per
pixel and the image size (each in powers of two), and the camera effects. An estimate
takes, per coefficient, the median of the latest :data:`RECENT` records of its own key —
Cycles' coefficients from records of the same scene kind, samples and size, the seconds
outside Cycles from records of the same effects and size, the fixed part from records of
the same whole key — widening to the scene kind, then to every record, only where its key
has none. So an estimate does not move when another kind of project renders, and one slow
render (a busy machine) among several of the same kind moves no median far. Cycles' part
is measured in CPU-seconds (all its threads), which a busy machine changes far less than
wall time, and divided by the cores to predict wall time. The wall seconds outside Cycles
(files, effects, preparation, start-up) are recorded as an idle machine's: scaled by the
share of the cores the frames' Cycles threads had (render_time.record.core_share), so a
render on a machine busy with other work does not make later estimates of an idle one
too long. Without any record the estimate uses :data:`REFERENCE` and says it is
uncalibrated.

Not modelled: buildings, plants and moving objects (more geometry than the terrain),
adaptive sampling (metrology preset: counted at its maximum samples), an estimate for a
machine that will be busy with other work (every estimate is an idle machine's), and
workers competing for the caches (two workers of one core each
render the example about 20 % slower than one worker with both cores, which the model
does not see: docs/benchmarks.md). A render of such a project records its own
coefficients under its own kind.
"""

from __future__ import annotations

import json
import math
import os
import time
from collections.abc import Sequence
from dataclasses import asdict, dataclass, replace
from pathlib import Path

import numpy as np

SPEED_FILE = "render-speed.json"
#: rays per image side used to measure the terrain fraction (cols × rows)
FRACTION_GRID = (16, 11)
#: a render of at least this many images replaces the stored coefficients outright
#: (:func:`refine`)
FULL_WEIGHT_IMAGES = 8
#: an estimate uses the median of at most this many latest records of its key
RECENT = 9
#: records kept in the file (the oldest dropped first)
MAX_RECORDS = 300
#: the coefficient groups and the key fields each is matched on, narrowest first
_MATCH = {
    ("terrain_cpu_s_per_mp_sample", "background_cpu_s_per_mp_sample"):
        (("scene", "texture", "samples_band", "size_band"), ("scene", "texture", "samples_band"),
         ("scene", "texture"), ("scene", "samples_band", "size_band"),
         ("scene", "samples_band"), ("scene",)),
    ("post_s_per_mp",): (("effects", "texture", "size_band"), ("effects", "texture"),
                         ("effects", "size_band"), ("effects",)),
    ("fixed_s",): (("scene", "texture", "effects", "samples_band", "size_band"),
                   ("scene", "effects", "samples_band", "size_band"), ("scene", "effects")),
}
#: How the renderer draws the ground texture (designer.render.job_terrain takes the same
#: choice, :func:`texture_path`): "baked" — one image lookup per sample (a plain tiled
#: texture, an orthophoto, or a varied texture baked whole); "tiled" — a varied texture
#: too wide for one bake, baked in tiles that each frame loads as it sees them; "node-graph" — the
#: varied texture blended by Cycles' nodes per sample (five lookups; ``designer bench
#: render``'s unbaked row, or a mesh terrain too wide for one bake). Each path's
#: coefficients come from renders of that path; until this machine has rendered one, the
#: other paths' are scaled by these priors (measured on the reference machine, 2026-12-06,
#: docs/benchmarks.md): the terrain's Cycles cost …
TEXTURE_PATH_CYCLES = {"baked": 1.0, "tiled": 1.25, "node-graph": 2.5}
#: … and the seconds per image added outside Cycles (the tiles' bake and load)
TEXTURE_PATH_POST_S = {"baked": 0.0, "tiled": 0.3, "node-graph": 0.0}
#: seconds of preparation per megapixel of the ground texture's bake (the bake kernel,
#: the light map folded in, the file written): the example's 77 MP bake took 12.7 s of
#: its 14.6 s preparation on the reference machine, 2026-12-06 (cProfile of prepare_job)
BAKE_S_PER_MP = 0.165
#: the least fixed part of a render: Blender's start and a small scene's preparation
MIN_FIXED_S = 1.0
#: a record from before the texture path was filed is of the path most renders took
_DEFAULT_PATH = "baked"


@dataclass(frozen=True)
class RenderSpeed:
    """This machine's render coefficients (see the module docstring)."""

    #: Cycles CPU-seconds per megapixel-sample where the pixels see the terrain
    terrain_cpu_s_per_mp_sample: float
    #: … where they see the empty background
    background_cpu_s_per_mp_sample: float
    #: worker seconds per megapixel outside Cycles (file, effects, encoding)
    post_s_per_mp: float
    #: preparation and worker start-up of one render (s)
    fixed_s: float
    #: "reference" (not measured here), "probe" (designer warmup) or "render"
    source: str = "reference"
    #: when it was measured (local time, ISO), and on how many images
    measured: str = ""
    images: int = 0
    #: the megapixels of the texture bake ``fixed_s`` was measured with (None: unknown,
    #: a record from before bakes were counted: ``fixed_s`` is used as it is)
    fixed_bake_mp: float | None = None
    #: seconds of preparation per megapixel of texture bake (fixed_for)
    bake_s_per_mp: float = BAKE_S_PER_MP

    @property
    def calibrated(self) -> bool:
        return self.source != "reference"

    def describe(self) -> str:
        """Where the estimate comes from, for reports and panels."""
        if not self.calibrated:
            return ("uncalibrated: the reference machine's figures until 'designer warmup' "
                    "or a first render measures this one")
        what = "probe render" if self.source == "probe" else "render"
        images = f"{self.images} image{'' if self.images == 1 else 's'}"
        return f"this machine, {what} of {images} on {self.measured}"


#: Fitted to the example survey on the reference machine (2 cores, Blender 5.0.1, the
#: baked texture with the light map folded in, one worker): the record of the render in
#: ``make demo`` on a fresh clone of d0aea2d with a new cache folder (the example's 60
#: images of 1368 × 912 px at 16 spp, every pixel on the terrain or its surroundings,
#: 59 frames fitted; render stage 258.7 s). The fixed part is that of a render with no
#: bake (the tiny study template's render, 2.36 s with its 1.44 MP bake, less the bake's
#: seconds): a render baking B megapixels adds ``BAKE_S_PER_MP · B``.
REFERENCE = RenderSpeed(terrain_cpu_s_per_mp_sample=0.369,
                        background_cpu_s_per_mp_sample=0.134, post_s_per_mp=0.203,
                        fixed_s=2.1, fixed_bake_mp=0.0)


def cache_dir() -> Path:
    """designer's cache folder (see the module docstring)."""
    if os.environ.get("DESIGNER_CACHE_DIR"):
        return Path(os.environ["DESIGNER_CACHE_DIR"])
    base = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    return Path(base) / "designer"


_COEFFICIENTS = ("terrain_cpu_s_per_mp_sample", "background_cpu_s_per_mp_sample",
                 "post_s_per_mp", "fixed_s")


def _band(value: float) -> int:
    """The power of two nearest ``value`` (samples 12 → 4 (16), 0.3 MP → -2 (0.25))."""
    return round(math.log2(value)) if value > 0 else -99


def cost_key(image: ImageCost) -> dict:
    """What drives an image's cost, as a record's key: scene kind, effects, samples and
    size (each a power of two)."""
    return {"scene": image.scene, "effects": image.effects, "texture": image.texture,
            "samples_band": _band(image.samples), "size_band": _band(image.megapixels)}


def _read_records() -> list[dict]:
    """The stored records (a file of the form before records, one coefficient set,
    is one record with no key); [] when absent or unreadable."""
    try:
        data = json.loads((cache_dir() / SPEED_FILE).read_text())
    except (OSError, ValueError):
        return []
    records = data.get("records") if isinstance(data, dict) and "records" in data else [data]
    out = []
    for r in records if isinstance(records, list) else []:
        if not isinstance(r, dict):
            continue
        try:
            values = [float(r[k]) for k in _COEFFICIENTS]
        except (KeyError, TypeError, ValueError):
            continue
        if all(math.isfinite(v) and v >= 0 for v in values):
            out.append({"texture": _DEFAULT_PATH, **r})
    return out


def _speed_of(record: dict, images: int | None = None) -> RenderSpeed:
    return RenderSpeed(*(float(record[k]) for k in _COEFFICIENTS),
                       source=str(record.get("source", "render")),
                       measured=str(record.get("measured", "")),
                       images=int(record.get("images", 0)) if images is None else images,
                       fixed_bake_mp=record.get("fixed_bake_mp"))


def load_speed(image: ImageCost | None = None) -> RenderSpeed:
    """This machine's coefficients for images like ``image`` (module docstring: the
    median of the latest records of its key, widened only where it has none); without
    ``image``, over the latest records of every kind. :data:`REFERENCE` when nothing was
    measured (or the file is unreadable)."""
    records = _read_records()
    if not records:
        if image is None:
            return REFERENCE
        reference = {**asdict(REFERENCE), "texture": _DEFAULT_PATH}
        return replace(REFERENCE, fixed_bake_mp=image.bake_mp,
                       **{name: _as_path(reference, name, image)
                          for name in ("terrain_cpu_s_per_mp_sample", "post_s_per_mp",
                                       "fixed_s")})
    key = cost_key(image) if image is not None else None
    values: dict[str, float] = {}
    used: dict[int, dict] = {}
    for names, levels in _MATCH.items():
        chosen = []
        for fields in (levels if key is not None else ()):
            chosen = [r for r in records if all(r.get(f) == key[f] for f in fields)]
            if chosen:
                break
        chosen = (chosen or records)[-RECENT:]
        for r in chosen:
            used[id(r)] = r
        for name in names:
            values[name] = float(np.median([_as_path(r, name, image) for r in chosen]))
    latest = max(used.values(), key=lambda r: records.index(r))
    return RenderSpeed(**values, source=str(latest.get("source", "render")),
                       measured=str(latest.get("measured", "")),
                       images=sum(int(r.get("images", 0)) for r in used.values()),
                       fixed_bake_mp=None if image is None else image.bake_mp)


def _as_path(record: dict, name: str, image: ImageCost | None) -> float:
    """A record's coefficient ``name`` for an image of ``image``'s texture path: scaled by
    the paths' priors (TEXTURE_PATH_CYCLES, TEXTURE_PATH_POST_S) when the record was
    rendered on another path; its fixed part for ``image``'s bake (:func:`fixed_for`)."""
    value = float(record[name])
    if name == "fixed_s" and image is not None:
        return fixed_for(RenderSpeed(0, 0, 0, value, fixed_bake_mp=record.get("fixed_bake_mp")),
                         image.bake_mp)
    mine, theirs = (image.texture, record["texture"]) if image is not None else ("", "")
    if mine == theirs:
        return value
    if name == "terrain_cpu_s_per_mp_sample":
        return value * (TEXTURE_PATH_CYCLES.get(mine, 1.0)
                        / TEXTURE_PATH_CYCLES.get(theirs, 1.0))
    if name == "post_s_per_mp":
        extra = TEXTURE_PATH_POST_S.get(mine, 0.0) - TEXTURE_PATH_POST_S.get(theirs, 0.0)
        return max(0.0, value + extra / max(image.megapixels, 1e-9))
    return value


def save_speed(speed: RenderSpeed, image: ImageCost | None = None) -> Path:
    """Add ``speed`` as the latest record, filed under ``image``'s key (module
    docstring; without ``image``, under no key: used only where no key matches);
    atomically; returns the file. A probe's record replaces the earlier probe's."""
    from designer.atomic import write_text_atomic

    records = _read_records()
    if speed.source == "probe":
        records = [r for r in records if r.get("source") != "probe"]
    record = {**asdict(speed), **(cost_key(image) if image is not None else {})}
    records = [*records, record][-MAX_RECORDS:]
    path = cache_dir() / SPEED_FILE
    path.parent.mkdir(parents=True, exist_ok=True)
    write_text_atomic(path, json.dumps({"records": records}, indent=1))
    return path


def default_workers(n_frames: int, cores: int | None = None) -> int:
    """Worker processes for this machine: one per two cores, at least one."""
    cores = cores or os.cpu_count() or 2
    return max(1, min(n_frames, cores // 2))


@dataclass(frozen=True)
class ImageCost:
    """What the model needs of one image."""

    megapixels: float  # of the finished image (W × H / 10⁶)
    samples: int
    terrain_fraction: float = 1.0
    #: the scene's kind: "terrain", or "terrain+buildings+plants+moving+objects" (those
    #: it has; :func:`scene_kind`)
    scene: str = "terrain"
    #: the camera effects applied ("none", or their names joined by "+": effects_key)
    effects: str = "none"
    #: how the renderer draws the ground texture (TEXTURE_PATH_CYCLES: texture_path)
    texture: str = "baked"
    #: megapixels of the ground texture bake the render prepares (project_bake_mp; the
    #: same for every image of a render; None: unknown)
    bake_mp: float | None = None


def fixed_for(speed: RenderSpeed, bake_mp: float | None) -> float:
    """``speed``'s fixed part for a render that bakes ``bake_mp`` megapixels (module
    docstring); as measured where either bake is unknown."""
    if bake_mp is None or speed.fixed_bake_mp is None:
        return speed.fixed_s
    return max(MIN_FIXED_S,
               speed.fixed_s + speed.bake_s_per_mp * (bake_mp - speed.fixed_bake_mp))


def frame_cpu_s(speed: RenderSpeed, image: ImageCost) -> float:
    """Cycles CPU-seconds of one image."""
    per = (speed.background_cpu_s_per_mp_sample + image.terrain_fraction
           * (speed.terrain_cpu_s_per_mp_sample - speed.background_cpu_s_per_mp_sample))
    return image.megapixels * image.samples * per


@dataclass(frozen=True)
class RenderEstimate:
    """A render's estimated wall seconds in its two parts: the set-up, paid once however
    many images (preparation, scene, texture bake, Blender's start: ``fixed``), and the
    images (Cycles and the work outside it)."""

    setup_s: float
    images_s: float
    n_images: int

    @property
    def total_s(self) -> float:
        return self.setup_s + self.images_s

    @property
    def per_image_s(self) -> float:
        """Seconds each further image adds (the set-up left out)."""
        return self.images_s / max(1, self.n_images)


def estimate_render_s(images: Sequence[ImageCost], workers: int, cores: int | None = None,
                      speed: RenderSpeed | None = None) -> float:
    """Wall seconds of the whole render stage (module docstring); without ``speed``, each
    kind of image (:func:`cost_key`) with this machine's coefficients for its kind."""
    return estimate_render(images, workers, cores, speed).total_s


def estimate_render(images: Sequence[ImageCost], workers: int, cores: int | None = None,
                    speed: RenderSpeed | None = None) -> RenderEstimate:
    """:func:`estimate_render_s` with the set-up apart from the images' seconds."""
    cores = max(1, cores or os.cpu_count() or 1)
    workers = max(1, min(workers, cores, max(1, len(images))))
    if speed is not None:
        speeds = [speed] * len(images)
    else:
        by_key: dict[str, RenderSpeed] = {}  # the speed file read once per kind of image
        speeds = []
        for i in images:
            key = json.dumps(cost_key(i), sort_keys=True)
            if key not in by_key:
                by_key[key] = load_speed(i)
            speeds.append(by_key[key])
        if not images:
            speeds, speed = [], load_speed()
    cpu = sum(frame_cpu_s(sp, i) for sp, i in zip(speeds, images, strict=True))
    post = sum(i.megapixels * sp.post_s_per_mp for sp, i in zip(speeds, images, strict=True))
    fixed = max((fixed_for(sp, i.bake_mp) for sp, i in zip(speeds, images, strict=True)),
                default=speed.fixed_s if speed else 0.0)
    return RenderEstimate(fixed, cpu / cores + post / workers, len(images))


def scene_kind(project) -> str:
    """What a project's scene holds beyond the terrain, as a key: 'terrain',
    'terrain+buildings', … (buildings, plants, moving objects, objects)."""
    scene = project.scene
    parts = ["terrain"]
    for name, present in (("buildings", scene.buildings), ("plants", scene.vegetation),
                          ("moving", scene.moving_objects), ("objects", scene.objects)):
        if present:
            parts.append(name)
    return "+".join(parts)


def effects_key(project) -> str:
    """The camera effects a project applies, as a key: 'none' or 'distortion+jpeg+…'."""
    from dataclasses import fields

    effects = project.effects
    names = sorted(f.name for f in fields(effects) if getattr(effects, f.name) is not None) \
        if effects is not None else []
    if any(getattr(c, "distortion", None) is not None for c in project.cameras):
        names.append("distortion")
    return "+".join(sorted(names)) or "none"


def fit_speed(images: Sequence[ImageCost], cycles_cpu_s: Sequence[float],
              post_s: Sequence[float], fixed_s: float, source: str,
              prior: RenderSpeed | None = None) -> RenderSpeed:
    """Coefficients from measured frames: Cycles CPU-seconds and seconds outside Cycles
    per image. The terrain and background costs are fitted by least squares where the
    frames' terrain fractions differ enough; otherwise the prior's ratio of the two is
    kept and one common factor fitted."""
    prior = prior or load_speed()
    x = np.array([i.megapixels * i.samples for i in images], float)
    f = np.array([i.terrain_fraction for i in images], float)
    y = np.asarray(cycles_cpu_s, float)
    ok = np.isfinite(y) & (x > 0)
    x, f, y = x[ok], f[ok], y[ok]
    if len(y) == 0:
        raise ValueError("no measured frame to fit the render speed to")
    terrain = background = None
    if len(y) >= 3 and np.ptp(f) > 0.2:
        A = np.column_stack([x * (1 - f), x * f])
        (b, t), *_ = np.linalg.lstsq(A, y, rcond=None)
        if t > 0 and 0 <= b <= t:
            terrain, background = float(t), float(b)
    if terrain is None:
        ratio = prior.background_cpu_s_per_mp_sample / prior.terrain_cpu_s_per_mp_sample
        per = x * (ratio + f * (1 - ratio))
        terrain = float(np.sum(y) / np.sum(per))
        background = terrain * ratio
    mp = np.array([i.megapixels for i in images], float)[ok]
    post = np.asarray(post_s, float)[ok]
    post_per_mp = float(np.sum(post) / np.sum(mp)) if np.all(np.isfinite(post)) else \
        prior.post_s_per_mp
    return RenderSpeed(terrain, background, post_per_mp, max(0.0, float(fixed_s)), source,
                       time.strftime("%Y-%m-%d %H:%M"), len(y))


def terrain_fractions(heightfield, C_world: np.ndarray, R_cam_to_world: np.ndarray,
                      interior, grid: tuple[int, int] = FRACTION_GRID) -> np.ndarray:
    """(N,) share of each image's pixels whose ray meets the terrain, from a grid of
    ``grid`` rays over the image (cols × rows at cell centres); 1 without a heightfield
    (a mesh terrain: assumed to fill the image)."""
    n = len(C_world)
    if heightfield is None or n == 0:
        return np.ones(n)
    from designer.core.projection import pixel_rays_world

    W, H = interior.image_size_px
    u = (np.arange(grid[0]) + 0.5) * W / grid[0]
    v = (np.arange(grid[1]) + 0.5) * H / grid[1]
    uv = np.column_stack([np.tile(u, len(v)), np.repeat(v, len(u))])
    rays_cam = pixel_rays_world(uv, np.eye(3), interior)  # the same rays in every image
    C = np.asarray(C_world, dtype=float).reshape(n, 3)
    R = np.asarray(R_cam_to_world, dtype=float).reshape(n, 3, 3)
    # every image's rays at once: only hit or miss is used (past the terrain's edge is a
    # miss), which the ray caster decides without casting most of them
    from designer.core.raycast import raycaster_of

    rays = np.einsum("kij,rj->kri", R, rays_cam).reshape(-1, 3)
    seen = raycaster_of(heightfield).sees_surface(np.repeat(C, len(uv), axis=0), rays)
    return seen.reshape(n, len(uv)).mean(axis=1)


def refine(stored: RenderSpeed, measured: RenderSpeed) -> RenderSpeed:
    """The coefficients after a render: the render's own where it had at least
    :data:`FULL_WEIGHT_IMAGES` images (or nothing was measured here before), else a
    blend weighted by image counts."""
    if not stored.calibrated or measured.images >= FULL_WEIGHT_IMAGES:
        return measured
    a = min(stored.images, FULL_WEIGHT_IMAGES)
    b = measured.images
    def mix(x, y):
        return (a * x + b * y) / (a + b)
    return replace(measured, images=a + b, **{
        k: mix(getattr(stored, k), getattr(measured, k))
        for k in ("terrain_cpu_s_per_mp_sample", "background_cpu_s_per_mp_sample",
                  "post_s_per_mp", "fixed_s")})


def render_workers(project, n_images: int, cores: int | None = None) -> int:
    """The worker processes a render of ``project`` uses (its ``<render workers>``, else
    :func:`default_workers`)."""
    return max(1, project.render.workers or default_workers(max(1, n_images), cores))


def texture_path(has_variation: bool, whole_bake_px: tuple[int, int],
                 declared_bake_px: tuple[int, int], grown: bool, heightfield: bool) -> str:
    """How the renderer draws a ground texture (TEXTURE_PATH_CYCLES), as
    :func:`designer.render.job.prepare_job` chooses: ``whole_bake_px`` and
    ``declared_bake_px`` are the (W, H) of its bake over the rendered and the declared
    terrain; ``grown``: the rendered terrain has surroundings; ``heightfield``: the
    terrain is a height field of small faces (not a mesh, nor a flat terrain's two
    triangles)."""
    from designer.project.scene_limits import MAX_BAKE_PX

    def fits(px):
        return 0 < px[0] <= MAX_BAKE_PX and 0 < px[1] <= MAX_BAKE_PX

    if not has_variation or fits(whole_bake_px):
        return "baked"
    if grown and fits(declared_bake_px):
        return "baked"  # a detail bake over the declared terrain, a coarse one beyond
    return "tiled" if heightfield else "node-graph"


def project_texture_path(project, rendered_extent_m, texture_px: tuple[int, int] | None = None
                         ) -> str:
    """:func:`texture_path` of a project whose rendered terrain spans ``rendered_extent_m``
    (x0, x1, y0, y1; None: a mesh terrain); ``texture_px`` (W, H) the tiled texture image's
    size (a procedural texture's is computed from its texel; an image texture of unknown
    size counts as baked)."""
    return project_texture(project, rendered_extent_m, texture_px)[0]


def project_bake_mp(project, rendered_extent_m, texture_px: tuple[int, int] | None = None
                    ) -> float | None:
    """Megapixels of the ground texture bake a render of the project prepares (arguments
    of :func:`project_texture_path`): the whole bake, or the detail bake over the declared
    terrain where the surroundings are baked coarsely (whose small coarse bake is not
    counted); 0 where nothing is baked before the frames (a texture without variation, an
    orthophoto, the tiled and node-graph paths); None where the texture's size is
    unknown."""
    return project_texture(project, rendered_extent_m, texture_px)[1]


def project_texture(project, rendered_extent_m, texture_px: tuple[int, int] | None = None
                    ) -> tuple[str, float | None]:
    """(:func:`project_texture_path`, :func:`project_bake_mp`)."""
    tex = project.scene.texture
    src = tex.source
    e = project.scene.terrain.extent
    if tex.variation is None or type(src).__name__ == "OrthophotoTexture":
        return "baked", 0.0
    if texture_px is None:
        texel = getattr(src, "texel_size_m", None)
        if texel is None:
            return "baked", None
        texture_px = (round(e.width_m / tex.repeat_X / texel),
                      round(e.length_m / tex.repeat_Y / texel))
    texel_x = e.width_m / tex.repeat_X / texture_px[0]
    texel_y = e.length_m / tex.repeat_Y / texture_px[1]
    declared = (round(e.width_m / texel_x), round(e.length_m / texel_y))
    if rendered_extent_m is None:
        path = texture_path(True, declared, declared, False, False)
        return path, declared[0] * declared[1] / 1e6 if path == "baked" else 0.0
    x0, x1, y0, y1 = rendered_extent_m
    whole = (round((x1 - x0) / texel_x), round((y1 - y0) / texel_y))
    grown = whole[0] > declared[0] or whole[1] > declared[1]
    # a flat terrain is two triangles, too wide to tile (render.job_tiles.needs_tiles)
    fine = type(project.scene.terrain.source).__name__ != "FlatTerrain"
    path = texture_path(True, whole, declared, grown, fine)
    if path != "baked":
        return path, 0.0
    from designer.project.scene_limits import MAX_BAKE_PX

    baked = whole if max(whole) <= MAX_BAKE_PX else declared
    return path, baked[0] * baked[1] / 1e6


def image_costs(heightfield, C_world: np.ndarray, R_cam_to_world: np.ndarray,
                interiors: Sequence, samples: int, project=None,
                texture: str = "baked", bake_mp: float | None = None) -> list[ImageCost]:
    """The model's view of N images: size (megapixels of each image's rendered interior),
    ``samples`` per pixel and the share of its pixels that see the terrain
    (``terrain_fractions``). ``C_world`` (N, 3) m and ``R_cam_to_world`` (N, 3, 3) are the
    images' poses, ``interiors`` their N rendered interior orientations; images sharing
    one interior object are measured together. ``project``: the images' project, whose
    scene kind and effects file them (:func:`cost_key`); ``texture`` the renderer's path
    for the ground texture (:func:`texture_path`), ``bake_mp`` the megapixels of its bake
    (:func:`project_bake_mp`)."""
    kind = ({"scene": scene_kind(project), "effects": effects_key(project)}
            if project is not None else {})
    kind["texture"] = texture
    kind["bake_mp"] = bake_mp
    C_world, R_cam_to_world = np.asarray(C_world, float), np.asarray(R_cam_to_world, float)
    groups: dict[int, list[int]] = {}
    for k, interior in enumerate(interiors):
        groups.setdefault(id(interior), []).append(k)
    out: list[ImageCost | None] = [None] * len(interiors)
    for members in groups.values():
        interior = interiors[members[0]]
        fractions = terrain_fractions(heightfield, C_world[members], R_cam_to_world[members],
                                      interior)
        W, H = interior.image_size_px
        for k, f in zip(members, fractions, strict=True):
            out[k] = ImageCost(W * H / 1e6, samples, float(f), **kind)
    return out


def project_image_costs(project, images, heightfield,
                        texture_px: tuple[int, int] | None = None) -> list[ImageCost]:
    """``image_costs`` of every image of a project (``images``:
    :func:`designer.survey.project_poses.project_images`), all cameras of a rig, at the
    project's samples per pixel, over the rendered terrain ``heightfield``;
    ``texture_px``: an image texture's size (:func:`project_texture_path`)."""
    from designer.project.interiors import render_interior

    interiors = {c: render_interior(project.camera(c), project.render.resolution_scale)
                 for c in images.camera_order()}
    st = images.stations
    texture, bake_mp = project_texture(project, None if heightfield is None
                                       else heightfield.extent_m, texture_px)
    return image_costs(heightfield, np.array([s.C_world for s in st]).reshape(-1, 3),
                       np.array([s.R_cam_to_world for s in st]).reshape(-1, 3, 3),
                       [interiors[c] for c in images.camera_ids],
                       project.render.effective_samples, project, texture, bake_mp)


def format_duration(seconds: float) -> str:
    """'45 s', '3.6 min', '2.4 h': never '0.0 min'."""
    if seconds < 90:
        return f"{max(1, round(seconds))} s"
    if seconds < 5400:
        return f"{seconds / 60:.1f} min"
    return f"{seconds / 3600:.1f} h"
