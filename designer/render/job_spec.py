"""The render job: the one typed interface between designer and its Blender workers.

``job.json`` is written by :mod:`designer.render.job` (a survey) or
:mod:`designer.experiments.jobs` (a validation scene) and read by the worker, the local
runner, the cluster runner and the pipeline — always through :class:`RenderJob`, whose
fields carry the only defaults. Everything in it is local (world − ``origin_world``):
Blender stores float32. No bpy and no numpy here, so the worker and every reader load
the same small module.

The job is self-contained: with the scene files beside it, it is all a worker reads —
the camera effects too (the project's effects model and each camera's interior
orientation, :class:`EffectsSpec`). It is written and read by the generic codec
(:mod:`designer.core.codec`) over these dataclasses' type hints, so a new part needs no
code here, and reading refuses a field no part has, naming its place. Reading a job
with camera effects imports their types (the interior orientation brings numpy).
"""

from __future__ import annotations

import json
from collections.abc import Iterator, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

from designer.atomic import write_text_atomic
from designer.core.codec import CodecError, from_data, reachable_dataclasses, to_data
from designer.errors import DesignerError

if TYPE_CHECKING:  # loaded when a job with camera effects is read (_TYPES)
    from designer.core.interior import InteriorOrientation
    from designer.project.model import Effects

#: Blender's image formats the worker writes: job name → (Blender format, file extension)
IMAGE_FORMATS = {"png": ("PNG", ".png"), "tiff": ("TIFF", ".tif")}
PIXEL_FILTER_NAMES = ("BOX", "GAUSSIAN", "BLACKMAN_HARRIS")
INTERPOLATIONS = ("Closest", "Linear", "Cubic")
EXTENSIONS = ("REPEAT", "EXTEND", "CLIP")
TEXTURE_COLORSPACES = ("sRGB", "Non-Color")
#: name of the second uv layer (mesh .npz array ``uv_texture``) a material may look up
TEXTURE_UV_MAP = "TextureUV"


class JobError(DesignerError, ValueError):
    """A job.json that cannot be read as a render job (message names the file and fix)."""


#: the sky seen above the horizon by images that look towards it (linear RGB; the
#: renderer's background, black otherwise: designer.render.terrain_bake): a clear,
#: slightly hazy blue
SKY_RGB = (0.50, 0.66, 0.92)


@dataclass(frozen=True)
class AdaptiveSampling:
    """Cycles' adaptive sampling: flat pixels stop early, samples go to the edges."""

    threshold: float = 0.01
    min_samples: int = 0


@dataclass(frozen=True)
class RenderSpec:
    """Cycles settings of a job (samples per pixel, pixel filter, output encoding)."""

    samples: int
    seed: int = 0
    pixel_filter: str = "BOX"
    filter_width_px: float = 1.0
    format: str = "png"
    bit_depth: int = 8
    #: the preset asked for on the command line (recorded in the manifest), if any
    quality: str | None = None
    adaptive_sampling: AdaptiveSampling | None = None
    #: Cycles threads per worker process, 0 = all cores (set by the runner per worker)
    threads: int = 0

    def __post_init__(self) -> None:
        if self.samples < 1:
            raise JobError(f"render samples = {self.samples}; must be >= 1")
        if self.pixel_filter not in PIXEL_FILTER_NAMES:
            raise JobError(f"pixel filter {self.pixel_filter!r}; use one of "
                           f"{', '.join(PIXEL_FILTER_NAMES)}")
        if self.format not in IMAGE_FORMATS:
            raise JobError(f"image format {self.format!r}; use one of {', '.join(IMAGE_FORMATS)}")
        if self.bit_depth not in (8, 16):
            raise JobError(f"bit depth {self.bit_depth}; use 8 or 16")

    @property
    def extension(self) -> str:
        return IMAGE_FORMATS[self.format][1]


@dataclass(frozen=True)
class CameraSpec:
    """Blender camera-data settings, in Blender's own terms (see blender_camera)."""

    lens_mm: float
    sensor_width_mm: float
    sensor_fit: str
    shift_x: float
    shift_y: float
    resolution_x_px: int
    resolution_y_px: int
    pixel_aspect_x: float
    pixel_aspect_y: float
    clip_start_m: float = 0.01
    clip_end_m: float = 1e5


@dataclass(frozen=True)
class MaterialSpec:
    """An emission material: a plain colour, or a tiled texture (optionally varied) × an
    optional light map.

    ``strength`` scales the emission (a light map stores L / strength to fit 16 bits).
    """

    color: tuple[float, float, float] | None = None
    texture: str | None = None
    uv_tiles: tuple[float, float] = (1.0, 1.0)
    interpolation: str = "Closest"
    lightmap: str | None = None
    strength: float = 1.0
    #: uv layer of the texture lookup: None = the mesh's ``uv`` (the light map's too),
    #: TEXTURE_UV_MAP = its ``uv_texture`` (an orthophoto placed by its geotransform)
    uv_map: str | None = None
    #: Blender image extension outside [0, 1]: REPEAT (tiles), EXTEND (edge texels), CLIP
    extension: str = "REPEAT"
    #: texture variation (designer.scene.texture_variation): 16-bit images over the UV
    #: 0..1 square of gain / 2, mix_a, mix_b and of the lookup warp (u, v encoded as
    #: 0.5 + warp / (2 variation_warp_uv)); None: the plain tiled texture
    variation: str | None = None
    variation_warp: str | None = None
    variation_warp_uv: float = 0.0
    #: how the texture's values are read: "sRGB" (8-bit codes, decoded after
    #: interpolation) or "Non-Color" (linear light, e.g. the 16-bit bake of a varied
    #: texture, designer.render.texture_bake, held as half floats)
    texture_colorspace: str = "sRGB"

    def __post_init__(self) -> None:
        if (self.color is None) == (self.texture is None):
            raise JobError("a material needs exactly one of 'color' and 'texture'")
        if self.extension not in EXTENSIONS:
            raise JobError(f"texture extension {self.extension!r}; use one of "
                           f"{', '.join(EXTENSIONS)}")
        if self.interpolation not in INTERPOLATIONS:
            raise JobError(f"texture interpolation {self.interpolation!r}; use one of "
                           f"{', '.join(INTERPOLATIONS)}")
        if self.texture_colorspace not in TEXTURE_COLORSPACES:
            raise JobError(f"texture colour space {self.texture_colorspace!r}; use one of "
                           f"{', '.join(TEXTURE_COLORSPACES)}")


@dataclass(frozen=True)
class MeshSpec:
    """One mesh object: an .npz beside job.json (vertices_local, faces, optional uv,
    uv_texture and material_index) and its materials."""

    name: str
    mesh: str
    materials: tuple[MaterialSpec, ...]


@dataclass(frozen=True)
class PlantSetSpec:
    """One plant group: its template mesh (an .npz beside job.json in the plant's frame:
    ``vertices_local``, ``faces``, ``material_index``) instanced at every plant of the
    ``instances`` .npz (``base_local`` (N, 3) m, ``scale`` (N, 3), ``yaw_rad``,
    ``phase_rad``), with its materials (foliage, wood)."""

    name: str
    template: str
    instances: str
    materials: tuple[MaterialSpec, ...]


@dataclass(frozen=True)
class WindSpec:
    """The plants' sway (designer.scene.vegetation): lean amplitude (deg), period (s) and
    the direction the wind blows to (deg clockwise from grid north)."""

    amplitude_deg: float
    gust_period_s: float
    direction_deg: float


@dataclass(frozen=True)
class CameraEffectsSpec:
    """One camera's part of the camera effects: its interior orientation as rendered
    (:class:`~designer.core.interior.InteriorOrientation`, with its lens distortion) and
    its cached distortion warp, a file beside job.json (None: no distortion)."""

    interior: InteriorOrientation
    warp: str | None = None


@dataclass(frozen=True)
class EffectsSpec:
    """The camera effects: all the worker needs to build each camera's effect chain
    (:func:`designer.effects.from_model.effects_from_model`) — the project's effects model
    (None: distortion only) and each camera's interior and warp.

    ``cameras``: camera id → its part, for every camera whose images have effects. One
    camera (``rig`` False): its single entry is every frame's. A multi-camera rig
    (``rig`` True): frames name their camera (:attr:`FrameSpec.camera_id`), and a camera
    absent here has images final as rendered.
    """

    model: Effects | None
    cameras: dict[str, CameraEffectsSpec]
    rig: bool = False


@dataclass(frozen=True)
class FrameSpec:
    """One image: its camera matrix in the local frame, what the effects need of it
    (GSD m/px, flight direction in the image, distance to the ground m) and, with a time
    line, when it is taken and the sun then (docs/world.md).

    ``time_s`` is seconds after take-off, ``time_utc`` the same moment as ISO 8601 UTC
    text ('2026-06-21T09:30:04.250000Z'); ``sun_azimuth_deg`` (clockwise from grid
    north) and ``sun_elevation_deg`` the sun the frame is lit by; ``light_step`` the
    index into :attr:`RenderJob.light_steps` of its lighting (None: the job's objects as
    they are). All None for a project without a time line (the static ideal).
    """

    index: int
    image_name: str
    matrix_world_local: tuple[tuple[float, ...], ...]
    gsd_m: float | None = None
    flight_direction_uv: tuple[float, float] | None = None
    distance_m: float | None = None
    time_s: float | None = None
    time_utc: str | None = None
    sun_azimuth_deg: float | None = None
    sun_elevation_deg: float | None = None
    light_step: int | None = None
    #: per moving object (RenderJob.moving_objects, same order): (name, X, Y, Z local m
    #: of its base centre, heading deg clockwise from grid north) at ``time_s``
    moving_poses: tuple[tuple[str, float, float, float, float], ...] | None = None
    #: a rolling-shutter camera (designer.render.job_rolling): the camera matrices (local)
    #: at the start and the end of Cycles' shutter, between which it moves linearly while
    #: the rows are read; None: a global shutter (``matrix_world_local`` only)
    shutter_matrices_local: tuple[tuple[tuple[float, ...], ...], ...] | None = None
    #: this frame's camera when a multi-camera rig gives frames different cameras
    #: (lens, sensor, resolution as rendered), the project camera's id and the finished
    #: image's (width, height) px; None: the job's ``camera``, width_px and height_px
    camera: CameraSpec | None = None
    camera_id: str | None = None
    size_px: tuple[int, int] | None = None
    #: a tiled texture (RenderJob.tiled_texture): the tiles this frame sees, loaded
    #: before it renders
    texture_tiles: tuple[int, ...] | None = None


#: FrameSpec fields left out of job.json and of provenance when None, so a job without
#: them reads and hashes as before they existed
OPTIONAL_FRAME_FIELDS = ("camera", "camera_id", "size_px", "texture_tiles")


@dataclass(frozen=True)
class TiledTextureSpec:
    """A varied ground texture baked in tiles (designer.render.tiled_bake): the inputs of
    the bake (the detail texture, its repeats and interpolation, the variation images and
    warp bound, the light map folded in or None), the grid (the whole bake's ``full_px``
    (W, H), ``core_px`` and ``pad_px``), ``digest`` naming the tiles' files, the terrain
    materials ``first_material`` … + columns · rows − 1 that show them, and ``coarse``:
    the bake over the whole terrain those materials show where a frame loads no tile."""

    texture: str
    uv_tiles: tuple[float, float]
    interpolation: str
    variation: str
    variation_warp: str
    variation_warp_uv: float
    full_px: tuple[int, int]
    core_px: int
    pad_px: int
    slots: tuple[int, int]
    digest: str
    coarse: str
    lightmap: str | None = None
    first_material: int = 0


#: the FrameSpec fields of the world over time, left out of provenance when None
TIME_FIELDS = ("time_s", "time_utc", "sun_azimuth_deg", "sun_elevation_deg", "light_step",
               "moving_poses", "shutter_matrices_local")


@dataclass(frozen=True)
class LightStep:
    """The scene's lit objects under one sun: replaces :attr:`RenderJob.objects` of the
    same names for the frames whose ``light_step`` points here. A spec with the same mesh
    file as the object already built only changes its materials (light map, colours)."""

    sun_azimuth_deg: float
    sun_elevation_deg: float
    objects: tuple[MeshSpec, ...]


@dataclass(frozen=True)
class RenderJob:
    """Everything a worker needs to render a set of frames; see the module docstring."""

    #: absolute folder the images are renamed into when complete; while rendering they
    #: are in the job folder's ``partial/`` (never in this folder)
    output_dir: str
    render: RenderSpec
    camera: CameraSpec
    objects: tuple[MeshSpec, ...]
    frames: tuple[FrameSpec, ...]
    width_px: int
    height_px: int
    origin_world: tuple[float, float, float] = (0.0, 0.0, 0.0)
    background_rgb: tuple[float, float, float] = (0.0, 0.0, 0.0)
    effects: EffectsSpec | None = None
    designer_version: str | None = None
    project: str | None = None
    #: the lighting of each sun over the flight (empty: one sun, ``objects`` as built)
    light_steps: tuple[LightStep, ...] = ()
    #: "exif": the worker writes each frame's ``time_utc`` into its image's EXIF
    image_metadata: str = "none"
    #: moving objects, each mesh in its own frame (base centre at 0, +Y forward, m),
    #: posed per frame by FrameSpec.moving_poses
    moving_objects: tuple[MeshSpec, ...] = ()
    #: plant groups, each one template instanced at its plants, posed per frame at its
    #: ``time_s`` by ``wind`` (upright without a time or wind)
    vegetation: tuple[PlantSetSpec, ...] = ()
    wind: WindSpec | None = None
    #: a ground texture baked in tiles, loaded per frame (None: none; left out of
    #: job.json then)
    tiled_texture: TiledTextureSpec | None = None
    image_names: dict[int, str] = field(init=False, repr=False, compare=False)
    _frames_by_index: dict[int, FrameSpec] = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        names = {f.index: f.image_name for f in self.frames}
        if len(names) != len(self.frames):
            raise JobError("frame indices repeat in the job")
        for f in self.frames:
            if f.light_step is not None and not 0 <= f.light_step < len(self.light_steps):
                raise JobError(f"frame {f.index} has light step {f.light_step}, but the job "
                               f"has {len(self.light_steps)}")
        names = {o.name for o in self.moving_objects}
        for f in self.frames:
            if f.moving_poses is not None and {p[0] for p in f.moving_poses} != names:
                raise JobError(f"frame {f.index} poses other moving objects than the job has")
        if self.image_metadata not in ("none", "exif"):
            raise JobError(f"image metadata {self.image_metadata!r}; use none or exif")
        object.__setattr__(self, "image_names",
                           {f.index: f.image_name for f in self.frames})
        object.__setattr__(self, "_frames_by_index", {f.index: f for f in self.frames})

    def to_json(self) -> str:
        data = to_data(self, RenderJob, _TYPES)
        if data["tiled_texture"] is None:
            del data["tiled_texture"]
        for frame in data["frames"]:
            for key in OPTIONAL_FRAME_FIELDS:
                if frame[key] is None:
                    del frame[key]
        return json.dumps(data, indent=1)

    def frame_size_px(self, index: int) -> tuple[int, int]:
        """(width, height) of the image of frame ``index``."""
        frame = self._frames_by_index[index]
        return self.frame_size(frame)

    def frame_size(self, frame: FrameSpec) -> tuple[int, int]:
        """(width, height) of a frame's finished image."""
        if frame.size_px is None:
            return self.width_px, self.height_px
        return tuple(frame.size_px)

    def frame_camera(self, frame: FrameSpec) -> CameraSpec:
        """The camera a frame is rendered with (its own, or the job's)."""
        return frame.camera if frame.camera is not None else self.camera

    @classmethod
    def from_json(cls, text: str, source: str = "job.json") -> RenderJob:
        """The job ``text`` describes. Every part is read by its type hints
        (:mod:`designer.core.codec`): a field no part has, a missing one or a value of the
        wrong kind is a JobError naming the file and the place (``frames[3].foo``)."""
        try:
            return from_data(cls, json.loads(text), "", _TYPES)
        except CodecError as error:
            raise JobError(f"{source}: {error.place}: {error.problem}; not a render job of "
                           "this designer version — prepare it again with 'designer render'"
                           ) from error
        except DesignerError as error:
            raise JobError(f"{source}: {error}") from error
        except ValueError as error:  # not JSON
            raise JobError(f"{source}: not a render job ({error}); prepare it again with "
                           "'designer render'") from error

    def write(self, path: Path) -> Path:
        write_text_atomic(Path(path), self.to_json())
        return Path(path)

    @classmethod
    def read(cls, path: Path) -> RenderJob:
        path = Path(path)
        try:
            text = path.read_text()
        except OSError as error:
            raise JobError(f"{path}: cannot read the render job ({error.strerror})") from error
        return cls.from_json(text, str(path))


#: the names imported only for type checking → their modules
_TYPE_MODULES = {"InteriorOrientation": "designer.core.interior",
                 "Effects": "designer.project.model"}


class _LazyTypes(Mapping):
    """The names this module imports only for type checking, imported when a type hint
    needs them (reading a job's camera effects), so importing it stays light."""

    def __getitem__(self, name: str):
        if name not in _TYPE_MODULES:
            raise KeyError(name)
        import importlib

        return getattr(importlib.import_module(_TYPE_MODULES[name]), name)

    def __iter__(self) -> Iterator[str]:
        return iter(_TYPE_MODULES)

    def __len__(self) -> int:
        return len(_TYPE_MODULES)


_TYPES = _LazyTypes()


def job_dataclasses() -> list[type]:
    """Every dataclass a render job may hold, RenderJob first (what job.json is made of)."""
    return reachable_dataclasses(RenderJob, _TYPES)
