"""Semantic checks of where photos are taken, the image effects and the render settings."""

from __future__ import annotations

import math
import re
from collections import Counter

from designer.core.rig import mount_tilt_deg
from designer.project import model as m
from designer.project.geometry import (
    polygon_area,
    polygon_is_degenerate,
    polygon_self_intersection,
)
from designer.project.problems import Issue
from designer.project.validate_declared import element_issues
from designer.project.validate_shared import (
    BIT_DEPTHS,
    EXTENSIONS,
    finite_issues,
    is_ok,
    plain_extent,
    plain_m,
)

_IMAGE_SUFFIX = re.compile(r"\.(png|jpe?g|tiff?|exr|bmp)$", re.IGNORECASE)


def trajectory_issues(project: m.Project) -> list[Issue]:
    traj = project.trajectory
    out: list[Issue] = []
    if not traj.exterior_orientations and traj.flight_plan is None and not traj.patterns:
        out.append(Issue(traj, "trajectory", "no photos: add exterior orientations (photos) "
                                             "or a flight plan",
                         code="no-photos"))
    out += rig_issues(project)
    out += pattern_issues(project)
    out += _photos(project)
    if traj.flight_plan is not None:
        out += _flight_plan(project, traj.flight_plan)
    return out


def _lowest_ground(terrain: m.Terrain) -> float | None:
    src = terrain.source
    if isinstance(src, m.FlatTerrain):
        return src.height_m
    if isinstance(src, m.ProceduralTerrain):
        return src.min_height_m
    return None


def _photos(project: m.Project) -> list[Issue]:
    photos = project.trajectory.exterior_orientations
    camera_ids = {c.id for c in project.cameras} | {r.name for r in project.trajectory.rigs}
    ground = _lowest_ground(project.scene.terrain)
    allowed = EXTENSIONS.get(project.render.output_format, ())
    out: list[Issue] = []
    counts = Counter(p.name for p in photos)
    reported: set[str] = set()
    for p in photos:
        if element_issues(p):
            continue  # a value out of its declared range (validate_declared names it)
        if counts[p.name] > 1 and p.name not in reported:
            reported.add(p.name)
            out.append(Issue(p, "photo", f"image name '{p.name}' is used by {counts[p.name]} "
                                         "photos; give each photo its own name", attr="name"))
        if p.camera not in camera_ids:
            out.append(_unknown_camera(p, "photo", camera_ids, bool(project.trajectory.rigs)))
        if ground is not None and p.Z <= ground:
            out.append(Issue(p, "photo", f"photo '{p.name}' at Z {p.Z:g} m is not above the "
                             f"terrain (lowest ground {ground:g} m); raise Z", attr="Z"))
        suffix = _IMAGE_SUFFIX.search(p.name)
        if suffix and allowed and suffix.group(0).lower() not in allowed:
            out.append(Issue(p, "photo", f"image name '{p.name}' does not match the output "
                             f"format {project.render.output_format}; use {allowed[0]} or "
                             "change the output format", attr="name", code="name-vs-format",
                             value=project.render.output_format, choices=allowed))
    return out


def _unknown_camera(obj, tag: str, camera_ids: set[str], rigs: bool = False) -> Issue:
    """The issue of ``obj``'s ``<tag camera>`` naming no camera (or rig) of the project:
    code "choice", the ids it may name as its choices."""
    known = ", ".join(sorted(camera_ids)) or "none"
    what = "a camera or rig" if rigs else "a camera"
    return Issue(obj, tag, f"camera '{obj.camera}' is not defined; use the id of {what} "
                 f"({known})", attr="camera", code="choice", value=obj.camera,
                 choices=tuple(sorted(camera_ids)))


#: largest angle (deg) between a mount's viewing axis and the platform's: beyond it the
#: camera would look backwards, away from where the platform points
MAX_MOUNT_TILT_DEG = 90.0


def pattern_issues(project: m.Project) -> list[Issue]:
    """Orbit and facade flights: a known camera or rig, a facade of some length, rows at
    finite heights, fewer than 100000 stations."""
    camera_ids = {c.id for c in project.cameras} | {r.name for r in project.trajectory.rigs}
    out: list[Issue] = []
    for p in project.trajectory.patterns:
        tag = "orbit" if isinstance(p, m.OrbitPattern) else "facade"
        if p.camera not in camera_ids:
            out.append(_unknown_camera(p, tag, camera_ids, bool(project.trajectory.rigs)))
        if isinstance(p, m.FacadePattern):
            length = math.dist(p.start, p.end)
            if not length > 0:
                out.append(Issue(p, tag, "the facade's two ends (X1, Y1) and (X2, Y2) are the "
                                 "same point; give its ends on the ground", attr="X2"))
            elif length / p.spacing_m * len(p.heights_m) > 100_000:
                out.append(Issue(p, tag, f"a spacing of {p.spacing_m:g} m gives more than 100000 "
                                 "stations; increase it", attr="spacing-m"))
            if not all(math.isfinite(h) for h in p.heights_m):
                out.append(Issue(p, tag, "the facade's heights must be numbers (m above its "
                                 "base), e.g. \"3 6 9\"", attr="heights-m"))
    return out


def rig_issues(project: m.Project) -> list[Issue]:
    """Rigs: unique names distinct from cameras, known cameras, unique suffixes, angles in
    range and every mount looking no further than 90° from the platform's axis."""
    camera_ids = {c.id for c in project.cameras}
    out: list[Issue] = []
    names = Counter(r.name for r in project.trajectory.rigs)
    for rig in project.trajectory.rigs:
        if rig.name in camera_ids:
            out.append(Issue(rig, "rig", f"rig name '{rig.name}' is also a camera id; give "
                             "the rig a name of its own", attr="name"))
        if names[rig.name] > 1:
            out.append(Issue(rig, "rig", f"rig name '{rig.name}' is used by {names[rig.name]} "
                             "rigs; give each rig its own name", attr="name"))
        if not rig.mounts:
            out.append(Issue(rig, "rig", f"rig '{rig.name}' has no mount; add one per camera"))
        suffixes = Counter(mt.suffix for mt in rig.mounts)
        for mount in rig.mounts:
            if mount.camera not in camera_ids:
                known = ", ".join(sorted(camera_ids)) or "none"
                out.append(Issue(mount, "mount", f"camera '{mount.camera}' of rig '{rig.name}' "
                                 f"is not defined; use the id of a camera ({known})",
                                 attr="camera", code="choice", value=mount.camera,
                                 choices=tuple(sorted(camera_ids))))
            if suffixes[mount.suffix] > 1:
                out.append(Issue(mount, "mount", f"suffix '{mount.suffix}' is used by "
                                 f"{suffixes[mount.suffix]} mounts of rig '{rig.name}'; give "
                                 "each mount its own suffix", attr="suffix"))
            angles = (mount.omega_deg, mount.phi_deg, mount.kappa_deg)
            if element_issues(mount):
                continue  # an angle out of its declared range (validate_declared names it)
            if (tilt := mount_tilt_deg(*angles)) > MAX_MOUNT_TILT_DEG:
                out.append(Issue(mount, "mount", f"mount '{mount.suffix}' of rig '{rig.name}' "
                                 f"looks {tilt:.1f} degrees away from the platform's axis; "
                                 f"keep omega and phi within {MAX_MOUNT_TILT_DEG:g} degrees "
                                 "of it", attr="omega"))
    return out


def _flight_plan(project: m.Project, fp: m.FlightPlan) -> list[Issue]:
    out = finite_issues(fp)
    camera_ids = {c.id for c in project.cameras} | {r.name for r in project.trajectory.rigs}
    if fp.camera not in camera_ids:
        out.append(_unknown_camera(fp, "flight-plan", camera_ids,
                                   bool(project.trajectory.rigs)))
    out += _area(project, fp)
    # the ranges of altitude, GSD, overlaps, angles and choices are declared
    # (designer.project.validate_declared)
    if (fp.altitude_agl_m is None) == (fp.gsd_m is None):
        out.append(Issue(fp, "flight-plan", "give exactly one of the flight height above ground "
                                              "and the GSD"))
    ref = fp.altitude_reference
    if not (ref in ("mean", "max", "min") if isinstance(ref, str) else is_ok(ref)):
        out.append(Issue(fp, "altitude-reference", f"altitude reference {ref!r} must be mean, "
                                                   "max, min or a finite height in m"))
    pattern = re.compile(rf"{re.escape(fp.image_prefix)}\d{{4,}}(\.\w+)?$")
    clash = next((p for p in project.trajectory.exterior_orientations
                  if pattern.match(p.name)), None)
    if clash is not None:
        out.append(Issue(clash, "photo", f"image name '{clash.name}' clashes with the names "
                         f"the flight plan gives its photos ({fp.image_prefix}0001, ...); "
                         "rename the photo or change the flight plan's image prefix", attr="name"))
    return out


def _area(project: m.Project, fp: m.FlightPlan) -> list[Issue]:
    vertices = fp.area
    if len(vertices) < 3:
        return [Issue(fp, "area", f"the area has {len(vertices)} vertices; a polygon needs at "
                                  "least 3")]
    if not all(is_ok(x) and is_ok(y) for x, y in vertices):
        return [Issue(fp, "area", "every vertex needs finite X and Y coordinates")]
    out = []
    for i, (a, b) in enumerate(zip(vertices, vertices[1:] + vertices[:1], strict=True)):
        if a == b:
            out.append(Issue(fp, "vertex", f"vertex {(i + 1) % len(vertices) + 1} repeats the "
                             "one before; remove it", key=f"vertex:{(i + 1) % len(vertices)}"))
    if out:
        return out
    zero_area = [Issue(fp, "area", "the area polygon has zero area (its vertices lie on a "
                                   "line); give the corners of the area to fly")]
    if polygon_is_degenerate(vertices):
        return zero_area
    crossing = polygon_self_intersection(vertices)
    if crossing is None and abs(polygon_area(vertices)) < 1e-6:
        return zero_area
    if crossing is not None:
        i, j = crossing
        return [Issue(fp, "vertex", f"the area polygon crosses itself: edge {i + 1} (vertex "
                      f"{i + 1} to {i + 2}) meets edge {j + 1}; list the vertices in order "
                      "around the area", key=f"vertex:{i}")]
    extent = project.scene.terrain.extent
    for i, (x, y) in enumerate(vertices):
        if not extent.contains(x, y):
            out.append(Issue(fp, "vertex", f"vertex {i + 1} (X {plain_m(x)}, Y {plain_m(y)}) lies "
                             f"outside the terrain extent ({plain_extent(extent)}); move it "
                             "inside or enlarge the extent",
                             key=f"vertex:{i}", attr="X", code="outside-extent",
                             value=(f"vertex {i + 1} of the survey area", x, y)))
    return out


def effects_issues(fx: m.Effects | None) -> list[Issue]:
    """What the effects' declared ranges (validate_declared) cannot say: the vignetting
    gain stays within 0 … 1 over the image."""
    if fx is None or fx.vignetting is None or element_issues(fx.vignetting):
        return []
    return _vignetting_gain_issues(fx.vignetting)


def _vignetting_gain_issues(v) -> list[Issue]:
    """The radial polynomial must keep the gain within 0 … 1 for ρ in 0 … 1."""
    rho2 = [(k / 200) ** 2 for k in range(201)]
    gains = [1 - v.corner_falloff * r + v.rho4 * r * r + v.rho6 * r ** 3 for r in rho2]
    worst = min(range(201), key=lambda k: min(gains[k], 1 - gains[k]))
    g = gains[worst]
    if 0 <= g <= 1 + 1e-12:
        return []
    return [Issue(v, "vignetting", "the vignetting gain 1 − falloff·ρ² + ρ⁴ term·ρ⁴ + ρ⁶ "
                  f"term·ρ⁶ is {g:.4g} at ρ = {worst / 200:g}; choose coefficients that keep it "
                  f"between 0 and 1 from the centre (ρ = 0) to the corners (ρ = 1)", attr="rho4")]


def render_output_issues(project: m.Project) -> list[Issue]:
    r, out = project.render, []
    # preset, samples, filter, scale, workers and their choices are declared
    # (designer.project.validate_declared); the bit depth each format allows is not
    depths = BIT_DEPTHS.get(r.output_format)
    if depths is not None and r.bit_depth not in depths:
        out.append(Issue(r, "output", f"{r.output_format} images cannot have {r.bit_depth} "
                         f"bits per channel; use bit-depth " + " or ".join(map(str, depths)),
                         attr="bit-depth"))
    outputs = project.outputs
    if not outputs.directory.strip():
        out.append(Issue(outputs, "outputs", "the output directory is empty; name a folder",
                         attr="directory"))
    seen = set()
    for i, fmt in enumerate(outputs.ground_truth):
        if fmt in seen:
            out.append(Issue(outputs, "ground-truth", f"ground-truth format '{fmt}' is listed "
                             "twice; remove one", key=f"ground-truth:{i}", attr="format"))
        seen.add(fmt)
    if "odm" in seen:
        from designer.core.crs import crs_token, odm_crs_problem

        problem = odm_crs_problem(crs_token(project.crs))
        if problem is not None:
            i = outputs.ground_truth.index("odm")
            out.append(Issue(outputs, "ground-truth", f"the CRS '{project.crs}' cannot head "
                             f"OpenDroneMap's files: {problem}; start the CRS with a projected "
                             "EPSG code in metres (e.g. 'EPSG:32632'), 'WGS84 UTM' and a zone "
                             "(e.g. 'WGS84 UTM 32N') or a +proj string, or drop the odm format",
                             key=f"ground-truth:{i}", attr="format"))
    return out
