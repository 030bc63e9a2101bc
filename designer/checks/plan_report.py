"""``designer plan``: what a project's flight will deliver, before any rendering.

Figures (units in the names): image count; GSD over the real terrain; footprint;
achieved front/side overlap measured by projecting real footprints; for each GCP the
number of images that see it unoccluded; share of the area seen by ≥ 2, ≥ 3, ≥ 5
images; and an estimated render time.
"""

from __future__ import annotations

import dataclasses
import math
import os
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from designer.checks.hard_cases import aliasing_warning, control_warning, network_warnings
from designer.core.heightfield import Heightfield
from designer.core.rotation import opk_from_rotation
from designer.errors import DesignerError
from designer.project import model as m
from designer.project.interiors import render_interior
from designer.render_time.model import (
    estimate_render_s,
    format_duration,
    load_speed,
    project_image_costs,
    render_workers,
)
from designer.scene.build import BuiltTarget, build_heightfield, build_targets
from designer.scene.surroundings import surroundings_mode
from designer.survey.coverage import PlanAnalysis, analyse_plan
from designer.survey.flight import Station
from designer.survey.gcp_sightings import project_gcp_visibility
from designer.survey.project_poses import platform_stations, project_images, project_stations
from designer.survey.surroundings import VOID_WARN, ImageGround, image_ground, repeat_warning


@dataclass(frozen=True)
class PlanResult:
    project: m.Project
    stations: tuple[Station, ...]
    heightfield: Heightfield
    targets: tuple[BuiltTarget, ...]
    #: its ``gcps`` count every image of the project (each camera of a rig; indices into
    #: project_images), not only the stations' planning camera
    analysis: PlanAnalysis
    footprint_m: tuple[float, float]
    #: the camera or rig of each station
    carriers: tuple[str, ...] = ()
    #: images of all cameras (a rig takes several per station)
    n_images_all_cameras: int | None = None
    #: per camera of a rig project: (camera id, images, median GSD at the principal point
    #: on the terrain m/px or NaN, median distance there m or NaN)
    cameras: tuple[tuple[str, int, float, float], ...] = ()
    #: where the render estimate's coefficients come from (RenderSpeed.describe)
    render_speed: str = ""
    #: every image's share of pixels that see no ground, over the rendered terrain
    ground: ImageGround | None = None


def plan_project(project: m.Project, base_dir: Path, cell_m: float | None = None) -> PlanResult:
    """Plan and analyse a project's flight over its terrain."""
    hf = build_heightfield(project.scene.terrain, Path(base_dir), project.crs)
    if hf is None:
        raise DesignerError("designer plan needs a height-field terrain (flat, procedural or "
                            "DEM); a mesh terrain cannot be analysed yet")
    platform = platform_stations(project, hf)  # the flight planned once for all three
    stations, camera_id = project_stations(project, hf, platform)
    carriers = tuple(platform[1])
    images = project_images(project, hf, platform)
    n_all = len(images.stations)
    # the images see the rendered terrain: the declared one and its surroundings
    ground = image_ground(project, hf, images)
    hf = ground.rendered
    per_camera = _camera_figures(project, images, hf) if project.trajectory.rigs else ()
    targets = build_targets(project, hf)
    interior = render_interior(project.camera(camera_id), project.render.resolution_scale)
    plan = project.trajectory.flight_plan
    area = np.array(plan.area) if plan is not None else _extent_polygon(project)
    rc = ground.raycaster
    analysis = analyse_plan(stations, interior, hf, area, cell_m=cell_m, raycaster=rc)
    if targets:
        # every image that sees a GCP counts (each camera of a rig), as in the GUI
        analysis = replace(analysis, gcps=project_gcp_visibility(
            project, images, np.array([t.true_xyz for t in targets]), rc))
    costs = project_image_costs(project, images, hf, _texture_px(project, Path(base_dir)))
    # each kind of image with this machine's figures for its kind
    speed = load_speed(costs[0] if costs else None)
    analysis = replace(analysis, render_time_s=estimate_render_s(
        costs, render_workers(project, n_all)))
    gsd = analysis.median_gsd_m()
    W, H = interior.image_size_px
    return PlanResult(project, tuple(stations), hf, targets, analysis, (W * gsd, H * gsd),
                      carriers, n_all, per_camera, speed.describe(), ground)


def _texture_px(project: m.Project, base_dir: Path) -> tuple[int, int] | None:
    """(W, H) of a tiled image texture (which decides the render's texture path); None
    for other textures or an unreadable file."""
    src = project.scene.texture.source
    if not isinstance(src, m.ImageTexture):
        return None
    from designer.scene.texture import load_texture

    try:
        h, w = load_texture(base_dir / src.file).shape[:2]
    except DesignerError:
        return None
    return w, h


def _camera_figures(project: m.Project, images, hf: Heightfield
                    ) -> tuple[tuple[str, int, float, float], ...]:
    """Per camera: its image count, the median GSD (m/px) and distance (m) where its
    principal ray meets the terrain (NaN where none does)."""
    from designer.core.projection import ground_sample_distance_m, pixel_rays_world

    out = []
    for camera_id in images.camera_order():
        interior = render_interior(project.camera(camera_id), project.render.resolution_scale)
        mine = [st for st, c in zip(images.stations, images.camera_ids, strict=True)
                if c == camera_id]
        centre = np.array([[interior.cx_px, interior.cy_px]])
        C = np.array([st.C_world for st in mine])
        rays = np.concatenate([pixel_rays_world(centre, st.R_cam_to_world, interior)
                               for st in mine])
        hits = hf.intersect_rays(C, rays)
        depth = np.einsum("ij,ij->i", hits - C, -np.array([st.R_cam_to_world[:, 2]
                                                             for st in mine]))
        ok = np.isfinite(depth)
        distance = float(np.median(depth[ok])) if ok.any() else math.nan
        gsd = float(ground_sample_distance_m(interior, distance))
        out.append((camera_id, len(mine), gsd, distance))
    return tuple(out)


def _extent_polygon(project: m.Project) -> np.ndarray:
    e = project.scene.terrain.extent
    return np.array([[e.min_X, e.min_Y], [e.max_X, e.min_Y], [e.max_X, e.max_Y],
                     [e.min_X, e.max_Y]])


def plan_summary(result: PlanResult) -> dict:
    """JSON-ready figures: the analysis summary plus per-GCP view counts."""
    out = dict(result.analysis.summary())
    out["footprint_m"] = list(result.footprint_m)
    gsd = result.analysis.coverage.gsd_mean_m
    finite = gsd[np.isfinite(gsd)]
    out["gsd_terrain_m"] = ({"min": float(finite.min()), "mean": float(finite.mean()),
                             "max": float(finite.max())} if finite.size else None)
    if result.ground is not None:
        g = result.ground
        out["surroundings"] = surroundings_mode(result.project.scene.terrain)
        x0, x1, y0, y1 = g.rendered.extent_m
        out["rendered_terrain_extent_m"] = {"min_X": x0, "max_X": x1, "min_Y": y0, "max_Y": y1}
        out["void_share_max"] = float(g.void_share.max()) if len(g.void_share) else 0.0
        out["images_void_over_1_percent"] = int(np.count_nonzero(g.void_share > VOID_WARN))
        out["void_share"] = {n: round(float(v), 5)
                             for n, v in zip(g.names, g.void_share, strict=True)}
    out["warnings"] = plan_warnings(result, out)
    out["render_time_source"] = result.render_speed
    out.update(rig_and_pattern_summary(result))
    if result.analysis.gcps is not None:
        out["gcps"] = [{"id": t.target.id, "role": t.target.role,
                        "images": int(result.analysis.gcps.counts[k])}
                       for k, t in enumerate(result.targets)]
    return {k: (None if isinstance(v, float) and math.isnan(v) else v) for k, v in out.items()}




def rig_and_pattern_summary(result: PlanResult) -> dict:
    """The rigs flown (cameras, images) and the orbit / facade flights (stations)."""
    traj = result.project.trajectory
    out: dict = {}
    if traj.rigs:
        out["n_images_all_cameras"] = result.n_images_all_cameras
        out["cameras"] = [{"id": c, "images": n,
                           "gsd_centre_median_m": None if math.isnan(g) else g,
                           "distance_centre_median_m": None if math.isnan(d) else d}
                          for c, n, g, d in result.cameras]
        out["rigs"] = [{"name": r.name, "cameras": [mt.camera for mt in r.mounts],
                        "suffixes": [mt.suffix for mt in r.mounts],
                        "stations": result.carriers.count(r.name),
                        "images": result.carriers.count(r.name) * len(r.mounts)}
                       for r in traj.rigs]
    if traj.patterns:
        patterns = []
        for p in traj.patterns:
            if isinstance(p, m.OrbitPattern):
                n = p.n_stations
            else:
                n = len(p.heights_m) * (math.floor(math.dist(p.start, p.end) / p.spacing_m
                                                   + 1e-9) + 1)
            if isinstance(p, m.OrbitPattern):
                patterns.append({"kind": "orbit", "camera": p.camera, "prefix": p.image_prefix,
                                 "stations": n, "radius_m": p.radius_m,
                                 "height_m": p.height_m, "tilt_deg": p.tilt_deg})
            else:
                patterns.append({"kind": "facade", "camera": p.camera,
                                 "prefix": p.image_prefix, "stations": n,
                                 "distance_m": p.distance_m, "rows": len(p.heights_m),
                                 "spacing_m": p.spacing_m, "tilt_deg": p.tilt_deg})
        out["patterns"] = patterns
    return out


def plan_warnings(result: PlanResult, figures: dict) -> list[str]:
    """Things a surveyor should fix before rendering."""
    warnings = []
    source = result.project.scene.texture.source
    gsd = figures.get("gsd_terrain_m")
    aliasing = aliasing_warning(source, gsd["min"]) if gsd else None
    if aliasing:
        warnings.append(aliasing)
    repeat = texture_repeat_warning(result.project.scene.texture,
                                    result.project.scene.terrain.extent, result.footprint_m)
    if repeat:
        warnings.append(repeat)
    void = result.ground.warning(result.project) if result.ground is not None else None
    if void:
        warnings.append(void)
    copies = (repeat_warning(result.project, result.ground.growth)
              if result.ground is not None else None)
    if copies:
        warnings.append(copies)
    if result.analysis.gcps is not None:
        few = [t.target.id for k, t in enumerate(result.targets)
               if result.analysis.gcps.counts[k] < 3]
        if few:
            warnings.append(f"GCPs seen by fewer than 3 images: {', '.join(few)}")
    control = control_warning(result.targets)
    if control is not None:  # in designer check's words
        warnings.append(f"{control.message}; {control.fix}")
    if result.stations:  # a result for the texture only has none
        n = result.n_images_all_cameras or len(result.stations)
        warnings += [f"{w.message}; {w.fix}" for w in network_warnings(
            result.project, n, [s.line_index for s in result.stations])]
    return warnings


def texture_repeat_warning(texture: m.Texture, extent: m.Extent,
                           footprint_m: tuple[float, float]) -> str | None:
    """A warning when a tiled texture without a variation repeats inside one image.

    The repeat period is the shorter tile side (m); the footprint the shorter side of
    the image's ground footprint (m). Without a ``<variation>`` two images whose
    footprints do not overlap can show the same texture, and matching pairs them.
    """
    if texture.variation is not None or (texture.repeat_X == 1 and texture.repeat_Y == 1):
        return None
    period_m = min(extent.width_m / texture.repeat_X, extent.length_m / texture.repeat_Y)
    side_m = min(footprint_m)
    if not (period_m < side_m):
        return None
    return (f"texture repeats every {period_m:g} m, shorter than the {side_m:.1f} m footprint: "
            "matching may pair images that do not overlap; give the texture a variation (e.g. "
            f"seed 1, scale {2 * period_m:g} m, strength 0.35; docs/world.md)")


def format_plan(result: PlanResult, source: str) -> str:
    """A plain-text report a surveyor can read."""
    s = plan_summary(result)
    lines = [f"{source}: {s['n_images']} images ({s['stations_over_area']} over the area)"]
    for r in s.get("rigs", ()):
        lines.append(f"  rig {r['name']}: {len(r['cameras'])} cameras "
                     f"({', '.join(r['cameras'])}) at {r['stations']} stations = "
                     f"{r['images']} images; {s['n_images_all_cameras']} images in all "
                     "(figures below: each station's planning camera)")
    for c in s.get("cameras", ()):
        gsd = c["gsd_centre_median_m"]
        where = ("its principal ray misses the terrain" if gsd is None else
                 f"GSD at the image centre {100 * gsd:.2f} cm, "
                 f"{c['distance_centre_median_m']:.1f} m away (medians)")
        lines.append(f"    camera {c['id']}: {c['images']} images, {where}")
    for p in s.get("patterns", ()):
        if p["kind"] == "orbit":
            tilt = "aimed at the centre" if p["tilt_deg"] is None else f"tilt {p['tilt_deg']:g}°"
            lines.append(f"  orbit {p['prefix']} ({p['camera']}): {p['stations']} stations, "
                         f"radius {p['radius_m']:g} m, {p['height_m']:g} m above the centre, "
                         f"{tilt}")
        else:
            lines.append(f"  facade {p['prefix']} ({p['camera']}): {p['stations']} stations in "
                         f"{p['rows']} rows every {p['spacing_m']:g} m, {p['distance_m']:g} m "
                         f"from the facade, {p['tilt_deg']:g}° below level")
    g = s["gsd_terrain_m"]
    if g:
        lines.append(f"  GSD over the terrain: {100 * g['min']:.2f} / {100 * g['mean']:.2f} / "
                     f"{100 * g['max']:.2f} cm (min / mean / max)")
    if "void_share" in s:
        x = s["rendered_terrain_extent_m"]
        lines.append(f"  rendered terrain ({s['surroundings']} surroundings): X "
                     f"{x['min_X']:.1f} to {x['max_X']:.1f}, Y {x['min_Y']:.1f} to "
                     f"{x['max_Y']:.1f}; pixels seeing no ground: at most "
                     f"{100 * s['void_share_max']:.2f} % of an image, "
                     f"{s['images_void_over_1_percent']} images over {100 * VOID_WARN:g} %")
    lines.append(f"  footprint at the median GSD: {s['footprint_m'][0]:.1f} x "
                 f"{s['footprint_m'][1]:.1f} m")
    for name, label in (("front_overlap", "front overlap"), ("side_overlap", "side overlap")):
        if s.get(f"{name}_median") is not None:
            lines.append(f"  {label}: median {100 * s[f'{name}_median']:.1f} %, 5th percentile "
                         f"{100 * s[f'{name}_p05']:.1f} %, min {100 * s[f'{name}_min']:.1f} %")
    shares = [f"{100 * s[f'area_seen_by_{k}_or_more']:.1f} % by >= {k}" for k in (2, 3, 5)]
    lines.append("  area seen: " + ", ".join(shares))
    if "gcps" in s:
        lines.append("  GCPs (images that see the target unoccluded):")
        for g in s["gcps"]:
            flag = "  <- fewer than 3" if g["images"] < 3 else ""
            lines.append(f"    {g['id']:<10} {g['role']:<8} {g['images']:>4}{flag}")
    for warning in s["warnings"]:
        lines.append(f"  warning: {warning}")
    if s.get("render_time_s") is not None:
        n_all = result.n_images_all_cameras or s["n_images"]
        workers = render_workers(result.project, n_all)
        lines.append(f"  estimated render time: {format_duration(s['render_time_s'])} for "
                     f"{n_all} images at {result.project.render.effective_samples} samples "
                     f"per pixel with {workers} worker{'s' if workers != 1 else ''} on "
                     f"{os.cpu_count()} cores ({result.render_speed})")
    return "\n".join(lines)


def project_with_explicit_poses(result: PlanResult) -> m.Project:
    """The project with its sampled stations written out as exterior orientations.

    The flight plan is dropped: a render of the new file needs no generator and gives
    exactly the same images.
    """
    project = result.project
    carriers = result.carriers or (project.trajectory.flight_plan.camera
                                   if project.trajectory.flight_plan
                                   else project.trajectory.exterior_orientations[0].camera,
                                   ) * len(result.stations)
    eos = []
    for st, camera_id in zip(result.stations, carriers, strict=True):
        omega, phi, kappa = (float(np.degrees(a)) for a in opk_from_rotation(st.R_cam_to_world))
        eos.append(m.ExteriorOrientation(st.image_name, camera_id, *map(float, st.C_world),
                                         omega, phi, kappa))
    trajectory = m.Trajectory(exterior_orientations=tuple(eos), rigs=project.trajectory.rigs)
    return dataclasses.replace(project, trajectory=trajectory)
