"""The render worker: the only module of designer that imports ``bpy``.

Run as ``python -m designer.render.worker JOB.json --frames 0,1,5 [--progress-fd N]``.
It builds the scene described by the job once, then renders the frames asked for,
each to a file in the job folder's ``partial/`` renamed into the images folder (the
job's ``output_dir``) when complete: nothing partial ever appears among the images.
Progress goes out as JSON lines on file descriptor N (stdout carries Blender's own log).

Only effects the job asks for are rendered: no denoiser, no adaptive sampling, no
dithering, a box pixel filter one pixel wide unless asked otherwise, the 'Standard'
view transform (no filmic tone curve), and texture interpolation as configured.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import math
import os
import sys
import time
from pathlib import Path

import bpy  # the one place in designer that imports bpy
import numpy as np
from mathutils import Matrix

from designer.core.layout import PARTIAL_DIR
from designer.render.effects_job import keep_raw, load_effects, process_frame
from designer.render.job_spec import (
    IMAGE_FORMATS,
    TEXTURE_UV_MAP,
    CameraSpec,
    FrameSpec,
    LightStep,
    MaterialSpec,
    MeshSpec,
    PlantSetSpec,
    RenderJob,
    TiledTextureSpec,
)
from designer.render.tiled_bake import (
    LOOK_AHEAD_FRAMES,
    TileGrid,
    ensure_tile,
    slots_to_show,
    tile_file,
)
from designer.render.void_share import VOID_MAP_SUFFIX, void_share_of_map
from designer.scene.texture_variation import MIRROR_OFFSETS


def reset_scene() -> bpy.types.Scene:
    bpy.ops.wm.read_factory_settings(use_empty=True)
    return bpy.context.scene


def configure_render(scene: bpy.types.Scene, job: RenderJob) -> None:
    render = job.render
    scene.render.engine = "CYCLES"
    cycles = scene.cycles
    cycles.device = "CPU"
    cycles.samples = render.samples
    cycles.use_adaptive_sampling = False
    if render.adaptive_sampling is not None:
        # Flat pixels (no edge inside) converge at once; samples go to the edges.
        cycles.use_adaptive_sampling = True
        cycles.adaptive_threshold = render.adaptive_sampling.threshold
        cycles.adaptive_min_samples = render.adaptive_sampling.min_samples
    cycles.use_denoising = False
    cycles.seed = render.seed
    cycles.use_animated_seed = False
    cycles.pixel_filter_type = render.pixel_filter
    cycles.filter_width = render.filter_width_px
    # Everything visible is emissive (light is baked): a camera ray's first hit is the
    # answer, so no bounces.
    cycles.max_bounces = 0
    cycles.diffuse_bounces = cycles.glossy_bounces = 0
    cycles.transmission_bounces = cycles.volume_bounces = cycles.transparent_max_bounces = 0
    threads = render.threads
    scene.render.threads_mode = "FIXED" if threads > 0 else "AUTO"
    if threads > 0:
        scene.render.threads = threads
    # Keep the synchronised scene (BVH, images, shaders) between frames: only the camera
    # moves, so each frame costs just its own path tracing.
    scene.render.use_persistent_data = True
    scene.render.dither_intensity = 0.0
    scene.render.film_transparent = False
    scene.render.use_compositing = False
    scene.render.use_sequencer = False
    scene.view_settings.view_transform = "Standard"
    scene.view_settings.look = "None"
    scene.view_settings.exposure = 0.0
    scene.view_settings.gamma = 1.0
    scene.display_settings.display_device = "sRGB"
    scene.sequencer_colorspace_settings.name = "sRGB"
    fmt, _ = IMAGE_FORMATS[render.format]
    settings = scene.render.image_settings
    settings.file_format = fmt
    settings.color_mode = "RGB"
    settings.color_depth = str(render.bit_depth)
    if fmt == "PNG":
        settings.compression = 15
    elif fmt == "TIFF":
        settings.tiff_codec = "DEFLATE"
    scene.render.use_file_extension = False
    # No metadata in the files (date, render time, host…): the same job then writes the
    # same bytes every time, and nothing about the machine leaks into the images.
    for name in dir(scene.render):
        if name.startswith("use_stamp"):
            setattr(scene.render, name, False)
    camera = job.camera
    scene.render.resolution_x = camera.resolution_x_px
    scene.render.resolution_y = camera.resolution_y_px
    scene.render.resolution_percentage = 100
    scene.render.pixel_aspect_x = camera.pixel_aspect_x
    scene.render.pixel_aspect_y = camera.pixel_aspect_y


def add_camera(scene: bpy.types.Scene, camera: CameraSpec) -> bpy.types.Object:
    data = bpy.data.cameras.new("survey_camera")
    data.type = "PERSP"
    data.lens_unit = "MILLIMETERS"
    _camera_data(data, camera)
    obj = bpy.data.objects.new("survey_camera", data)
    scene.collection.objects.link(obj)
    scene.camera = obj
    return obj


def _camera_data(data, camera: CameraSpec) -> None:
    data.lens = camera.lens_mm
    data.sensor_fit = camera.sensor_fit
    data.sensor_width = camera.sensor_width_mm
    data.shift_x = camera.shift_x
    data.shift_y = camera.shift_y
    data.clip_start = camera.clip_start_m
    data.clip_end = camera.clip_end_m


def set_camera(scene: bpy.types.Scene, obj: bpy.types.Object, camera: CameraSpec) -> None:
    """Give the survey camera (and the render size) another camera's settings: the
    frames of a multi-camera rig differ in lens, sensor and resolution."""
    _camera_data(obj.data, camera)
    scene.render.resolution_x = camera.resolution_x_px
    scene.render.resolution_y = camera.resolution_y_px
    scene.render.pixel_aspect_x = camera.pixel_aspect_x
    scene.render.pixel_aspect_y = camera.pixel_aspect_y


def load_image(path: str, interpolation_colour: str, half: bool = False) -> bpy.types.Image:
    """Load (once) an image with its colour space; ``half`` holds a float image as half
    floats in the render (the 16-bit bake of a varied texture: half the memory)."""
    image = bpy.data.images.load(path, check_existing=True)
    image.colorspace_settings.name = interpolation_colour
    if half:
        image.use_half_precision = True
    return image


def emission_material(name: str, spec: MaterialSpec, base: Path) -> bpy.types.Material:
    """Emission shader: colour = texture (tiled) × optional light map (one tile)."""
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    nodes.clear()
    out = nodes.new("ShaderNodeOutputMaterial")
    emit = nodes.new("ShaderNodeEmission")
    # A light map stores L / strength so it fits 16 bits; strength scales it back.
    emit.inputs["Strength"].default_value = spec.strength
    links.new(emit.outputs["Emission"], out.inputs["Surface"])
    if spec.color is not None:
        emit.inputs["Color"].default_value = (*spec.color, 1.0)
        return mat
    uv = nodes.new("ShaderNodeTexCoord")
    mapping = nodes.new("ShaderNodeMapping")
    mapping.vector_type = "POINT"
    tiles = spec.uv_tiles
    mapping.inputs["Scale"].default_value = (float(tiles[0]), float(tiles[1]), 1.0)
    lookup_uv = uv.outputs["UV"]
    if spec.uv_map:
        texture_uv = nodes.new("ShaderNodeUVMap")
        texture_uv.uv_map = spec.uv_map
        lookup_uv = texture_uv.outputs["UV"]
    elif spec.variation_warp:
        lookup_uv = _warped_uv(nodes, links, spec, base, uv.outputs["UV"])
    links.new(lookup_uv, mapping.inputs["Vector"])
    tex = nodes.new("ShaderNodeTexImage")
    # named: a tiled texture's tiles are swapped into these two (show_texture_tiles)
    tex.name, mapping.name = "texture", "texture_mapping"
    tex.image = load_image(str(base / spec.texture), spec.texture_colorspace,
                           half=spec.texture_colorspace == "Non-Color")
    tex.interpolation = spec.interpolation
    tex.extension = spec.extension
    links.new(mapping.outputs["Vector"], tex.inputs["Vector"])
    colour = tex.outputs["Color"]
    if spec.variation:
        colour = _varied(nodes, links, spec, base, uv.outputs["UV"], lookup_uv, colour)
    if spec.lightmap:
        light = nodes.new("ShaderNodeTexImage")
        light.image = load_image(str(base / spec.lightmap), "Non-Color")
        light.interpolation = "Linear"
        light.extension = "EXTEND"
        links.new(uv.outputs["UV"], light.inputs["Vector"])
        mix = nodes.new("ShaderNodeMix")
        mix.data_type = "RGBA"
        mix.blend_type = "MULTIPLY"
        mix.inputs["Factor"].default_value = 1.0
        links.new(colour, mix.inputs["A"])
        links.new(light.outputs["Color"], mix.inputs["B"])
        colour = mix.outputs["Result"]
    links.new(colour, emit.inputs["Color"])
    return mat


def _mix(nodes, links, blend: str, factor, a, b):
    mix = nodes.new("ShaderNodeMix")
    mix.data_type = "RGBA"
    mix.blend_type = blend
    if isinstance(factor, float):
        mix.inputs["Factor"].default_value = factor
    else:
        links.new(factor, mix.inputs["Factor"])
    links.new(a, mix.inputs["A"])
    links.new(b, mix.inputs["B"])
    return mix.outputs["Result"]


def _variation_image(nodes, links, path: Path, uv):
    node = nodes.new("ShaderNodeTexImage")
    node.image = load_image(str(path), "Non-Color")
    node.interpolation = "Linear"
    node.extension = "EXTEND"
    links.new(uv, node.inputs["Vector"])
    return node.outputs["Color"]


def _warped_uv(nodes, links, spec: MaterialSpec, base: Path, uv):
    """UV + the variation's warp, decoded from 0.5 + warp / (2 bound)."""
    warp = _variation_image(nodes, links, base / spec.variation_warp, uv)
    decode = nodes.new("ShaderNodeMapping")
    decode.vector_type = "POINT"
    bound = float(spec.variation_warp_uv)
    decode.inputs["Scale"].default_value = (2 * bound, 2 * bound, 0.0)
    decode.inputs["Location"].default_value = (-bound, -bound, 0.0)
    links.new(warp, decode.inputs["Vector"])
    add = nodes.new("ShaderNodeVectorMath")
    add.operation = "ADD"
    links.new(uv, add.inputs[0])
    links.new(decode.outputs["Vector"], add.inputs[1])
    return add.outputs["Vector"]


def _varied(nodes, links, spec: MaterialSpec, base: Path, uv, lookup_uv, colour):
    """The tiled texture blended with two mirrored, shifted copies of itself by the
    variation's mix_a and mix_b, times its gain / GAIN_ENCODING (the strength holds the
    factor); the variation images span the UV square once (world X, Y of the terrain),
    the copies are looked up at the warped UV like the texture."""
    planes = nodes.new("ShaderNodeSeparateColor")
    links.new(_variation_image(nodes, links, base / spec.variation, uv), planes.inputs["Color"])
    tx, ty = (float(t) for t in spec.uv_tiles)
    image = bpy.data.images.load(str(base / spec.texture), check_existing=True)
    for (du, dv), scale, weight in zip(MIRROR_OFFSETS, ((-tx, ty), (tx, -ty)),
                                       ("Green", "Blue"), strict=True):
        mapping = nodes.new("ShaderNodeMapping")
        mapping.vector_type = "POINT"
        mapping.inputs["Scale"].default_value = (scale[0], scale[1], 1.0)
        mapping.inputs["Location"].default_value = (du, dv, 0.0)
        links.new(lookup_uv, mapping.inputs["Vector"])
        copy = nodes.new("ShaderNodeTexImage")
        copy.image = image
        copy.interpolation = spec.interpolation
        copy.extension = "REPEAT"
        links.new(mapping.outputs["Vector"], copy.inputs["Vector"])
        colour = _mix(nodes, links, "MIX", planes.outputs[weight], colour, copy.outputs["Color"])
    return _mix(nodes, links, "MULTIPLY", 1.0, colour, planes.outputs["Red"])


def show_texture_tiles(spec: TiledTextureSpec, tiles, base: Path, upcoming=()) -> None:
    """Give the terrain's tile slots the frame's tiles, and when any changes the tiles
    of the ``upcoming`` frames (designer.render.tiled_bake.slots_to_show; each baked
    first if no worker has); a slot no frame wants keeps what it shows (the coarse bake
    until it first gets a tile); tiles no slot shows any more are freed."""
    mesh = bpy.data.objects["terrain"].data
    grid = TileGrid(tuple(spec.full_px), spec.core_px, spec.pad_px)
    rows, columns = spec.slots
    shown = {}
    for slot in range(rows * columns):
        material = mesh.materials[spec.first_material + slot]
        # no light is sampled from the ground (no bounces): without this, every swap of
        # an image rebuilds Cycles' light tree over the terrain's triangles (set once:
        # setting a property tags the material for a new shader, even to its value)
        if material.cycles.emission_sampling != "NONE":
            material.cycles.emission_sampling = "NONE"
        shown[slot] = _shown_tile(material.node_tree.nodes["texture"].image.filepath,
                                  spec.digest)
    for slot, k in slots_to_show(grid, spec.slots, shown, tiles, upcoming).items():
        nodes = mesh.materials[spec.first_material + slot].node_tree.nodes
        tex, mapping = nodes["texture"], nodes["texture_mapping"]
        old = tex.image
        tex.image = load_image(str(ensure_tile(spec, k, base)), "Non-Color", half=True)
        scale, offset = grid.uv_transform(k)
        mapping.inputs["Scale"].default_value = (*scale, 1.0)
        mapping.inputs["Location"].default_value = (*offset, 0.0)
        if old.users == 0:
            bpy.data.images.remove(old)


def _shown_tile(filepath: str, digest: str) -> int | None:
    """The tile an image file of the job is (None: the coarse bake)."""
    name = Path(filepath).name
    prefix = tile_file(digest, 0)[:-len("0.tif")]
    if not name.startswith(prefix):
        return None
    return int(name[len(prefix):-len(".tif")])


def set_materials(mesh: bpy.types.Mesh, spec: MeshSpec, base: Path, data=None) -> None:
    """Give the mesh the spec's emission materials (and per-face material indices)."""
    mesh.materials.clear()
    for i, mspec in enumerate(spec.materials):
        mesh.materials.append(emission_material(f"{spec.name}_{i}", mspec, base))
    if data is not None and "material_index" in data:
        mesh.polygons.foreach_set("material_index", np.asarray(data["material_index"], np.int32))


def apply_light_step(scene: bpy.types.Scene, current: dict[str, MeshSpec],
                     step: LightStep, base: Path) -> None:
    """Light the scene for one sun of the flight: objects whose mesh file changes are
    built anew, the others only get the step's materials (light map, colours)."""
    for spec in step.objects:
        old = current.get(spec.name)
        if old == spec:
            continue
        obj = bpy.data.objects[spec.name]
        if old is not None and old.mesh == spec.mesh:
            set_materials(obj.data, spec, base)
        else:
            mesh = obj.data
            bpy.data.objects.remove(obj)
            bpy.data.meshes.remove(mesh)
            add_mesh(scene, spec, base)
        current[spec.name] = spec
    for material in list(bpy.data.materials):  # the previous sun's materials and maps
        if material.users == 0:
            bpy.data.materials.remove(material)
    for image in list(bpy.data.images):
        if image.users == 0:
            bpy.data.images.remove(image)


def add_mesh(scene: bpy.types.Scene, spec: MeshSpec, base: Path) -> bpy.types.Object:
    data = np.load(base / spec.mesh)
    verts = np.ascontiguousarray(data["vertices_local"], dtype=np.float32)
    faces = np.ascontiguousarray(data["faces"], dtype=np.int32)
    mesh = bpy.data.meshes.new(spec.name)
    mesh.vertices.add(len(verts))
    mesh.vertices.foreach_set("co", verts.ravel())
    n_faces = len(faces)
    corners = faces.shape[1]
    mesh.loops.add(n_faces * corners)
    mesh.loops.foreach_set("vertex_index", faces.ravel())
    mesh.polygons.add(n_faces)
    loop_start = np.arange(0, n_faces * corners, corners, dtype=np.int32)
    mesh.polygons.foreach_set("loop_start", loop_start)
    mesh.polygons.foreach_set("loop_total", np.full(n_faces, corners, dtype=np.int32))
    if "uv" in data:
        layer = mesh.uv_layers.new(name="UVMap")
        loop_uv = np.asarray(data["uv"], dtype=np.float32)[faces.ravel()]
        layer.data.foreach_set("uv", loop_uv.ravel())
        layer.active_render = True
    if "uv_texture" in data:
        layer = mesh.uv_layers.new(name=TEXTURE_UV_MAP)
        loop_uv = np.asarray(data["uv_texture"], dtype=np.float32)[faces.ravel()]
        layer.data.foreach_set("uv", loop_uv.ravel())
    set_materials(mesh, spec, base, data)
    mesh.update(calc_edges=True)
    mesh.validate(verbose=False)
    obj = bpy.data.objects.new(spec.name, mesh)
    scene.collection.objects.link(obj)
    return obj


#: per-plant brightness spread of the foliage (emission × 1 ± this, by instance)
PLANT_BRIGHTNESS_SPREAD = 0.2


def add_plants(scene: bpy.types.Scene, spec: PlantSetSpec, base: Path) -> dict:
    """One plant group: its template mesh (kept out of the scene) instanced by geometry
    nodes on a point per plant, each turned by the point's ``plant_rotation``
    (quaternion, set per frame by :func:`pose_plants`) and scaled by ``plant_scale``:
    Blender then holds one mesh per group however many plants it has."""
    template = add_mesh(scene, MeshSpec(spec.name + ":template", spec.template,
                                        spec.materials), base)
    scene.collection.objects.unlink(template)
    for mat in template.data.materials:  # each plant a little brighter or darker
        nodes, links = mat.node_tree.nodes, mat.node_tree.links
        emit = next(n for n in nodes if n.bl_idname == "ShaderNodeEmission")
        info = nodes.new("ShaderNodeObjectInfo")
        spread = nodes.new("ShaderNodeMath")
        spread.operation = "MULTIPLY_ADD"
        spread.inputs[1].default_value = 2 * PLANT_BRIGHTNESS_SPREAD
        spread.inputs[2].default_value = 1.0 - PLANT_BRIGHTNESS_SPREAD
        links.new(info.outputs["Random"], spread.inputs[0])
        strength = nodes.new("ShaderNodeMath")
        strength.operation = "MULTIPLY"
        strength.inputs[1].default_value = emit.inputs["Strength"].default_value
        links.new(spread.outputs["Value"], strength.inputs[0])
        links.new(strength.outputs["Value"], emit.inputs["Strength"])
    data = np.load(base / spec.instances)
    at = {k: np.asarray(data[k], float) for k in ("base_local", "scale", "yaw_rad",
                                                  "phase_rad")}
    n = len(at["base_local"])
    mesh = bpy.data.meshes.new(spec.name)
    mesh.vertices.add(n)
    mesh.vertices.foreach_set("co", np.ascontiguousarray(at["base_local"], np.float32).ravel())
    mesh.attributes.new("plant_rotation", "QUATERNION", "POINT")
    scale = mesh.attributes.new("plant_scale", "FLOAT_VECTOR", "POINT")
    scale.data.foreach_set("vector", np.ascontiguousarray(at["scale"], np.float32).ravel())
    mesh.update()
    carrier = bpy.data.objects.new(spec.name, mesh)
    scene.collection.objects.link(carrier)
    tree = bpy.data.node_groups.new(spec.name, "GeometryNodeTree")
    tree.interface.new_socket(name="Geometry", in_out="INPUT",
                              socket_type="NodeSocketGeometry")
    tree.interface.new_socket(name="Geometry", in_out="OUTPUT",
                              socket_type="NodeSocketGeometry")
    nodes, links = tree.nodes, tree.links
    group_in, group_out = nodes.new("NodeGroupInput"), nodes.new("NodeGroupOutput")
    instance = nodes.new("GeometryNodeInstanceOnPoints")
    info = nodes.new("GeometryNodeObjectInfo")
    info.transform_space = "ORIGINAL"
    info.inputs["Object"].default_value = template
    rotation = nodes.new("GeometryNodeInputNamedAttribute")
    rotation.data_type = "QUATERNION"
    rotation.inputs["Name"].default_value = "plant_rotation"
    size = nodes.new("GeometryNodeInputNamedAttribute")
    size.data_type = "FLOAT_VECTOR"
    size.inputs["Name"].default_value = "plant_scale"
    links.new(group_in.outputs[0], instance.inputs["Points"])
    links.new(info.outputs["Geometry"], instance.inputs["Instance"])
    links.new(rotation.outputs["Attribute"], instance.inputs["Rotation"])
    links.new(size.outputs["Attribute"], instance.inputs["Scale"])
    links.new(instance.outputs["Instances"], group_out.inputs[0])
    carrier.modifiers.new("plants", "NODES").node_group = tree
    return {"mesh": mesh, "yaw_rad": at["yaw_rad"], "phase_rad": at["phase_rad"]}


def pose_plants(plants: list[dict], wind, time_s: float | None) -> None:
    """Turn every plant to its sway at ``time_s`` (designer.scene.vegetation)."""
    from designer.scene.vegetation import plant_rotations, quaternions_wxyz

    for group in plants:
        key = time_s if wind is not None else None  # still plants are posed once
        if group.get("posed", ()) == key:
            continue
        group["posed"] = key
        q = quaternions_wxyz(plant_rotations(group["yaw_rad"], group["phase_rad"], wind,
                                             time_s))
        mesh = group["mesh"]
        mesh.attributes["plant_rotation"].data.foreach_set(
            "value", np.ascontiguousarray(q, np.float32).ravel())
        mesh.update()


def build_scene(job: RenderJob, base: Path) -> tuple[bpy.types.Scene, bpy.types.Object]:
    scene = reset_scene()
    configure_render(scene, job)
    world = bpy.data.worlds.new("world")
    world.use_nodes = True
    background = world.node_tree.nodes.get("Background")
    background.inputs["Color"].default_value = (*job.background_rgb, 1)
    background.inputs["Strength"].default_value = 1.0
    scene.world = world
    for spec in (*job.objects, *job.moving_objects):
        add_mesh(scene, spec, base)
    camera = add_camera(scene, job.camera)
    return scene, camera


def add_void_map(scene: bpy.types.Scene, folder: Path) -> Path | None:
    """Have every render also write its void map (:mod:`designer.render.void_share`) to
    the file returned, in ``folder``: Cycles' mist pass with the mist from the camera to
    far beyond any object (a sample that hits an object adds 0, one that sees only the
    background 1), written by the compositor as a 16-bit grey PNG. Neither changes the
    image: the mist pass is a pass of its own and the compositor tree has no output but
    the file. None (no void measured) with Blender before 5.0, whose compositor is set
    up otherwise."""
    if not hasattr(scene, "compositing_node_group"):
        return None
    import uuid

    scene.view_layers[0].use_pass_mist = True
    mist = scene.world.mist_settings
    # (1 - d / 1e30) is 1.0 in float32 for any distance: a hit adds exactly 0 to the pass
    mist.start, mist.depth, mist.falloff = 0.0, 1e30, "LINEAR"
    scene.render.use_compositing = True
    scene.render.compositor_device = "CPU"
    scene.render.compositor_precision = "FULL"
    tree = bpy.data.node_groups.new("void map", "CompositorNodeTree")
    scene.compositing_node_group = tree
    layers = tree.nodes.new("CompositorNodeRLayers")
    out = tree.nodes.new("CompositorNodeOutputFile")
    out.format.media_type = "IMAGE"
    out.format.file_format = "PNG"
    out.format.color_mode = "BW"
    out.format.color_depth = "16"
    out.format.compression = 1
    out.save_as_render = False  # the pass's values, no view transform
    out.file_output_items.new("FLOAT", "")
    tree.links.new(layers.outputs["Mist"], out.inputs[0])
    # one name for the whole process, unique among the workers sharing ``folder`` (a
    # cluster's too), without '#' (Blender writes the frame number there); written as
    # given (configure_render: no file extension added)
    folder.mkdir(parents=True, exist_ok=True)
    out.directory = str(folder) + os.sep
    out.file_name = f"void-map-{uuid.uuid4().hex}.png"
    return folder / out.file_name


def render_frame(scene, camera, frame: FrameSpec, out_dir: Path, ext: str, partial: Path,
                 chain=None, exif: bool = False, setup_s: float = 0.0, bare: bool = False,
                 raw_dir: Path | None = None, void_map: Path | None = None) -> dict:
    """Render one frame; apply the camera effects (if any); write its time into the EXIF
    when ``exif``; rename the image into place. Returns its path, the seconds of each
    stage (``stages``: :data:`designer.render_time.stages.FRAME_STAGES`) and its
    ``void_share`` (0..1, :mod:`designer.render.void_share`; None without ``void_map``,
    the file :func:`add_void_map` has each render write); ``setup_s`` is the caller's
    part of the frame's set-up (light step, plants).

    Blender's file and the finished image are written in ``partial`` (a folder outside
    ``out_dir`` on the same file system); only the complete image is renamed into
    ``out_dir``, which therefore never holds anything but finished images. ``bare``
    renders without writing anything (``designer bench render``'s bare Cycles row);
    ``raw_dir`` keeps Blender's file there too (before the camera effects), and its void
    map beside it (``STEM.void-map.png``) for an effect pass to record.
    """
    t_setup = time.perf_counter()
    if frame.camera is not None:  # a rig: this frame's camera, then its pose
        set_camera(scene, camera, frame.camera)
    camera.matrix_world = Matrix(frame.matrix_world_local)
    if frame.shutter_matrices_local is not None or scene.render.use_motion_blur:
        set_rolling_shutter(scene, camera, frame.shutter_matrices_local)
    for name, x, y, z, heading_deg in frame.moving_poses or ():
        obj = bpy.data.objects[name]  # its mesh: base centre at 0, +Y forward
        obj.location = (x, y, z)
        obj.rotation_euler = (0.0, 0.0, -math.radians(heading_deg))
    stages = {"setup_s": setup_s + time.perf_counter() - t_setup}
    final = out_dir / frame.image_name
    partial.mkdir(parents=True, exist_ok=True)
    tmp = partial / f"{final.stem}.rendering{ext}"
    staged = partial / final.name  # the finished image, before its rename into out_dir
    if void_map is not None:
        void_map.unlink(missing_ok=True)  # a map found after the render is this frame's
    t0, cpu0 = time.perf_counter(), time.process_time()
    bpy.ops.render.render(write_still=False)
    t1, cpu = time.perf_counter(), time.process_time() - cpu0
    stages["cycles_s"] = t1 - t0
    stages["cycles_cpu_s"] = cpu
    if bare:
        return {"path": None, "seconds": time.perf_counter() - t_setup + setup_s,
                "render_seconds": t1 - t0, "render_cpu_seconds": cpu,
                "effects_seconds": 0.0, "stages": stages, "void_share": None}
    void_share = None
    try:
        if void_map is not None:
            void_share = void_share_of_map(void_map)
            stages["void_s"] = time.perf_counter() - t1
        t_write = time.perf_counter()
        # the same file write_still=True writes (the scene's image settings)
        bpy.data.images["Render Result"].save_render(filepath=str(tmp), scene=scene)
        t2 = time.perf_counter()
        stages["blender_write_s"] = t2 - t_write
        if raw_dir is not None:  # kept for effect passes (effects_job.apply_effects_pass)
            keep_raw(tmp, raw_dir / f"{final.stem}{ext}")
            if void_map is not None:
                keep_raw(void_map, raw_dir / f"{final.stem}{VOID_MAP_SUFFIX}")
        process_frame(tmp, staged, frame, chain, stages)
        if exif and frame.time_utc is not None:
            from designer.render.exif import write_time

            t_exif = time.perf_counter()
            write_time(staged, frame.time_utc)
            stages["exif_s"] = time.perf_counter() - t_exif
        os.replace(staged, final)
    finally:
        tmp.unlink(missing_ok=True)
        staged.unlink(missing_ok=True)
        if void_map is not None:
            void_map.unlink(missing_ok=True)
    t_end = time.perf_counter()
    stages["effects_total_s"] = t_end - t2
    return {"path": str(final), "seconds": t_end - t_setup + setup_s,
            "render_seconds": t1 - t0, "render_cpu_seconds": cpu,
            "effects_seconds": t_end - t2, "stages": stages, "void_share": void_share}


def set_rolling_shutter(scene, camera, matrices) -> None:
    """Cycles' own rolling shutter, exact (designer.render.job_rolling): motion blur on a
    shutter of one frame from frame 1, the rows read top to bottom over the whole shutter
    (duration 0: no motion blur), the camera keyed linearly from the first matrix at frame
    1 to the second at frame 2. ``matrices`` None turns it off again (a global shutter)."""
    camera.animation_data_clear()
    if matrices is None:
        scene.render.use_motion_blur = False
        return
    scene.render.use_motion_blur = True
    scene.render.motion_blur_position = "START"
    scene.render.motion_blur_shutter = 1.0
    scene.cycles.rolling_shutter_type = "TOP"
    scene.cycles.rolling_shutter_duration = 0.0
    for frame_number, matrix in zip((1, 2), matrices, strict=True):
        camera.matrix_world = Matrix(matrix)
        camera.keyframe_insert("location", frame=frame_number)
        camera.keyframe_insert("rotation_euler", frame=frame_number)
    from bpy_extras import anim_utils

    action = camera.animation_data.action
    channels = anim_utils.action_get_channelbag_for_slot(action, camera.animation_data.action_slot)
    for curve in channels.fcurves:
        for key in curve.keyframe_points:
            key.interpolation = "LINEAR"
    scene.frame_set(1)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="designer.render.worker")
    parser.add_argument("job", type=Path)
    parser.add_argument("--frames", required=True, help="comma-separated frame indices")
    parser.add_argument("--progress-fd", type=int, default=None)
    parser.add_argument("--threads", type=int, default=0, help="Cycles threads (0: all)")
    parser.add_argument("--parent-pid", type=int, default=None,
                        help="end with this process (Linux: killed when it exits)")
    parser.add_argument("--keep-raw", type=Path, default=None, metavar="DIR",
                        help="also keep each frame's raw render (before the camera effects) "
                             "in DIR")
    parser.add_argument("--bare", action="store_true",
                        help="render only (no file, no effects): the bare Cycles time")
    args = parser.parse_args(argv)
    if args.parent_pid is not None:
        from designer.lifetime import die_with_parent

        die_with_parent(args.parent_pid)
    job = RenderJob.read(args.job)
    if args.threads:
        job = dataclasses.replace(job, render=dataclasses.replace(job.render,
                                                                  threads=args.threads))
    base = args.job.parent
    progress = os.fdopen(args.progress_fd, "w", buffering=1) if args.progress_fd else sys.stderr
    wanted = [int(i) for i in args.frames.split(",") if i != ""]
    frames = {f.index: f for f in job.frames}
    out_dir = Path(job.output_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    ext = job.render.extension
    t0 = time.perf_counter()
    scene, camera = build_scene(job, base)
    plants = [add_plants(scene, spec, base) for spec in job.vegetation]
    chains = {} if args.bare else load_effects(job, base)
    void_map = None if args.bare else add_void_map(scene, base / PARTIAL_DIR)
    emit(progress, event="scene_ready", seconds=time.perf_counter() - t0)
    current = {spec.name: spec for spec in job.objects}
    exif = job.image_metadata == "exif"
    for order, index in enumerate(wanted):
        t_setup = time.perf_counter()
        step = frames[index].light_step
        if step is not None:
            apply_light_step(scene, current, job.light_steps[step], base)
        frame = frames[index]
        if plants:
            pose_plants(plants, job.wind, frame.time_s)
        if job.tiled_texture is not None:
            upcoming = [frames[i].texture_tiles
                        for i in wanted[order + 1:order + 1 + LOOK_AHEAD_FRAMES]]
            show_texture_tiles(job.tiled_texture, frame.texture_tiles, base, upcoming)
        done = render_frame(scene, camera, frame, out_dir, ext, base / PARTIAL_DIR,
                            chains.get(frame.camera_id), exif,
                            setup_s=time.perf_counter() - t_setup, bare=args.bare,
                            raw_dir=args.keep_raw, void_map=void_map)
        # order: the frame's place in this process (its first frame also builds Cycles'
        # copy of the scene)
        emit(progress, event="frame_done", index=index, order=order, **done)
    import resource

    peak_mb = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    emit(progress, event="worker_done", blender=bpy.app.version_string, peak_rss_mb=peak_mb)
    return 0


def emit(stream, **fields) -> None:
    stream.write(json.dumps(fields) + "\n")
    stream.flush()


if __name__ == "__main__":
    sys.exit(main())
