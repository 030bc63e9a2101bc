"""Semantic checks of the world over time: the flight's time line, the sun that follows
it and the image metadata that carries it (docs/world.md)."""

from __future__ import annotations

import math

from designer.project import model as m
from designer.project.declare import declared_field
from designer.project.problems import Issue
from designer.project.utc import EXAMPLE_UTC, parse_utc
from designer.project.validate_declared import element_issues
from designer.project.validate_shared import is_ok, plain_extent, plain_m


def trigger_distance_m(project: m.Project, plan: m.FlightPlan) -> float | None:
    """Planned distance between photos along a line (m), nadir footprint × (1 − front
    overlap), as designer.survey.flight.camera_calc computes it; None if not computable."""
    try:
        cam = project.camera(plan.camera)
    except KeyError:
        return None
    f_mm = cam.focal_length_mm
    if plan.altitude_agl_m is not None:
        altitude_m = plan.altitude_agl_m
    elif plan.gsd_m is not None:
        altitude_m = plan.gsd_m * f_mm / (cam.sensor_width_mm / cam.image_width_px)
    else:
        return None
    along_mm = cam.sensor_height_mm if plan.orientation == "landscape" else cam.sensor_width_mm
    distance = altitude_m * along_mm / f_mm * (1.0 - plan.front_overlap_percent / 100.0)
    return distance if math.isfinite(distance) else None


def world_issues(project: m.Project) -> list[Issue]:
    """Problems of the time line, the sun over time and the image metadata."""
    traj = project.trajectory
    tl = traj.time_line
    out: list[Issue] = _moving_objects(project)
    if project.scene.vegetation is not None:
        out += _vegetation(project, project.scene.vegetation)
    out += _rolling_shutters(project)
    if tl is not None:
        out += _time_line(project, tl)
    timed = [p for p in traj.exterior_orientations if p.time_s is not None]
    if timed and tl is None:
        out.append(Issue(timed[0], "photo", f"photo '{timed[0].name}' has a time but the "
                         "trajectory has no time line; add one or remove the time",
                         attr="time-s", code="needs-time-line"))
    last = None
    for p in timed:
        if not declared_field(m.ExteriorOrientation, "time_s").in_range(p.time_s):
            continue  # validate_declared names it
        if last is not None and p.time_s < last.time_s:
            out.append(Issue(p, "photo", f"photo '{p.name}' at {p.time_s:g} s comes "
                             f"before '{last.name}' ({last.time_s:g} s) which is flown first; "
                             "give the photos in the order they are taken", attr="time-s"))
        else:
            last = p
    sun = project.scene.lighting.sun
    if isinstance(sun, m.SunOverTime):
        out += _sun_over_time(project, sun)
    render = project.render
    if render.image_metadata not in ("none", "exif"):
        out.append(Issue(render, "output", f"metadata {render.image_metadata!r} must be none or "
                         "exif", attr="metadata"))
    elif render.image_metadata == "exif":
        if tl is None:
            out.append(Issue(render, "output", "metadata exif writes each photo's time, but the "
                             "trajectory has no time line; add one or write metadata none",
                             attr="metadata", code="needs-time-line"))
        if render.output_format not in ("jpeg", "tiff"):
            out.append(Issue(render, "output", f"metadata exif is written into JPEG and TIFF "
                             f"photos, not {render.output_format}; use format jpeg or tiff",
                             attr="metadata"))
    return out


def _time_line(project: m.Project, tl: m.TimeLine) -> list[Issue]:
    out = []
    if parse_utc(tl.takeoff_utc) is None:
        out.append(Issue(tl, "time-line", f"the take-off time {tl.takeoff_utc!r} is not an "
                         f"ISO 8601 moment in UTC; write it with Z, e.g. {EXAMPLE_UTC}",
                         attr="takeoff-utc"))
    interval = tl.trigger_interval_s
    if interval is None or element_issues(tl):  # ranges: validate_declared
        return out
    plan = project.trajectory.flight_plan
    distance = None if plan is None else trigger_distance_m(project, plan)
    if distance is not None and distance / tl.speed_m_s < interval * (1 - 1e-9):
        out.append(Issue(tl, "time-line", f"the flight plan takes a photo every {distance:.3g} m, "
                         f"{distance / tl.speed_m_s:.3g} s at {tl.speed_m_s:g} m/s, sooner than "
                         f"the camera's trigger interval of {interval:g} s; fly at most "
                         f"{distance / interval:.3g} m/s or lower the front overlap",
                         attr="trigger-interval-s"))
    return out


#: the longest readout a camera may have (s); consumer sensors read in 0.01 to 0.05 s
MAX_READOUT_S = declared_field(m.RollingShutter, "readout_s").attr.high


def _rolling_shutters(project: m.Project) -> list[Issue]:
    """A rolling shutter's readout range, and what it needs: the flight's time line (the
    rows' poses follow the flight), a readout shorter than the trigger interval and a
    lens without distortion (the render is exact for a pinhole camera only)."""
    out = []
    tl = project.trajectory.time_line
    for cam in project.cameras:
        rs = cam.rolling_shutter
        if rs is None:
            continue
        readout = rs.readout_s
        if element_issues(rs) or readout == 0:  # ranges: validate_declared
            continue
        if tl is None:
            out.append(Issue(rs, "rolling-shutter", f"camera '{cam.id}' reads its rows out "
                             f"over {readout:g} s, but the trajectory has no time line to "
                             "move the camera along; add a time line to the trajectory or set "
                             "readout-s 0", attr="readout-s", code="needs-time-line",
                             value=readout))
        elif tl.trigger_interval_s is not None and readout >= tl.trigger_interval_s:
            out.append(Issue(rs, "rolling-shutter", f"camera '{cam.id}': readout-s {readout:g} "
                             "s is not shorter than the time line's trigger-interval-s "
                             f"{tl.trigger_interval_s:g} s; a frame must be read before the "
                             "next is taken: shorten the readout", attr="readout-s",
                             code="readout-not-shorter",
                             value=(cam.id, readout, tl.trigger_interval_s)))
        if cam.distortion is not None:
            out.append(Issue(rs, "rolling-shutter", f"camera '{cam.id}' has lens distortion "
                             "and a rolling shutter, which designer does not render exactly; "
                             "remove the distortion element or set readout-s 0",
                             attr="readout-s", code="distortion-and-rolling-shutter",
                             value=cam.id))
    return out


def _sun_over_time(project: m.Project, sun: m.SunOverTime) -> list[Issue]:
    out = []
    if project.trajectory.time_line is None:
        out.append(Issue(sun, "sun-over-time", "the sun follows each photo's time, but the "
                         "trajectory has no time line; add one or give the sun by its direction "
                         "or for a moment and place", code="needs-time-line"))
    if (sun.latitude_deg is None) != (sun.longitude_deg is None):
        out.append(Issue(sun, "sun-over-time", "give both the latitude and the longitude, or "
                         "neither (then the project origin is used)",
                         attr="latitude-deg" if sun.latitude_deg is None else "longitude-deg"))
    elif sun.latitude_deg is not None:
        pass  # ranges: validate_declared
    else:
        from designer.core.crs import crs_token

        try:
            from pyproj import CRS

            ok = CRS.from_user_input(crs_token(project.crs)).is_projected
        except Exception:  # pyproj's CRSError and anything it raises for a label
            ok = False
        if not ok:
            out.append(Issue(sun, "sun-over-time", f"the project CRS {project.crs!r} is not a "
                             "projected CRS PROJ knows, so the site's latitude and longitude "
                             "cannot be found; give the site's latitude and longitude"))
    return out


def _moving_objects(project: m.Project) -> list[Issue]:
    """Problems of the scene's moving objects (docs/world.md, Moving objects)."""
    out: list[Issue] = []
    seen: set[str] = set()
    for obj in project.scene.moving_objects:
        if project.trajectory.time_line is None:
            out.append(Issue(obj, "object", f"moving object '{obj.id}' is posed at each "
                             "photo's time, but the trajectory has no time line; add one "
                             "or remove the moving objects", code="needs-time-line"))
        if obj.id in seen:
            out.append(Issue(obj, "object", f"moving object id '{obj.id}' is used twice; "
                             "give each object its own id", attr="id"))
        seen.add(obj.id)
        if (obj.shape is None) == (obj.file is None):
            out.append(Issue(obj, "object", f"moving object '{obj.id}' needs exactly one of "
                             "shape and file; give a shape (car, person or box) or a "
                             "mesh file", attr="shape", code="shape-or-mesh"))
        elif obj.shape is not None and obj.shape not in m.MOVING_SHAPES:
            out.append(Issue(obj, "object", f"unknown shape {obj.shape!r}; use one of "
                             f"{', '.join(m.MOVING_SHAPES)} or give a mesh file",
                             attr="shape", code="choice", value=obj.shape,
                             choices=tuple(m.MOVING_SHAPES)))
        elif obj.shape == "box" and (obj.size_m is None or None in obj.size_m):
            out.append(Issue(obj, "object", f"box '{obj.id}' needs a length, a width and a "
                             "height (m)", attr="length-m"))
        if obj.size_m is not None:
            for name, value in zip(m.MOVING_SIZE_XML, obj.size_m,
                                   strict=True):
                if value is not None and not (math.isfinite(value) and 0 < value <= 1000):
                    out.append(Issue(obj, "object", f"{name} = {value!r} must be greater "
                                     "than 0 and at most 1000 m", attr=name))
        if len(obj.albedo_rgb) != 3 or not all(
                math.isfinite(v) and 0 <= v <= 1 for v in obj.albedo_rgb):
            out.append(Issue(obj, "object", "albedo-rgb must be three numbers from 0 to 1 "
                             "(linear red green blue), e.g. \"0.8 0.1 0.1\"",
                             attr="albedo-rgb", code="colour", value=obj.albedo_rgb))
        # speed-m-s and start-s: their declared ranges (validate_declared)
        if len(obj.path) < 2:
            out.append(Issue(obj, "path", f"the path of '{obj.id}' has {len(obj.path)} "
                             "point(s); give at least two points", key="path"))
        elif sum(math.dist((a.X, a.Y), (b.X, b.Y))
                 for a, b in zip(obj.path, obj.path[1:], strict=False)) <= 0:
            out.append(Issue(obj, "path", f"the path of '{obj.id}' has no length; give "
                             "points that differ", key="path"))
        out += _path_off_terrain(obj, project.scene.terrain.extent)
    return out


def _path_off_terrain(obj: m.MovingObject, extent: m.Extent) -> list[Issue]:
    """The first point of ``obj``'s path outside the terrain extent: there the object
    would stand at the height of the terrain's nearest edge, in the air or in the
    ground."""
    for i, p in enumerate(obj.path):
        if is_ok(p.X) and is_ok(p.Y) and not extent.contains(p.X, p.Y):
            return [Issue(p, "point", f"moving object '{obj.id}': path point {i + 1} "
                          f"(X {plain_m(p.X)}, Y {plain_m(p.Y)}) lies outside the terrain "
                          f"extent ({plain_extent(extent)}), where the object has no ground "
                          "to stand on; move the point inside the extent (the path of "
                          "the object in the project file) or enlarge the terrain extent",
                          code="outside-extent",
                          value=(f"path point {i + 1} of moving object '{obj.id}'", p.X,
                                 p.Y))]
    return []


#: most plants a project may hold (memory and render time grow with the count)
MAX_PLANTS = 1_000_000


def _range_issue(obj, tag: str, attr: str, value, lo: float, hi: float, unit: str,
                 low_open: bool = False, high_open: bool = False) -> list[Issue]:
    ok = (value is not None and math.isfinite(value)
          and (lo < value if low_open else lo <= value)
          and (value < hi if high_open else value <= hi))
    if ok:
        return []
    if not (low_open or high_open):
        text = f"from {lo:g} to {hi:g}"
    else:
        low = f"greater than {lo:g}" if low_open else f"at least {lo:g}"
        text = f"{low} and " + (f"below {hi:g}" if high_open else f"at most {hi:g}")
    return [Issue(obj, tag, f"{attr} = {value!r} must be {text}{unit}", attr=attr,
                  code="within", value=value, limits=(lo, hi))]


def _vegetation(project: m.Project, veg: m.Vegetation) -> list[Issue]:
    """Problems of the scene's vegetation beyond the declared ranges (validate_declared):
    a group is a kind or a mesh, its height spread within its mean height, and the plant
    count the densities give (docs/world.md, Vegetation and wind)."""
    out: list[Issue] = []
    if not veg.plants:
        out.append(Issue(veg, "vegetation", "the vegetation has no plant group; add one, e.g. "
                         "shrubs at 0.1 per m²", code="no-plants"))
    ext = project.scene.terrain.extent
    area_m2 = max(ext.max_X - ext.min_X, 0.0) * max(ext.max_Y - ext.min_Y, 0.0)
    total = 0.0
    for g in veg.plants:
        if (g.kind is None) == (g.mesh is None):
            kinds = ", ".join(f'"{k}"' for k in m.PLANT_KINDS)
            out.append(Issue(g, "plants", "a plant group needs exactly one of kind and mesh; give "
                             f"a kind ({kinds}) or a mesh file", attr="kind",
                             code="shape-or-mesh"))
        elif g.kind is not None and g.kind not in m.PLANT_KINDS:
            out.append(Issue(g, "plants", f"unknown plant kind {g.kind!r}; use one of "
                             f"{', '.join(m.PLANT_KINDS)} or give a mesh file", attr="kind",
                             code="choice", value=g.kind, choices=tuple(m.PLANT_KINDS)))
        mean_m = g.height_m or m.PLANT_KINDS.get(g.kind, (150.0,))[0]
        if g.height_sd_m <= 150 and not element_issues(g):
            out += _range_issue(g, "plants", "height-sd-m", g.height_sd_m, 0, mean_m,
                                " m (the mean height)")
        if g.albedo_rgb is not None and (len(g.albedo_rgb) != 3 or not all(
                math.isfinite(v) and 0 <= v <= 1 for v in g.albedo_rgb)):
            out.append(Issue(g, "plants", "albedo-rgb must be three numbers from 0 to 1 "
                             "(linear red green blue), e.g. \"0.1 0.3 0.05\"",
                             attr="albedo-rgb", code="colour", value=g.albedo_rgb))
        if math.isfinite(g.density_per_m2) and g.density_per_m2 > 0:
            total += g.density_per_m2 * area_m2
    if total > MAX_PLANTS:
        out.append(Issue(veg, "vegetation", f"the densities give about {total:.3g} plants on "
                         f"the {area_m2:.3g} m² terrain, more than {MAX_PLANTS:,}; lower "
                         "density-per-m2", code="too-many-plants", value=total,
                         limits=(None, MAX_PLANTS)))
    return out  # the wind's ranges: validate_declared
