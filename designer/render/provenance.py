"""Render provenance: what each image and the ground truth were made from, as hashes.

Every image depends on parts of the render job (:class:`~designer.render.job_spec.RenderJob`)
and the files beside it; each part is hashed on its own (SHA-256 of a canonical
encoding), so a changed project re-renders exactly the images it changes and says why:

============  ===============================================================  =========
part          what goes in                                                      images
============  ===============================================================  =========
``software``  designer's version and the bpy package's version                 all
``render``    Cycles settings (samples, filter, seed, format, bit depth)       all
``camera``    the Blender camera (lens, sensor, shift, resolution)             all
``scene``     terrain mesh, texture (+ variation), light map, objects,        all /
              buildings (mesh, textures, light), sky; with a sun over time    per image
              the frame's own light step (its sun)
``targets``   GCP target materials; target geometry inside the frame's view    per image
``effects``   the camera-effects model, the camera's interior as rendered,     all /
              its distortion warp                                              per camera
``pose``      the frame's index, name, camera matrix (+ effect context, time)  per image
============  ===============================================================  =========

Beside the parts, each record keeps ``details`` that explain a change but decide nothing
(they are not in the digest): the image size, the camera without its size, the pose as
Blender uses it, and digests of the project's terrain, texture, lighting, GCP targets and
objects. :meth:`ImageProvenance.changed_parts` turns a changed part into what a person
changed ("image size 1368 × 912 → 684 × 456", "lighting"); a record written before the
details existed gets the part names.

Targets are hashed per frame: only the target vertices that project into the frame
(with a 25 % margin) count, so moving one GCP re-renders the images that see it. The
ground truth is hashed from the files it is written to (the exporters write text that is
a pure function of the project). Array files are hashed by content (dtype, shape,
bytes), never by their zip container, whose timestamps change on every write.
"""

from __future__ import annotations

import hashlib
import json
from dataclasses import asdict, dataclass, field
from functools import cache
from pathlib import Path

import numpy as np

from designer import __version__
from designer.render.job_spec import OPTIONAL_FRAME_FIELDS, TIME_FIELDS, FrameSpec, RenderJob

PARTS = ("software", "render", "camera", "scene", "targets", "effects", "pose")
#: the name the job builder gives the GCP targets' mesh (hashed per frame)
TARGETS_MESH = "gcp_targets"
#: fraction of the image added on every side when deciding which targets a frame sees
VIEW_MARGIN = 0.25


#: the project's parts a scene or targets change is explained by (details, model terms)
SCENE_REASONS = ("terrain", "texture", "lighting", "objects", "gcp targets")


@dataclass(frozen=True)
class ImageProvenance:
    """The hash of each part an image depends on, and of all of them together;
    ``details`` explain a change (see the module docstring) and are not in the digest."""

    parts: dict[str, str]
    details: dict = field(default_factory=dict, compare=False)

    @property
    def digest(self) -> str:
        return _digest(json.dumps(self.parts, sort_keys=True))

    def changed_parts(self, recorded: dict | None,
                      size_on_disk_px: tuple[int, int] | None = None) -> list[str]:
        """What changed since a manifest entry's ``inputs`` were recorded, in words of the
        project: the parts that differ, each refined by the details both records have
        (``["unrecorded"]`` without a record). ``size_on_disk_px`` (W, H): the size of
        the image file now there, which a record without details does not hold."""
        if not recorded:
            return ["unrecorded"]
        changed = [p for p in PARTS if recorded.get(p) != self.parts.get(p)]
        old = recorded.get("details") if isinstance(recorded.get("details"), dict) else {}
        new = self.details
        reasons: list[str] = []
        for part in changed:
            reasons += self._reasons(part, old, new, size_on_disk_px)
        if "pose" in reasons and "targets" in reasons:
            reasons.remove("targets")  # a moved camera sees other targets: that is the pose
        out = list(dict.fromkeys(reasons))
        if "effect context" in out and len(out) > 1:
            # the GSD or motion an effect reads changed because of what else changed
            out.remove("effect context")
        return out

    def _reasons(self, part: str, old: dict, new: dict, size_on_disk_px) -> list[str]:
        if part == "camera":
            before = tuple(size_on_disk_px or old.get("size_px") or ())
            after = tuple(new.get("size_px") or ())
            sized = bool(before and after and before != after)
            out = [size_reason(before, after)] if sized else []
            if not old.get("camera_unsized"):
                return out or ["camera"]
            if old.get("camera_unsized") != new.get("camera_unsized"):
                out.append("camera")
            return out or ["camera"]
        if part in ("scene", "targets"):
            return _scene_reasons(old, new) or [part]
        if part == "effects":
            if old.get("effects_model") and old.get("effects_model") == new.get("effects_model"):
                return ["effect context"]  # the camera they apply to changed
            return ["effects"]
        if part == "pose":
            if old.get("pose_blender") and old.get("pose_blender") == new.get("pose_blender"):
                return ["effect context"]  # only what the camera effects read changed
            return ["pose"]
        return [part]

    def to_json(self) -> dict:
        return {**self.parts, "digest": self.digest, "details": self.details}


def _scene_reasons(old: dict, new: dict) -> list[str]:
    """The project's scene parts whose digests differ (both records must have them)."""
    return [r for r in SCENE_REASONS
            if old.get(r) is not None and new.get(r) is not None and old[r] != new[r]]


def size_reason(before: tuple, after: tuple) -> str:
    """'image size 1368 × 912 → 684 × 456'."""
    return f"image size {before[0]} × {before[1]} → {after[0]} × {after[1]}"


def project_details(project) -> dict[str, str]:
    """Digests of the project's scene parts that explain a change (not in any digest
    that decides whether an image is up to date)."""
    scene = project.scene
    return {"terrain": _digest(repr(scene.terrain)), "texture": _digest(repr(scene.texture)),
            "lighting": _digest(repr(scene.lighting), repr(getattr(project, "timeline", None))),
            "objects": _digest(repr((scene.objects, scene.moving_objects, scene.buildings,
                                     scene.vegetation))),
            "gcp targets": _digest(repr(scene.targets))}


def _digest(*chunks: bytes | str) -> str:
    h = hashlib.sha256()
    for c in chunks:
        h.update(c.encode() if isinstance(c, str) else c)
        h.update(b"\x00")
    return h.hexdigest()[:32]


def _canonical(value) -> str:
    return json.dumps(value, sort_keys=True, separators=(",", ":"))


def _array_digest(array: np.ndarray) -> str:
    a = np.ascontiguousarray(array)
    return _digest(str(a.dtype), str(a.shape), a.tobytes())


def _file_digest(path: Path) -> str:
    if path.suffix == ".npz":
        with np.load(path) as data:
            return _digest(*(f"{k}={_array_digest(data[k])}" for k in sorted(data.files)))
    return _digest(path.read_bytes())


def _material_fields(mat) -> dict:
    """A material's fields; those of an absent texture variation and the default colour
    space are left out, so a material without them hashes as before they existed."""
    fields = asdict(mat)
    if mat.variation is None:
        for name in ("variation", "variation_warp", "variation_warp_uv"):
            fields.pop(name)
    if mat.texture_colorspace == "sRGB":  # as before the baked texture existed
        fields.pop("texture_colorspace")
    return fields


@cache
def bpy_version() -> str:
    """The installed bpy package's version (without importing Blender)."""
    from importlib import metadata

    try:
        return metadata.version("bpy")
    except metadata.PackageNotFoundError:
        return "absent"


def job_provenance(job: RenderJob, job_dir: Path, project=None
                   ) -> dict[int, ImageProvenance]:
    """Per frame index, the provenance of the image the job renders for it; with the
    ``project`` the job was made from, details that say in its terms what changed."""
    job_dir = Path(job_dir)
    scene_details = project_details(project) if project is not None else {}
    render = {k: v for k, v in asdict(job.render).items() if k not in ("threads", "quality")}
    common = {
        "software": _digest(__version__, bpy_version()),
        "render": _digest(_canonical(render)),
        "camera": _digest(_canonical([asdict(job.camera), job.width_px, job.height_px])),
    }
    background = _canonical(list(job.background_rgb))
    scene_chunks, target_chunks, target_vertices = _objects_chunks(job.objects, job_dir)
    if job.moving_objects:  # their poses are in each frame's pose
        scene_chunks += _objects_chunks(job.moving_objects, job_dir)[0]
    # plants: their templates, placements, materials and wind (their sway is in each
    # frame's time, part of its pose)
    plant_chunks = _plant_chunks(job, job_dir)
    scene_chunks += plant_chunks
    # a tiled texture: its tiles' names digest everything they show
    tiled = [_canonical(asdict(job.tiled_texture))] if job.tiled_texture is not None else []
    scene_chunks += tiled
    common["scene"] = _digest(background, *scene_chunks)
    # a sun over time: each light step is the scene (and target lighting) of its frames
    steps = [_objects_chunks(step.objects, job_dir) for step in job.light_steps]
    effects, camera_effects = "none", {}
    if job.effects is not None:  # each camera's effects: the model, its interior, its warp
        spec = job.effects
        camera_effects = {c: _digest(repr(spec.model), repr(part.interior),
                                     _file_digest(job_dir / part.warp) if part.warp
                                     else "no warp")
                          for c, part in spec.cameras.items()}
        if not spec.rig:
            effects = next(iter(camera_effects.values()))
    common["effects"] = effects
    # what the project asks of the effects (their interior follows the camera)
    effects_model = _digest(repr(job.effects.model)) if job.effects is not None else "none"
    out = {}
    for frame in job.frames:
        parts = dict(common)
        chunks = target_chunks
        if frame.light_step is not None:
            step_scene, chunks, _ = steps[frame.light_step]
            parts["scene"] = _digest(background, *step_scene,
                                     *_objects_chunks(job.moving_objects, job_dir)[0],
                                     *plant_chunks, *tiled)
        parts["targets"] = _digest(*chunks, _targets_in_view(target_vertices, frame, job))
        if frame.camera is not None:  # a rig: each frame's own camera
            parts["camera"] = _digest(_canonical([asdict(frame.camera),
                                                  list(job.frame_size(frame))]))
        if job.effects is not None and job.effects.rig:  # a rig: its camera's effects
            parts["effects"] = camera_effects.get(frame.camera_id, "none")
        pose = asdict(frame)
        for key in OPTIONAL_FRAME_FIELDS:
            pose.pop(key)
        if job.effects is None:  # the effect context (GSD, distance) changes no pixel then
            pose = {k: pose[k] for k in ("index", "image_name", "matrix_world_local",
                                         *TIME_FIELDS)}
        # no time line: the pose hashes as before the time fields existed
        pose = {k: v for k, v in pose.items() if k not in TIME_FIELDS or v is not None}
        if job.image_metadata != "none":
            pose["image_metadata"] = job.image_metadata
        parts["pose"] = _digest(_canonical(pose))
        camera = asdict(job.frame_camera(frame))
        del camera["resolution_x_px"], camera["resolution_y_px"]
        # where the camera is and looks (the sun it is lit by is the lighting's detail)
        blender_pose = {k: v for k, v in asdict(frame).items()
                        if k not in (*_EFFECT_ONLY_FRAME_FIELDS, *_NOT_POSE_FIELDS)}
        details = {"size_px": list(job.frame_size(frame)),
                   "camera_unsized": _digest(_canonical(camera)),
                   "pose_blender": _digest(_canonical(blender_pose)),
                   "effects_model": effects_model, **scene_details}
        out[frame.index] = ImageProvenance({p: parts[p] for p in PARTS}, details)
    return out


def _plant_chunks(job: RenderJob, job_dir: Path) -> list[str]:
    """Canonical descriptions of a job's plant groups and wind ([] without plants)."""
    if not job.vegetation:
        return []
    out = [_canonical(asdict(job.wind) if job.wind is not None else None)]
    for spec in job.vegetation:
        out += [_canonical([spec.name, [_material_fields(mat) for mat in spec.materials]]),
                _file_digest(job_dir / spec.template), _file_digest(job_dir / spec.instances)]
    return out


def _objects_chunks(objects, job_dir: Path):
    """Canonical descriptions of a job's objects: (scene chunks, target chunks, the
    targets' (vertices, faces, material index) or None)."""
    scene_chunks: list[str] = []
    target_chunks: list[str] = []
    target_vertices = None
    for obj in objects:
        materials = [_material_fields(mat) for mat in obj.materials]
        files = [f for mat in obj.materials
                 for f in (mat.texture, mat.lightmap, mat.variation, mat.variation_warp) if f]
        described = _canonical([obj.name, materials, [_file_digest(job_dir / f) for f in files]])
        if obj.name == TARGETS_MESH:
            target_chunks.append(described)
            with np.load(job_dir / obj.mesh) as data:
                target_vertices = (np.asarray(data["vertices_local"], float),
                                   np.asarray(data["faces"]),
                                   np.asarray(data["material_index"]))
        else:
            scene_chunks += [described, _file_digest(job_dir / obj.mesh)]
    return scene_chunks, target_chunks, target_vertices


def _targets_in_view(mesh, frame: FrameSpec, job: RenderJob) -> str:
    """Digest of the target vertices (and their faces' materials) a frame can see."""
    if mesh is None:
        return "no targets"
    vertices, faces, material_index = mesh
    M = np.array(frame.matrix_world_local, float)
    R, t = M[:3, :3], M[:3, 3]
    cam = (vertices - t) @ R  # Blender camera axes: x right, y up, looking along -z
    depth = -cam[:, 2]
    cam_spec = job.frame_camera(frame)
    f_over_w = cam_spec.lens_mm / cam_spec.sensor_width_mm
    W, H = cam_spec.resolution_x_px, cam_spec.resolution_y_px
    with np.errstate(divide="ignore", invalid="ignore"):
        # image widths from the image centre (the shift moves the frustum)
        x = cam[:, 0] / depth * f_over_w - cam_spec.shift_x
        y = cam[:, 1] / depth * f_over_w * cam_spec.pixel_aspect_y - cam_spec.shift_y
    half_x = 0.5 + VIEW_MARGIN
    half_y = (0.5 + VIEW_MARGIN) * H / W
    seen = (depth > 0) & (np.abs(x) <= half_x) & (np.abs(y) <= half_y)
    index = np.flatnonzero(seen)
    face_seen = np.isin(faces, index).any(axis=1)
    return _digest(_array_digest(index), _array_digest(vertices[index]),
                   _array_digest(faces[face_seen]), _array_digest(material_index[face_seen]))


def ground_truth_digest(folder: Path) -> str:
    """Digest of every file under a ground-truth folder (relative names and bytes)."""
    folder = Path(folder)
    files = sorted(p for p in folder.rglob("*") if p.is_file() and not p.name.startswith("."))
    return _digest(*(f"{p.relative_to(folder).as_posix()}:{_digest(p.read_bytes())}"
                     for p in files))


def describe_parts(parts: list[str]) -> str:
    """'pose, targets' → words for a person: 'the pose and the GCP targets'."""
    words = {"software": "the designer or Blender version", "render": "the render settings",
             "camera": "the camera",
             "scene": "the scene (terrain, texture, lighting, buildings or plants)",
             "targets": "the GCP targets in view", "effects": "the camera effects",
             "pose": "the pose", "unrecorded": "no record of its inputs",
             "terrain": "the terrain", "texture": "the texture", "lighting": "the lighting",
             "objects": "the scene objects (buildings, plants, objects)",
             "gcp targets": "the GCP targets",
             "effect context": "what the camera effects read per image (GSD, motion)",
             "missing": "the image is missing"}
    names = [words.get(p, p) for p in parts]
    return names[0] if len(names) == 1 else ", ".join(names[:-1]) + " and " + names[-1]


#: frame fields that are not where the camera is: its camera, size and sun
_NOT_POSE_FIELDS = ("camera", "camera_id", "size_px", "sun_azimuth_deg",
                    "sun_elevation_deg", "light_step", "texture_tiles")

#: frame fields that only the camera effects or the file's metadata use: a raw render
#: (Blender's image, before the effects) does not depend on them
_EFFECT_ONLY_FRAME_FIELDS = ("gsd_m", "flight_direction_uv", "distance_m", "time_utc")


def raw_render_digests(job: RenderJob, provenance: dict[int, ImageProvenance]
                       ) -> dict[int, str]:
    """Per frame, the hash of its raw render — Blender's image before the camera effects:
    the image's provenance without its ``effects`` part and with only the pose fields
    Blender uses. Two frames with equal digests give the same raw render, whatever
    their effects (designer.render.effects_job)."""
    out = {}
    for frame in job.frames:
        parts = provenance[frame.index].parts
        pose = {k: v for k, v in asdict(frame).items() if k not in _EFFECT_ONLY_FRAME_FIELDS}
        out[frame.index] = _digest(*(parts[p] for p in PARTS if p not in ("effects", "pose")),
                                   _canonical(pose))
    return out
