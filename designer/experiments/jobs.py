"""Render small validation scenes through the ordinary render worker.

A scene is a list of :class:`MeshObject` (local coordinates, emission materials) and a
list of camera poses; :func:`render_views` writes the mesh, texture and job files the
worker reads (``designer.render.worker``), runs it with ``designer.render.runner`` and
returns the image paths with the render seconds per image.

Oversampling (``RenderSettings.oversample`` = k) renders the same camera k× larger —
same focal length and principal point in mm, so every output pixel is exactly k × k
render pixels — as 16-bit PNG, decodes sRGB to linear light, averages the blocks and
encodes 8-bit sRGB again: area sampling with k² stratified positions per pixel.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path

import cv2
import numpy as np

from designer.atomic import atomic_path
from designer.core.interior import InteriorOrientation
from designer.effects.resample import block_mean
from designer.effects.srgb import decode_image, encode_image
from designer.errors import DesignerError
from designer.experiments.settings import RenderSettings
from designer.render.blender_camera import blender_camera, blender_matrix_world
from designer.render.job_spec import FrameSpec, MaterialSpec, MeshSpec, RenderJob
from designer.render.runner import render_frames


@dataclass(frozen=True)
class MeshObject:
    """One mesh in local coordinates (m) with emission materials.

    A textured material names a key of ``textures`` (file name → (H, W, 3) uint8 RGB
    image) and gets the settings' interpolation.
    """

    name: str
    vertices_local: np.ndarray
    faces: np.ndarray
    materials: tuple[MaterialSpec, ...]
    uv: np.ndarray | None = None
    material_index: np.ndarray | None = None
    textures: dict[str, np.ndarray] = field(default_factory=dict)


@dataclass(frozen=True)
class RenderedViews:
    """Rendered images (sRGB PNG, in pose order), wall and CPU seconds per image.

    ``seconds`` is the worker's time for the frame (render call and file); ``cpu_seconds``
    the CPU time of the render call over all its threads (machine load disturbs it much
    less than wall time). Both include the oversampling's downsampling, if any.
    """

    paths: list[Path]
    seconds: list[float]
    interior: InteriorOrientation
    settings: RenderSettings
    cpu_seconds: list[float] = field(default_factory=list)

    def gray(self, k: int) -> np.ndarray:
        """Image ``k`` as (H, W) uint8 grey (the scenes are black and white)."""
        image = self.codes(k)
        if image.dtype == np.uint16:
            image = np.rint(image / 257.0).astype(np.uint8)
        return image

    def codes(self, k: int) -> np.ndarray:
        """Image ``k``'s green channel as stored (H, W), uint8 or uint16 sRGB codes."""
        image = cv2.imread(str(self.paths[k]), cv2.IMREAD_UNCHANGED)
        if image is None:
            raise DesignerError(f"cannot read the rendered image {self.paths[k]}")
        return image[:, :, 1] if image.ndim == 3 else image

    def linear(self, k: int) -> np.ndarray:
        """Image ``k`` as (H, W) float32 linear light (sRGB decoded exactly)."""
        return decode_image(self.codes(k))

    @property
    def megapixels(self) -> float:
        W, H = self.interior.image_size_px
        return W * H / 1e6


def scaled_interior(interior: InteriorOrientation, k: int) -> InteriorOrientation:
    """The same camera with k× the pixels (same f, sensor and principal point in mm)."""
    W, H = interior.image_size_px
    return replace(interior, image_width_px=W * k, image_height_px=H * k)


def write_job(folder: Path, objects: Sequence[MeshObject], interior: InteriorOrientation,
              poses: Sequence[tuple[np.ndarray, np.ndarray]], settings: RenderSettings,
              out_dir: Path, *, background_rgb=(0.0, 0.0, 0.0), seed: int = 0,
              prefix: str = "view", bit_depth: int = 8) -> Path:
    """Write mesh/texture files and job.json under ``folder``; return the job path.

    ``poses`` are (C_local (3,), R_cam_to_world (3, 3)); images go to ``out_dir`` as
    ``{prefix}_{k:04d}.png``.
    """
    folder.mkdir(parents=True, exist_ok=True)
    render_interior = scaled_interior(interior, settings.oversample)
    job_objects = []
    for obj in objects:
        arrays = {"vertices_local": np.asarray(obj.vertices_local, float),
                  "faces": np.asarray(obj.faces, np.int64)}
        if obj.uv is not None:
            arrays["uv"] = np.asarray(obj.uv, float)
        if obj.material_index is not None:
            arrays["material_index"] = np.asarray(obj.material_index, np.int64)
        with atomic_path(folder / f"{obj.name}.npz") as tmp, open(tmp, "wb") as f:
            np.savez(f, **arrays)
        for name, rgb in obj.textures.items():
            with atomic_path(folder / name) as tmp:
                if not cv2.imwrite(str(tmp), cv2.cvtColor(rgb, cv2.COLOR_RGB2BGR)):
                    raise OSError(f"could not write {folder / name}")
        materials = tuple(replace(m, interpolation=settings.interpolation)
                          if m.texture is not None else m for m in obj.materials)
        job_objects.append(MeshSpec(obj.name, f"{obj.name}.npz", materials))
    W, H = render_interior.image_size_px
    job = RenderJob(
        output_dir=str(Path(out_dir).resolve()),
        # Oversampled renders are averaged in linear light: keep 16 bits until then.
        render=replace(settings.job_render(seed),
                       bit_depth=16 if settings.oversample > 1 else bit_depth),
        background_rgb=tuple(float(c) for c in background_rgb),
        camera=blender_camera(render_interior),
        width_px=W, height_px=H,
        objects=tuple(job_objects),
        frames=tuple(FrameSpec(index=k, image_name=_name(prefix, k, settings),
                               matrix_world_local=tuple(tuple(float(v) for v in row) for row in
                                                        blender_matrix_world(C, R, np.zeros(3))))
                     for k, (C, R) in enumerate(poses)),
    )
    return job.write(folder / "job.json")


def _name(prefix: str, k: int, settings: RenderSettings) -> str:
    return f"{prefix}_{k:04d}{'_big' if settings.oversample > 1 else ''}.png"


def render_views(folder: Path, objects: Sequence[MeshObject], interior: InteriorOrientation,
                 poses: Sequence[tuple[np.ndarray, np.ndarray]], settings: RenderSettings,
                 *, background_rgb=(0.0, 0.0, 0.0), seed: int = 0, prefix: str = "view",
                 bit_depth: int = 8, workers: int | None = None,
                 progress: Callable[[dict], None] | None = None) -> RenderedViews:
    """Render ``poses`` of the scene into ``folder/images``; see :func:`write_job`."""
    folder = Path(folder)
    out_dir = folder / "images"
    job_path = write_job(folder / "job", objects, interior, poses, settings, out_dir,
                         background_rgb=background_rgb, seed=seed, prefix=prefix,
                         bit_depth=bit_depth)
    cpu: dict[int, float] = {}

    def on_event(event: dict) -> None:
        if event.get("event") == "frame_done":
            cpu[int(event["index"])] = float(event.get("render_cpu_seconds", math.nan))
        if progress is not None:
            progress(event)

    report = render_frames(job_path, list(range(len(poses))), workers=workers,
                           progress=on_event)
    if report.failed:
        log = folder / "job" / "logs"
        raise DesignerError(f"Cycles failed to render {len(report.failed)} validation image(s) "
                            f"(frames {report.failed[:5]}); see the worker logs in {log}")
    paths, seconds, cpu_seconds = [], [], []
    for k in range(len(poses)):
        path = out_dir / _name(prefix, k, settings)
        t, c = report.rendered[k], cpu.get(k, math.nan)
        if settings.oversample > 1:
            t0, c0 = time.perf_counter(), time.process_time()
            path = _downsample(path, settings.oversample, np.uint16 if bit_depth == 16
                               else np.uint8)
            t += time.perf_counter() - t0
            c += time.process_time() - c0
        paths.append(path)
        seconds.append(t)
        cpu_seconds.append(c)
    return RenderedViews(paths, seconds, interior, settings, cpu_seconds)


def _downsample(big_path: Path, k: int, dtype) -> Path:
    """k× render (16-bit sRGB) → area-averaged sRGB image (``dtype``) beside it; the big
    one is deleted."""
    big = cv2.imread(str(big_path), cv2.IMREAD_UNCHANGED)
    if big is None:
        raise DesignerError(f"cannot read the rendered image {big_path}")
    small = encode_image(block_mean(decode_image(big), k), dtype)
    path = big_path.with_name(big_path.name.replace("_big", ""))
    with atomic_path(path) as tmp:
        if not cv2.imwrite(str(tmp), small):
            raise OSError(f"could not write {path}")
    big_path.unlink()
    return path
