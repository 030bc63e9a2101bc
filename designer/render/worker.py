"""The render worker: the only module of designer that imports ``bpy``.

Run as ``python -m designer.render.worker JOB.json --frames 0,1,5 [--progress-fd N]``.
It builds the scene described by the job once, then renders the frames asked for,
each to a temporary file renamed into place when complete. Progress goes out as JSON
lines on file descriptor N (stdout carries Blender's own log).

Only effects the job asks for are rendered: no denoiser, no adaptive sampling, no
dithering, a box pixel filter one pixel wide unless asked otherwise, the 'Standard'
view transform (no filmic tone curve), and texture interpolation as configured.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import os
import sys
import time
from pathlib import Path

import bpy  # the one place in designer that imports bpy
import numpy as np
from mathutils import Matrix

from designer.render.job_spec import (
    IMAGE_FORMATS,
    TEXTURE_UV_MAP,
    CameraSpec,
    FrameSpec,
    MaterialSpec,
    MeshSpec,
    RenderJob,
)
from designer.render.png_text import move_without_text


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
    data.lens = camera.lens_mm
    data.sensor_fit = camera.sensor_fit
    data.sensor_width = camera.sensor_width_mm
    data.shift_x = camera.shift_x
    data.shift_y = camera.shift_y
    data.clip_start = camera.clip_start_m
    data.clip_end = camera.clip_end_m
    obj = bpy.data.objects.new("survey_camera", data)
    scene.collection.objects.link(obj)
    scene.camera = obj
    return obj


def load_image(path: str, interpolation_colour: str) -> bpy.types.Image:
    image = bpy.data.images.load(path, check_existing=True)
    image.colorspace_settings.name = interpolation_colour
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
    if spec.uv_map:
        texture_uv = nodes.new("ShaderNodeUVMap")
        texture_uv.uv_map = spec.uv_map
        links.new(texture_uv.outputs["UV"], mapping.inputs["Vector"])
    else:
        links.new(uv.outputs["UV"], mapping.inputs["Vector"])
    tex = nodes.new("ShaderNodeTexImage")
    tex.image = load_image(str(base / spec.texture), "sRGB")
    tex.interpolation = spec.interpolation
    tex.extension = spec.extension
    links.new(mapping.outputs["Vector"], tex.inputs["Vector"])
    colour = tex.outputs["Color"]
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
    for i, mspec in enumerate(spec.materials):
        mesh.materials.append(emission_material(f"{spec.name}_{i}", mspec, base))
    if "material_index" in data:
        mesh.polygons.foreach_set("material_index", np.asarray(data["material_index"], np.int32))
    mesh.update(calc_edges=True)
    mesh.validate(verbose=False)
    obj = bpy.data.objects.new(spec.name, mesh)
    scene.collection.objects.link(obj)
    return obj


def build_scene(job: RenderJob, base: Path) -> tuple[bpy.types.Scene, bpy.types.Object]:
    scene = reset_scene()
    configure_render(scene, job)
    world = bpy.data.worlds.new("world")
    world.use_nodes = True
    background = world.node_tree.nodes.get("Background")
    background.inputs["Color"].default_value = (*job.background_rgb, 1)
    background.inputs["Strength"].default_value = 1.0
    scene.world = world
    for spec in job.objects:
        add_mesh(scene, spec, base)
    camera = add_camera(scene, job.camera)
    return scene, camera


def render_frame(scene, camera, frame: FrameSpec, out_dir: Path, ext: str, chain=None) -> dict:
    """Render one frame; apply the camera effects (if any); rename the image into place."""
    camera.matrix_world = Matrix(frame.matrix_world_local)
    final = out_dir / frame.image_name
    tmp = final.with_name(f".{final.stem}.rendering{ext}")
    scene.render.filepath = str(tmp)
    t0, cpu0 = time.perf_counter(), time.process_time()
    bpy.ops.render.render(write_still=True)
    t1, cpu = time.perf_counter(), time.process_time() - cpu0
    if chain is None and final.suffix.lower() == ".png":
        move_without_text(tmp, final)  # Blender's render-time and date text only
    elif chain is None:
        os.replace(tmp, final)
    else:
        from designer.effects.base import FrameContext
        from designer.effects.chain import process_file

        context = FrameContext(gsd_m=frame.gsd_m, flight_direction_uv=frame.flight_direction_uv,
                               distance_m=frame.distance_m)
        try:
            process_file(tmp, final, chain, frame.index, context)
        finally:
            tmp.unlink(missing_ok=True)
    return {"path": str(final), "seconds": time.perf_counter() - t0,
            "render_seconds": t1 - t0, "render_cpu_seconds": cpu,
            "effects_seconds": time.perf_counter() - t1}


def load_effects(job: RenderJob, base: Path):
    """The camera-effects chain of the job, or None when the images are final as rendered."""
    spec = job.effects
    if spec is None:
        return None
    from designer.effects.distortion_render import DistortionWarp
    from designer.effects.from_model import effects_from_model
    from designer.project import read_project
    from designer.survey.project_poses import render_interior

    project = read_project(base / spec.project)
    interior = render_interior(project.camera(spec.camera_id), spec.resolution_scale)
    warp = DistortionWarp.load(base / spec.warp, interior) if spec.warp else None
    return effects_from_model(project.effects, interior, warp=warp)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="designer.render.worker")
    parser.add_argument("job", type=Path)
    parser.add_argument("--frames", required=True, help="comma-separated frame indices")
    parser.add_argument("--progress-fd", type=int, default=None)
    parser.add_argument("--threads", type=int, default=0, help="Cycles threads (0: all)")
    args = parser.parse_args(argv)
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
    chain = load_effects(job, base)
    emit(progress, event="scene_ready", seconds=time.perf_counter() - t0)
    for index in wanted:
        done = render_frame(scene, camera, frames[index], out_dir, ext, chain)
        emit(progress, event="frame_done", index=index, **done)
    import resource

    peak_mb = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    emit(progress, event="worker_done", blender=bpy.app.version_string, peak_rss_mb=peak_mb)
    return 0


def emit(stream, **fields) -> None:
    stream.write(json.dumps(fields) + "\n")
    stream.flush()


if __name__ == "__main__":
    sys.exit(main())
