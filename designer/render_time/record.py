"""After a render: record this machine's render coefficients fitted to its frames
(:mod:`designer.render_time.model`), filed under what drives their cost, so the next
estimate of that kind of render is this machine's.

It reads the render's prepared job (:class:`designer.render.job.PreparedJob`) and its
report (:class:`designer.render.runner.RenderReport`) by their fields alone: the render
calls it, so it imports nothing of render."""

from __future__ import annotations

import json
import os
from collections import Counter
from dataclasses import replace

import numpy as np

from designer.render_time.model import (
    cost_key,
    fit_speed,
    frame_cpu_s,
    image_costs,
    load_speed,
    project_bake_mp,
    save_speed,
)


def job_texture_path(job) -> str:
    """The path a job's renderer takes for the ground texture (model.texture_path):
    tiled, node-graph (a material blends the variation itself) or baked."""
    if job.tiled_texture is not None:
        return "tiled"
    terrain = next((o for o in job.objects if o.name == "terrain"), None)
    if terrain is not None and any(m.variation for m in terrain.materials):
        return "node-graph"
    return "baked"


def job_bake_mp(prepared, project) -> float | None:
    """Megapixels of the ground texture bake the job prepared (model.project_bake_mp
    of its project, with the texture image it built); None without the project."""
    if project is None:
        return None
    if job_texture_path(prepared.job) != "baked":
        return 0.0  # tiles baked as frames see them, or no bake (bench render's node graph)
    hf = prepared.scene.heightfield
    rgb = prepared.scene.texture_rgb
    return project_bake_mp(project, None if hf is None else hf.extent_m,
                           None if rgb is None else (rgb.shape[1], rgb.shape[0]))


def record_render_speed(prepared, report,
                        prepare_seconds: float, cores: int | None = None,
                        source: str = "render", project=None):
    """Fit the coefficients to the frames ``report`` rendered (with their stages) and
    add them as a record filed under the frames' kind (``project``'s scene and effects,
    the samples and the image size: the most common among the frames); a probe's record
    replaces the earlier probe's. Returns the recorded :class:`RenderSpeed`, or None
    when the run rendered no frame with stages."""
    timed = sorted(i for i, st in report.stages.items()
                   if "cycles_cpu_s" in st and i in report.rendered)
    if not timed:
        return None
    # a worker's first frame also builds Cycles' scene: fitted only when nothing else
    # was rendered (its extra time lands in the fixed part through the wall time)
    frames = [i for i in timed if i not in report.first_frames] or timed
    cores = max(1, cores or os.cpu_count() or 1)
    workers = max(1, len(report.peak_rss_mb) or len(report.scene_seconds) or 1)
    poses = [prepared.poses[i] for i in timed]
    costs = image_costs(prepared.scene.heightfield,
                        np.array([p.C_world for p in poses]).reshape(-1, 3),
                        np.array([p.R_cam_to_world for p in poses]).reshape(-1, 3, 3),
                        [prepared.interior_of(p.image_name) for p in poses],
                        prepared.job.render.samples, project, job_texture_path(prepared.job),
                        job_bake_mp(prepared, project))
    all_costs = dict(zip(timed, costs, strict=True))
    images = [all_costs[i] for i in frames]
    cpu = [report.stages[i]["cycles_cpu_s"] for i in frames]
    # a busy machine stretches the wall seconds outside Cycles; each frame's are scaled
    # to the idle machine by the share of the cores its Cycles threads had
    threads = prepared.job.render.threads or max(1, cores // workers)
    shares = {i: core_share(report.stages[i], threads) for i in timed}
    post = [max(0.0, report.rendered[i] - report.stages[i].get("cycles_s", 0.0)) * shares[i]
            for i in frames]
    keys = Counter(json.dumps(cost_key(c), sort_keys=True) for c in images)
    typical = next(c for c in images
                   if json.dumps(cost_key(c), sort_keys=True) == keys.most_common(1)[0][0])
    measured = fit_speed(images, cpu, post, 0.0, source, prior=load_speed(typical))
    # the fixed part: what the model of every timed frame (an idle machine's seconds)
    # leaves of the wall time, the wall time first scaled to the idle machine by the
    # frames' median share of the cores (a busy machine's frames took 1/share as long)
    frames_wall = (sum(frame_cpu_s(measured, c) for c in all_costs.values()) / cores
                   + sum(c.megapixels * measured.post_s_per_mp for c in all_costs.values())
                   / workers)
    share = float(np.median(list(shares.values())))
    fixed = (prepare_seconds + max(0.0, report.wall_seconds - frames_wall / share)) * share
    measured = replace(measured, fixed_s=fixed, fixed_bake_mp=typical.bake_mp)
    save_speed(measured, typical)
    return measured


def core_share(stages: dict, threads: int) -> float:
    """The share of its ``threads`` cores a frame's Cycles render had (its CPU-seconds
    over its wall seconds times the threads, at most 1; 1 when not measured): near 1 on
    an idle machine, 0.3 when other work took seven tenths of the cores. The seconds
    outside Cycles a busy machine measured, times this share, are an idle machine's."""
    wall = float(stages.get("cycles_s") or 0.0)
    cpu = float(stages.get("cycles_cpu_s") or 0.0)
    if wall <= 0.0 or cpu <= 0.0:
        return 1.0
    return min(1.0, max(0.05, cpu / (wall * threads)))
