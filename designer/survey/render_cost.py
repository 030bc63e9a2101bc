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
bake, lens warp, Blender start-up).

The coefficients are this machine's (:class:`RenderSpeed`), kept in
``render-speed.json`` in designer's cache folder (``$DESIGNER_CACHE_DIR``, else
``$XDG_CACHE_HOME/designer``, else ``~/.cache/designer``). ``designer warmup`` (run by
``make setup``) measures them with a short probe render of the example survey, and every
``designer render`` refines them from its own frames (the manifest's per-stage
seconds). Without either, the estimate uses :data:`REFERENCE` and says it is
uncalibrated.

Not modelled: buildings, plants and moving objects (more geometry than the terrain),
adaptive sampling (metrology preset: counted at its maximum samples), a machine busy
with other work, and workers competing for the caches (two workers of one core each
render the example about 20 % slower than one worker with both cores, which the model
does not see: docs/benchmarks.md). A render of such a project refines the
coefficients towards it.
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
FULL_WEIGHT_IMAGES = 8


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

    @property
    def calibrated(self) -> bool:
        return self.source != "reference"

    def describe(self) -> str:
        """Where the estimate comes from, for reports and panels."""
        if not self.calibrated:
            return ("uncalibrated (reference figures; 'designer warmup' or a first render "
                    "measures this machine)")
        what = "probe render" if self.source == "probe" else "render"
        return f"this machine, {what} of {self.images} image(s) on {self.measured}"


#: Fitted to the example survey on the reference machine (2 cores, Blender 5.0.1, the
#: baked texture with the light map folded in, one worker; ``designer render`` of
#: ``designer new --template survey`` in ``make demo`` on a fresh clone: 60 images of
#: 1368 × 912 px at 16 spp, 20 % to 100 % of each on the terrain, render stage 161 s).
REFERENCE = RenderSpeed(terrain_cpu_s_per_mp_sample=0.301,
                        background_cpu_s_per_mp_sample=0.109, post_s_per_mp=0.175,
                        fixed_s=9.7)


def cache_dir() -> Path:
    """designer's cache folder (see the module docstring)."""
    if os.environ.get("DESIGNER_CACHE_DIR"):
        return Path(os.environ["DESIGNER_CACHE_DIR"])
    base = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    return Path(base) / "designer"


def load_speed() -> RenderSpeed:
    """This machine's coefficients, or :data:`REFERENCE` when none were measured (or the
    file is unreadable)."""
    path = cache_dir() / SPEED_FILE
    try:
        data = json.loads(path.read_text())
        speed = RenderSpeed(**{k: data[k] for k in RenderSpeed.__dataclass_fields__
                               if k in data})
    except (OSError, ValueError, TypeError):
        return REFERENCE
    values = (speed.terrain_cpu_s_per_mp_sample, speed.background_cpu_s_per_mp_sample,
              speed.post_s_per_mp, speed.fixed_s)
    if not all(math.isfinite(v) and v >= 0 for v in values):
        return REFERENCE
    return speed


def save_speed(speed: RenderSpeed) -> Path:
    """Store the coefficients atomically; returns the file."""
    from designer.atomic import write_text_atomic

    path = cache_dir() / SPEED_FILE
    path.parent.mkdir(parents=True, exist_ok=True)
    write_text_atomic(path, json.dumps(asdict(speed), indent=1))
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


def frame_cpu_s(speed: RenderSpeed, image: ImageCost) -> float:
    """Cycles CPU-seconds of one image."""
    per = (speed.background_cpu_s_per_mp_sample + image.terrain_fraction
           * (speed.terrain_cpu_s_per_mp_sample - speed.background_cpu_s_per_mp_sample))
    return image.megapixels * image.samples * per


def estimate_render_s(images: Sequence[ImageCost], workers: int, cores: int | None = None,
                      speed: RenderSpeed | None = None) -> float:
    """Wall seconds of the whole render stage (module docstring)."""
    speed = speed or load_speed()
    cores = max(1, cores or os.cpu_count() or 1)
    workers = max(1, min(workers, cores, max(1, len(images))))
    cpu = sum(frame_cpu_s(speed, i) for i in images)
    post = sum(i.megapixels * speed.post_s_per_mp for i in images)
    return speed.fixed_s + cpu / cores + post / workers


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
    rays_cam = None
    out = np.empty(n)
    for k in range(n):
        if rays_cam is None:  # the same pixel rays in every image of this camera
            rays_cam = pixel_rays_world(uv, np.eye(3), interior)
        rays = rays_cam @ np.asarray(R_cam_to_world[k]).T
        hits = heightfield.intersect_rays(np.broadcast_to(C_world[k], rays.shape), rays)
        out[k] = float(np.mean(np.isfinite(hits[:, 0])))
    return out


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


def image_costs(heightfield, C_world: np.ndarray, R_cam_to_world: np.ndarray,
                interiors: Sequence, samples: int) -> list[ImageCost]:
    """The model's view of N images: size (megapixels of each image's rendered interior),
    ``samples`` per pixel and the share of its pixels that see the terrain
    (``terrain_fractions``). ``C_world`` (N, 3) m and ``R_cam_to_world`` (N, 3, 3) are the
    images' poses, ``interiors`` their N rendered interior orientations; images sharing
    one interior object are measured together."""
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
            out[k] = ImageCost(W * H / 1e6, samples, float(f))
    return out


def project_image_costs(project, images, heightfield) -> list[ImageCost]:
    """``image_costs`` of every image of a project (``images``:
    :func:`designer.survey.project_poses.project_images`), all cameras of a rig, at the
    project's samples per pixel."""
    from designer.project.interiors import render_interior

    interiors = {c: render_interior(project.camera(c), project.render.resolution_scale)
                 for c in images.camera_order()}
    st = images.stations
    return image_costs(heightfield, np.array([s.C_world for s in st]).reshape(-1, 3),
                       np.array([s.R_cam_to_world for s in st]).reshape(-1, 3, 3),
                       [interiors[c] for c in images.camera_ids],
                       project.render.effective_samples)


def format_duration(seconds: float) -> str:
    """'45 s', '3.6 min', '2.4 h': never '0.0 min'."""
    if seconds < 90:
        return f"{max(1, round(seconds))} s"
    if seconds < 5400:
        return f"{seconds / 60:.1f} min"
    return f"{seconds / 3600:.1f} h"
