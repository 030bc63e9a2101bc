"""Turn a project into a render job: scene files in local coordinates plus job.json.

The job is what a render worker reads (``designer.render.worker``); it is prepared once
per output folder and shared by all workers, local or on a cluster. Everything handed
to Blender is local — world minus the project origin — because Blender stores float32.
"""

from __future__ import annotations

import hashlib
from dataclasses import dataclass, replace
from pathlib import Path

import cv2
import numpy as np

from designer import __version__
from designer.atomic import write_text_atomic
from designer.core.interior import InteriorOrientation
from designer.core.layout import IMAGES_DIR, JOB_DIR
from designer.core.projection import ground_sample_distance_m, pixel_rays_world
from designer.core.truth import CameraPose, CameraSet
from designer.effects.distortion_render import pinhole_render_camera
from designer.effects.from_model import effects_from_model
from designer.effects.motion import flight_direction_uv
from designer.errors import DesignerError
from designer.project import model as m
from designer.project.interiors import render_interior
from designer.project.utc import iso_utc
from designer.render.blender_camera import blender_camera, blender_matrix_world
from designer.render.job_files import save_npz, write_png
from designer.render.job_light import (  # noqa: F401  (TARGET_*: part of the job's face)
    TARGET_BLACK,
    TARGET_WHITE,
    ObjectLighting,
    frame_suns,
)
from designer.render.job_spec import (
    SKY_RGB,
    TEXTURE_UV_MAP,
    AdaptiveSampling,
    CameraEffectsSpec,
    EffectsSpec,
    FrameSpec,
    MaterialSpec,
    RenderJob,
    RenderSpec,
)
from designer.render.job_tiles import TiledTexture, needs_tiles
from designer.render.terrain_bake import (
    FAR_TEXTURE,
    far_ground_arrays,
    far_tile,
    needs_two_levels,
    sample_light_rect,
    two_level_bake,
)
from designer.render.texture_bake import bake_size_px, bake_varied_texture, can_bake
from designer.scene.build import BuiltScene, build_scene
from designer.scene.texture_variation import GAIN_ENCODING
from designer.survey.project_poses import project_images
from designer.survey.surroundings import project_surroundings
from designer.survey.timeline import StationTime, project_station_times

#: the job's file of the varied ground texture baked into one image
BAKED_TEXTURE = "texture_varied.png"
#: … times the light map, for a static sun (one light map for every frame)
BAKED_LIT_TEXTURE = "texture_lit.png"
#: the job's file of the coarse bake over wide surroundings (render.terrain_bake)
BAKED_COARSE_TEXTURE = "texture_coarse.png"
#: a bake larger than this a side is written as an uncompressed TIFF (the terrain with
#: its surroundings: PNG encoding took 14 s for 8800², TIFF 0.2 s); smaller ones stay PNG
PNG_BAKE_MAX_PX = 4096


def bake_file(name: str, shape: tuple[int, ...]) -> str:
    """The job's file name of a bake of ``shape``: ``name`` (a .png), or its .tif twin."""
    return name if max(shape[:2]) <= PNG_BAKE_MAX_PX else name.rsplit(".", 1)[0] + ".tif"


#: samples per pixel of each quality preset; measured costs in the README
QUALITY_SAMPLES = {"draft": 4, "survey": 16, "metrology": 64}
PIXEL_FILTERS = {"box": "BOX", "gaussian": "GAUSSIAN", "blackman-harris": "BLACKMAN_HARRIS"}


@dataclass(frozen=True)
class PreparedJob:
    job_path: Path
    job: RenderJob
    interior: InteriorOrientation
    poses: tuple[CameraPose, ...]
    scene: BuiltScene
    #: when each image is taken (None: the project has no time line)
    times: tuple[StationTime, ...] | None = None
    #: the sun (grid azimuth, elevation; deg) of each image
    suns: tuple[tuple[float, float], ...] = ()
    #: per image, every moving object's pose then (empty: no moving objects)
    moving_poses: tuple[tuple, ...] = ()
    #: {moving object id: (vertices, faces) in its own frame, m}
    moving_meshes: dict | None = None
    #: the one camera's rolling shutter (None: a global shutter, or several cameras: see
    #: ``frame_shutters``) and, when any image has one, the platform's velocity at each
    #: image (world m/s, (N, 3))
    rolling_shutter: m.RollingShutter | None = None
    velocities_m_s: np.ndarray | None = None
    #: each image's rolling shutter, its own camera's (None: a global shutter); empty
    #: when no image has one
    frame_shutters: tuple = ()
    #: the buildings as drawn (designer.scene.buildings.BuildingMesh; empty: none)
    buildings: tuple = ()
    #: the placed plants, one PlantSet per group (empty: no vegetation)
    plants: tuple = ()
    #: a multi-camera rig: every camera's rendered interior and each image's camera
    #: (None: one camera, ``interior``)
    cameras: CameraSet | None = None

    @property
    def camera_model(self) -> InteriorOrientation | CameraSet:
        """What the exporters take: the one interior, or the camera set of a rig."""
        return self.interior if self.cameras is None else self.cameras

    def interior_of(self, image_name: str) -> InteriorOrientation:
        """The rendered interior orientation of one image's camera."""
        return self.interior if self.cameras is None else self.cameras.interior_of(image_name)


def prepare_job(
    project: m.Project,
    base_dir: Path,
    out_dir: Path,
    quality: str | None = None,
    *,
    bake_texture: bool = True,
) -> PreparedJob:
    """Build the scene, write its files under ``out_dir/.designer-job`` and the job.json.

    The job's workers write the images into ``out_dir/images``
    (:mod:`designer.core.layout`). A varied ground texture is baked into one image
    (:mod:`designer.render.texture_bake`) where the bake fits; ``bake_texture=False``
    keeps Cycles' node graph (``designer bench render`` measures both).
    """
    out_dir = Path(out_dir)
    job_dir = out_dir / JOB_DIR
    job_dir.mkdir(parents=True, exist_ok=True)
    origin = np.array([project.origin.E0, project.origin.N0, project.origin.H0])
    # the stations are planned over the declared terrain; the surroundings grow the
    # rendered terrain as far as their images see
    growth, declared = project_surroundings(project, base_dir)
    scene = build_scene(project, base_dir, growth)
    images = project_images(project, declared)
    stations = list(images.stations)
    poses = [CameraPose(s.image_name, s.C_world, s.R_cam_to_world) for s in stations]
    camera_order = images.camera_order()
    camera_id = camera_order[0]
    interiors = {c: render_interior(project.camera(c), project.render.resolution_scale)
                 for c in camera_order}
    interior = interiors[camera_id]
    # A distorted camera is rendered as a pinhole just large enough to cover its field,
    # then warped through the exact inverse (designer.effects): the warp is made once
    # per camera.
    rendered = {c: pinhole_render_camera(i, project.render.distortion_oversample)
                for c, i in interiors.items()}
    render_camera = rendered[camera_id][0]
    multi = images.is_multi_camera
    n = len(stations)
    frame_cameras, frame_ids, frame_sizes = [None] * n, [None] * n, [None] * n
    cameras = None
    if multi:
        cameras = CameraSet(interiors, dict(zip((s.image_name for s in stations),
                                                images.camera_ids, strict=True)))
        specs = {c: blender_camera(rendered[c][0]) for c in interiors}
        frame_cameras = [specs[c] for c in images.camera_ids]
        frame_ids = list(images.camera_ids)
        frame_sizes = [interiors[c].image_size_px for c in images.camera_ids]
    effects = None
    with_effects = [c for c, i in interiors.items()
                    if not effects_from_model(project.effects, i, warp=rendered[c][1]).is_empty]
    if with_effects:
        # everything the worker needs to build each chain: the project's effects model,
        # each camera's interior as rendered and its distortion warp (cached beside the job)
        parts: dict[str, CameraEffectsSpec] = {}
        for c in with_effects:
            w, warp_file = rendered[c][1], None
            if w is not None:
                warp_file = "distortion_warp.npz" if not multi else f"distortion_warp_{c}.npz"
                w.save(job_dir / warp_file)
            parts[c] = CameraEffectsSpec(interior=interiors[c], warp=warp_file)
        effects = EffectsSpec(model=project.effects, cameras=parts, rig=multi)

    write_png(job_dir / "texture.png", cv2.cvtColor(scene.texture_rgb, cv2.COLOR_RGB2BGR))
    terrain_material = MaterialSpec(texture="texture.png",
                                    uv_tiles=tuple(float(t) for t in scene.texture_tiles),
                                    interpolation=scene.interpolation.capitalize())
    baked = None  # written below, with the light map folded in where the sun is static
    two = None  # a detail and a coarse bake for wide surroundings (render.terrain_bake)
    tiled = None  # a bake in tiles (render.job_tiles)
    repeat = (project.scene.texture.repeat_X, project.scene.texture.repeat_Y)
    if (bake_texture and scene.variation is not None
            and can_bake(scene.texture_rgb.shape, scene.texture_tiles)):
        # the blend of the three lookups baked into one image: one lookup per sample
        # (baked when written, unless the job folder holds it from the same inputs)
        baked = VariedBake(scene.texture_rgb, scene.texture_tiles, scene.variation,
                           scene.interpolation)
        terrain_material = MaterialSpec(texture=bake_file(BAKED_TEXTURE, baked.shape),
                                        uv_tiles=(1.0, 1.0),
                                        interpolation="Linear", extension="EXTEND",
                                        texture_colorspace="Non-Color",
                                        strength=terrain_material.strength * GAIN_ENCODING)
    elif bake_texture and needs_two_levels(scene, repeat):
        two = two_level_bake(scene, repeat, project.scene.texture.variation)
        baked_material = MaterialSpec(texture=bake_file(BAKED_TEXTURE, two.inner.shape),
                                      uv_tiles=(1.0, 1.0), interpolation="Linear",
                                      extension="EXTEND", texture_colorspace="Non-Color",
                                      strength=terrain_material.strength * GAIN_ENCODING)
        terrain_material = (replace(baked_material, uv_map=TEXTURE_UV_MAP),
                            replace(baked_material, texture=BAKED_COARSE_TEXTURE))
    elif bake_texture and needs_tiles(scene):
        # too wide for one bake: tiles of the same bake, each frame loading those it sees
        tiled = TiledTexture(scene, job_dir, terrain_material.strength, poses,
                             [rendered[c][0] for c in images.camera_ids])
        terrain_material = tiled.materials()
    elif scene.variation is not None:
        var = scene.variation
        write_png(job_dir / "variation.png", cv2.cvtColor(var.shading, cv2.COLOR_RGB2BGR))
        write_png(job_dir / "variation_warp.png", cv2.cvtColor(var.warp, cv2.COLOR_RGB2BGR))
        # the image stores gain / GAIN_ENCODING; the emission strength scales it back
        terrain_material = replace(terrain_material, variation="variation.png",
                                   variation_warp="variation_warp.png",
                                   variation_warp_uv=var.warp_bound_uv,
                                   strength=terrain_material.strength * GAIN_ENCODING)
    terrain_uv = {}
    if two is not None:
        terrain_uv = {"uv_texture": two.inner_uv, "material_index": two.material_index}
    if tiled is not None:
        terrain_uv = {"material_index": tiled.face_slot}
    if scene.texture_uv is not None:
        # An orthophoto: its own texture coordinates (from its geotransform), no tiling,
        # edge texels held beyond the image; the light map keeps the terrain's uv.
        terrain_material = replace(terrain_material, uv_tiles=(1.0, 1.0),
                                   uv_map=TEXTURE_UV_MAP, extension="EXTEND")
        terrain_uv = {"uv_texture": scene.texture_uv}
    arrays = {"vertices_world": scene.terrain.vertices_world, "faces": scene.terrain.faces,
              "uv": scene.terrain.uv, **terrain_uv}
    if scene.growth.horizon and scene.heightfield is not None:
        # images look towards the horizon: a far ground ring out to it, a sky above it
        materials = terrain_material if isinstance(terrain_material, tuple) else (
            terrain_material,)
        write_png(job_dir / FAR_TEXTURE, cv2.cvtColor(far_tile(scene.texture_rgb),
                                                      cv2.COLOR_RGB2BGR))
        far = MaterialSpec(texture=FAR_TEXTURE,
                           uv_tiles=tuple(float(t) for t in scene.texture_tiles),
                           interpolation="Linear")
        if scene.texture_uv is not None:  # an orthophoto's edge colours
            far = materials[0]
        arrays = far_ground_arrays(scene, arrays, len(materials))
        terrain_material = (*materials, far)
    world = arrays.pop("vertices_world")
    save_npz(job_dir / "terrain.npz", vertices_local=world - origin, **arrays)
    contexts = _frame_contexts(stations, [interiors[c] for c in images.camera_ids], scene)
    light = ObjectLighting(project, base_dir, scene, origin, job_dir, terrain_material)
    # the time line is the platform's: every image of a rig station is taken then
    times = project_station_times(project, images.platform)
    if times is not None:
        times = [StationTime(st.image_name, times[k].time_s, times[k].time_utc)
                 for st, k in zip(stations, images.station_index, strict=True)]
    suns = frame_suns(project, times)
    clouds = project.scene.lighting.clouds
    drifting = clouds is not None and times is not None
    if suns is None and not drifting:
        # one sun (and clouds frozen at take-off, if any): the objects as built are lit
        # for every frame
        steps, frame_steps = (), [None] * len(stations)
        objects = light.objects(scene.sun_azimuth_deg, scene.sun_elevation_deg)
        suns = [(scene.sun_azimuth_deg, scene.sun_elevation_deg)] * len(stations)
    else:
        if suns is None:
            suns = [(scene.sun_azimuth_deg, scene.sun_elevation_deg)] * len(stations)
        steps, frame_steps = light.steps(
            suns, [t.time_s for t in times] if drifting else None)
        objects = list(steps[0].objects)
    if baked is not None:
        objects = _write_bake(baked, objects, job_dir, lit=not steps)
    if two is not None:
        objects = _write_two_bakes(two, scene.heightfield.extent_m, objects, job_dir,
                                   lit=not steps)
    tiled_spec = None
    if tiled is not None:
        # with a sun over time the light steps' materials keep their light maps
        objects, tiled_spec = tiled.finish(objects, lit=not steps)
        for i, tiles in enumerate(tiled.seen):
            contexts[i]["texture_tiles"] = tiles
    if times is not None:
        for i, t in enumerate(times):
            contexts[i].update(time_s=t.time_s, time_utc=iso_utc(t.time_utc),
                               sun_azimuth_deg=float(suns[i][0]),
                               sun_elevation_deg=float(suns[i][1]), light_step=frame_steps[i])
    moving_specs, meshes, moving = (), None, []
    if project.scene.moving_objects and times is not None:
        from designer.render.job_moving import frame_moving_poses, local_poses, moving_meshes

        moving_specs, meshes = moving_meshes(project, base_dir, job_dir)
        moving = frame_moving_poses(project, scene, [t.time_s for t in times])
        for i, frame_poses in enumerate(moving):
            contexts[i]["moving_poses"] = local_poses(frame_poses, origin)
    plant_specs, wind_spec, plants = (), None, []
    if project.scene.vegetation is not None:
        from designer.render.job_vegetation import vegetation_job

        plant_specs, wind_spec, plants = vegetation_job(project, base_dir, scene, job_dir,
                                                        origin)
    frame_shutters, velocities = _rolling_shutters(project, images, times)
    for i, (pose, rs) in enumerate(zip(poses, frame_shutters, strict=True)):
        if rs is not None:
            from designer.render.job_rolling import shutter_matrices_local

            contexts[i]["shutter_matrices_local"] = shutter_matrices_local(
                pose, velocities[i], rs.readout_s, rs.direction,
                interiors[images.camera_ids[i]].image_height_px, origin)
    rolling = frame_shutters[0] if not multi else None
    if velocities is None:
        frame_shutters = ()
    render = project.render
    samples = QUALITY_SAMPLES[quality] if quality else render.effective_samples
    preset = quality or (render.preset if render.samples is None else None)
    job = RenderJob(
        designer_version=__version__,
        project=project.name,
        output_dir=str((out_dir / IMAGES_DIR).resolve()),
        origin_world=tuple(float(v) for v in origin),
        render=RenderSpec(
            samples=samples, seed=0,
            pixel_filter=PIXEL_FILTERS[render.pixel_filter_type],
            filter_width_px=float(render.pixel_filter_width_px),
            format="tiff" if render.output_format == "tiff" else "png",
            bit_depth=render.bit_depth, quality=quality,
            # metrology: plain 64 spp's corner accuracy in a third of its time, from the
            # sweep in docs/validation.md (designer bench accuracy)
            adaptive_sampling=(AdaptiveSampling(threshold=0.01, min_samples=4)
                               if preset == "metrology" else None)),
        camera=blender_camera(render_camera),
        width_px=interior.image_width_px,
        height_px=interior.image_height_px,
        objects=tuple(objects),
        # the sky above the horizon where images see it (else the black background)
        background_rgb=SKY_RGB if scene.growth.horizon else (0.0, 0.0, 0.0),
        light_steps=steps,
        moving_objects=moving_specs,
        vegetation=plant_specs,
        wind=wind_spec,
        tiled_texture=tiled_spec,
        image_metadata=render.image_metadata,
        effects=effects,
        frames=tuple(FrameSpec(index=i, image_name=p.image_name,
                               matrix_world_local=_matrix_rows(blender_matrix_world(
                                   p.C_world, p.R_cam_to_world, origin)),
                               camera=frame_cameras[i], camera_id=frame_ids[i],
                               size_px=frame_sizes[i], **contexts[i])
                     for i, p in enumerate(poses)),
    )
    job_path = job.write(job_dir / "job.json")
    return PreparedJob(job_path=job_path, job=job, interior=interior, poses=tuple(poses),
                       scene=scene, times=None if times is None else tuple(times),
                       suns=tuple(suns), moving_poses=tuple(moving), moving_meshes=meshes,
                       rolling_shutter=rolling, velocities_m_s=velocities,
                       frame_shutters=tuple(frame_shutters),
                       buildings=tuple(light.buildings), plants=tuple(plants),
                       cameras=cameras)


class VariedBake:
    """The varied texture's bake (:func:`bake_varied_texture`), computed when first
    asked for; ``key`` digests everything it depends on (the inputs and the code)."""

    def __init__(self, texture_rgb: np.ndarray, tiles, variation, interpolation: str) -> None:
        self.args = (texture_rgb, tiles, variation, interpolation)
        W, H = bake_size_px(texture_rgb.shape, tiles)
        self.shape = (H, W, 3)
        self._image: np.ndarray | None = None
        h = hashlib.sha256()
        for part in (texture_rgb, variation.shading, variation.warp):
            a = np.ascontiguousarray(part)
            h.update(f"{a.dtype}{a.shape}".encode() + a.tobytes())
        h.update(repr((tuple(float(t) for t in tiles), float(variation.warp_bound_uv),
                       interpolation)).encode())
        for module in ("texture_bake.py", "_bake_kernel.py", "job.py"):
            h.update((Path(__file__).parent / module).read_bytes())
        self.key = h.hexdigest()

    @property
    def image(self) -> np.ndarray:
        if self._image is None:
            self._image = bake_varied_texture(*self.args)
        return self._image


def _kept(path: Path, key: str) -> bool:
    """True if ``path`` was written from inputs of digest ``key`` (its ``.key`` file)."""
    key_path = path.with_name(path.name + ".key")
    return path.is_file() and key_path.is_file() and key_path.read_text() == key


def _write_keyed(path: Path, image: np.ndarray, key: str) -> None:
    """Write a bake (BGR) and then its key: a bake without its key is written again."""
    key_path = path.with_name(path.name + ".key")
    key_path.unlink(missing_ok=True)
    write_png(path, image, fast=True)
    write_text_atomic(key_path, key)


def _write_bake(bake: VariedBake, objects: list, job_dir: Path, lit: bool) -> list:
    """Write the baked varied texture; with ``lit`` (one sun for every frame) the
    terrain's light map is multiplied in, so Cycles makes one texture lookup per sample
    instead of two. The light map is sampled at the bake's texel centres as the renderer
    samples it (bilinear, edge texels extended over the same UV square). A file the job
    folder holds from the same inputs (the bake's key, and the light map's bytes) is kept:
    a resumed render does not bake again."""
    terrain = next((o for o in objects if o.name == "terrain"), None)
    material = terrain.materials[0] if terrain is not None else None
    if not lit or material is None or material.lightmap is None:
        path = job_dir / bake_file(BAKED_TEXTURE, bake.shape)
        if not _kept(path, bake.key):
            _write_keyed(path, cv2.cvtColor(bake.image, cv2.COLOR_RGB2BGR), bake.key)
        return objects
    light_bytes = (job_dir / material.lightmap).read_bytes()
    lit_file = bake_file(BAKED_LIT_TEXTURE, bake.shape)
    key = hashlib.sha256(bake.key.encode() + light_bytes).hexdigest()
    if not _kept(job_dir / lit_file, key):
        baked = bake.image
        light = cv2.imdecode(np.frombuffer(light_bytes, np.uint8), cv2.IMREAD_UNCHANGED)
        H, W = baked.shape[:2]
        # cv2's linear resize samples the source at (x + 0.5) · scale − 0.5, edges
        # replicated: Blender's texel-centre convention with EXTEND
        light = cv2.resize(light.astype(np.float32) / np.float32(65535.0), (W, H),
                           interpolation=cv2.INTER_LINEAR)
        lit_image = np.empty_like(baked)
        for r in range(0, H, 256):  # bands of rows: the float copy of a large bake stays small
            product = baked[r:r + 256].astype(np.float32) * light[r:r + 256, :, None]
            lit_image[r:r + 256] = np.clip(np.rint(product), 0, 65535)
        _write_keyed(job_dir / lit_file, cv2.cvtColor(lit_image, cv2.COLOR_RGB2BGR), key)
    folded = replace(material, texture=lit_file, lightmap=None)
    return [replace(o, materials=(folded, *o.materials[1:])) if o is terrain else o
            for o in objects]


def _write_two_bakes(two, extent_m, objects: list, job_dir: Path, lit: bool) -> list:
    """Write the detail and coarse bakes (render.terrain_bake); with ``lit`` the light map
    is folded into each, sampled over the part of the terrain each covers."""
    terrain = next(o for o in objects if o.name == "terrain")
    rects = (two.inner_rect_uv(extent_m), (0.0, 1.0, 0.0, 1.0))
    light = None
    if lit and terrain.materials[0].lightmap is not None:
        light = cv2.imread(str(job_dir / terrain.materials[0].lightmap),
                           cv2.IMREAD_UNCHANGED).astype(np.float32) / np.float32(65535.0)
    folded = []
    for material, bake, rect in zip(terrain.materials[:2], (two.inner, two.coarse), rects,
                                    strict=True):
        if light is None:
            write_png(job_dir / material.texture, cv2.cvtColor(bake, cv2.COLOR_RGB2BGR),
                      fast=True)
            folded.append(material)
            continue
        H, W = bake.shape[:2]
        lit_image = np.empty_like(bake)
        for r in range(0, H, 256):  # bands of rows: the light's float copy stays small
            r1 = min(r + 256, H)
            top = rect[3] - r / H * (rect[3] - rect[2])
            bottom = rect[3] - r1 / H * (rect[3] - rect[2])
            band = sample_light_rect(light, (r1 - r, W), (rect[0], rect[1], bottom, top))
            product = bake[r:r1].astype(np.float32) * band[:, :, None]
            lit_image[r:r1] = np.clip(np.rint(product), 0, 65535)
        name = material.texture.replace("texture_", "texture_lit_", 1)
        write_png(job_dir / name, cv2.cvtColor(lit_image, cv2.COLOR_RGB2BGR), fast=True)
        folded.append(replace(material, texture=name, lightmap=None))
    folded += terrain.materials[2:]  # the far ground keeps its own texture and light map
    return [replace(o, materials=tuple(folded)) if o is terrain else o for o in objects]


def _rolling_shutters(project: m.Project, images, times):
    """(each image's rolling shutter, its own camera's: None for a global shutter (no
    element, or a readout of 0); the platform velocity at each image (N, 3) m/s, None when
    no image has a rolling shutter). Every image of a rig station shares its velocity."""
    shutters = {}
    for c in images.camera_order():
        rs = project.camera(c).rolling_shutter
        shutters[c] = None if rs is None or rs.readout_s == 0 else rs
    frame_shutters = [shutters[c] for c in images.camera_ids]
    rolling = [c for c, rs in shutters.items() if rs is not None]
    if not rolling:
        return frame_shutters, None
    if times is None:
        raise DesignerError(f"camera '{rolling[0]}' has a rolling shutter but the trajectory "
                            "has no <time-line>; add one or set readout-s 0")
    _readout_within_frame_interval(shutters, images, times)
    from designer.survey.timeline import station_velocities_m_s

    platform = station_velocities_m_s(images.platform, project.trajectory.time_line)
    return frame_shutters, platform[np.asarray(images.station_index)]


def _readout_within_frame_interval(shutters, images, times) -> None:
    """DesignerError when a camera's readout is not shorter than the time between two of
    its photos: its rows would still be read when the next exposure starts (validation
    checks this against a declared trigger-interval-s; here, against the time line)."""
    for cam, rs in shutters.items():
        if rs is None:
            continue
        mine = [t for t, c in zip(times, images.camera_ids, strict=True) if c == cam]
        seconds = np.unique([t.time_s for t in mine])  # a rig station's images: one time
        if len(seconds) < 2:
            continue
        gaps = np.diff(seconds)
        k = int(np.argmin(gaps))
        if rs.readout_s >= gaps[k] * (1 - 1e-9):
            first = next(t.image_name for t in mine if t.time_s == seconds[k])
            second = next(t.image_name for t in mine if t.time_s == seconds[k + 1])
            raise DesignerError(
                f"camera '{cam}': readout-s {rs.readout_s:g} s is not shorter than the "
                f"{gaps[k]:.3g} s between {first} and {second} on the time line; a frame "
                "must be read before the next is taken: shorten the readout, fly slower or "
                "space the photos further")


def _matrix_rows(M: np.ndarray) -> tuple[tuple[float, ...], ...]:
    return tuple(tuple(float(v) for v in row) for row in M)


def _frame_contexts(stations, interiors: list[InteriorOrientation], scene: BuiltScene
                    ) -> list[dict]:
    """Per frame (with its camera's interior): GSD at the principal point (m/px), the
    flight direction in the image and the distance along the optical axis to the ground
    there (m)."""
    out = []
    for st, interior in zip(stations, interiors, strict=True):
        centre = np.array([[interior.cx_px, interior.cy_px]])
        ray = pixel_rays_world(centre, st.R_cam_to_world, interior)
        depth = None
        if scene.heightfield is not None:
            hit = scene.heightfield.intersect_rays(st.C_world[None], ray)[0]
            if np.isfinite(hit[0]):
                depth = float(-(hit - st.C_world) @ st.R_cam_to_world[:, 2])
        if depth is None:
            depth = float(st.C_world[2] - np.mean(scene.terrain.vertices_world[:, 2]))
        az = np.radians(st.flight_azimuth_deg)
        velocity = np.array([np.sin(az), np.cos(az), 0.0])
        du, dv = flight_direction_uv(velocity, st.R_cam_to_world)
        out.append({"gsd_m": float(ground_sample_distance_m(interior, abs(depth))),
                    "flight_direction_uv": (float(du), float(dv)),
                    "distance_m": float(abs(depth))})
    return out
