"""Semantic checks of the scene: terrain, texture, GCP targets, objects, lighting."""

from __future__ import annotations

import math
from collections import Counter
from datetime import datetime
from pathlib import Path

from designer.project import model as m
from designer.project.files import (
    ascii_grid_extent,
    ascii_grid_header,
    dem_problem,
    image_problem,
    mesh_problem,
    orthophoto_problem,
    resolve,
)
from designer.project.problems import Issue
from designer.project.scene_limits import (
    GRID_TOL,
    MAX_TERRAIN_NODES,
    MAX_TEXTURE_TEXELS,
    MIN_TEXTURE_TEXELS,
)
from designer.project.validate_buildings import building_issues
from designer.project.validate_declared import element_issues
from designer.project.validate_shared import (
    file_issue,
    finite_issues,
    is_ok,
    plain_extent,
    plain_m,
)


def scene_issues(scene: m.Scene, base: Path | None) -> list[Issue]:
    """Problems of the scene; referenced files are checked when ``base`` is given."""
    return (_terrain(scene.terrain, base)
            + _texture(scene.texture, scene.terrain.extent, base)
            + _targets(scene.targets, scene.terrain.extent)
            + _objects(scene.objects, base)
            + [i for obj in scene.moving_objects if base is not None and obj.file is not None
               for i in file_issue(obj, "object", mesh_problem(resolve(base, obj.file)))]
            + building_issues(scene, base)
            + [i for g in (scene.vegetation.plants if scene.vegetation else ())
               if base is not None and g.mesh is not None
               for i in file_issue(g, "plants", mesh_problem(resolve(base, g.mesh)))]
            + _lighting(scene.lighting))


def _terrain(terrain: m.Terrain, base: Path | None) -> list[Issue]:
    out = []
    e, src = terrain.extent, terrain.source
    if is_ok(e.min_X) and is_ok(e.max_X) and not e.min_X < e.max_X:
        out.append(Issue(e, "extent", f"min-X {e.min_X!r} must be less than max-X "
                                      f"{e.max_X!r}; swap or correct them", attr="min-X",
                         code="order", value=(e.min_X, e.max_X)))
    if is_ok(e.min_Y) and is_ok(e.max_Y) and not e.min_Y < e.max_Y:
        out.append(Issue(e, "extent", f"min-Y {e.min_Y!r} must be less than max-Y "
                                      f"{e.max_Y!r}; swap or correct them", attr="min-Y",
                         code="order", value=(e.min_Y, e.max_Y)))
    if terrain.surroundings == "auto" and isinstance(src, m.MeshTerrain):
        out.append(Issue(terrain, "surroundings", "surroundings mode auto continues a "
                         "height-field terrain (flat, procedural or DEM); a mesh terrain "
                         "cannot be continued: choose mode none or a DEM", attr="mode",
                         code="surroundings-need-height-field", value=terrain.surroundings))
    if isinstance(src, m.ProceduralTerrain):
        if src.min_height_m > src.max_height_m:
            out.append(Issue(src, "procedural", f"min-height-m {src.min_height_m!r} is above "
                             f"max-height-m {src.max_height_m!r}; swap them",
                             attr="min-height-m", code="order",
                             value=(src.min_height_m, src.max_height_m)))
        out += _grid(src, e)
    elif isinstance(src, m.DemTerrain) and base is not None:
        path = resolve(base, src.file)
        problem = dem_problem(path)
        out += file_issue(src, "dem", problem)
        if problem is None and path.suffix.lower() == ".asc":
            with path.open("rb") as f:
                header = ascii_grid_header(f.read(4096))
            x0, y0, x1, y1 = ascii_grid_extent(header)
            if not (x0 <= e.min_X and y0 <= e.min_Y and x1 >= e.max_X and y1 >= e.max_Y):
                out.append(Issue(src, "dem", f"the DEM covers X {plain_m(x0)}..{plain_m(x1)}, Y "
                                 f"{plain_m(y0)}..{plain_m(y1)}"
                                 f", not the whole terrain extent; shrink the extent or use a "
                                 "larger DEM", attr="file", code="dem-coverage",
                                 value=(x0, x1, y0, y1)))
    elif isinstance(src, m.MeshTerrain) and base is not None:
        out += file_issue(src, "mesh", mesh_problem(resolve(base, src.file)))
    return out


def _grid(src: m.ProceduralTerrain, e: m.Extent) -> list[Issue]:
    """The extent must be a whole number of grid cells, and not too many of them."""
    spacing = src.grid_spacing_m
    if not (is_ok(spacing) and spacing > 0):
        return [Issue(src, "procedural", "the grid spacing must be greater than 0 m",
                      attr="grid-spacing-m")]
    if not (e.width_m > 0 and e.length_m > 0):
        return []  # reported with the extent
    out = []
    cells = (e.width_m / spacing) * (e.length_m / spacing)
    if not math.isfinite(cells) or cells > MAX_TERRAIN_NODES:
        return [Issue(src, "procedural", f"a {spacing:g} m grid over {plain_m(e.width_m)} x "
                      f"{plain_m(e.length_m)} m has more than {MAX_TERRAIN_NODES:.3g} nodes; use a "
                      "coarser grid-spacing-m or a smaller extent", attr="grid-spacing-m",
                      code="grid-nodes", value=(spacing, e.width_m, e.length_m),
                      limits=(None, MAX_TERRAIN_NODES))]
    for name, size in (("width", e.width_m), ("length", e.length_m)):
        n = round(size / spacing)
        if n < 1 or abs(n * spacing - size) > GRID_TOL * size:
            out.append(Issue(src, "procedural", f"the extent's {name} {plain_m(size)} m is "
                             f"not a whole number of {spacing:g} m grid cells; choose a "
                             "grid-spacing-m that divides the extent", attr="grid-spacing-m",
                             code="grid-cells", value=(name, size, spacing)))
    nodes = (e.width_m / spacing + 1) * (e.length_m / spacing + 1)
    if not out and nodes > MAX_TERRAIN_NODES:
        out.append(Issue(src, "procedural", f"a {spacing:g} m grid over {plain_m(e.width_m)} x "
                         f"{plain_m(e.length_m)} m has {nodes:.3g} nodes, more than "
                         f"{MAX_TERRAIN_NODES:.3g}; use a coarser grid-spacing-m",
                         attr="grid-spacing-m", code="grid-nodes",
                         value=(spacing, e.width_m, e.length_m),
                         limits=(None, MAX_TERRAIN_NODES)))
    return out


def _texture(tex: m.Texture, extent: m.Extent, base: Path | None) -> list[Issue]:
    out = []  # the repeats' ranges and the interpolation: validate_declared
    src = tex.source
    if isinstance(src, m.OrthophotoTexture):
        if tex.variation is not None:
            out.append(Issue(tex.variation, "variation", "an orthophoto does not repeat: the "
                             "variation applies to tiled textures only; remove the variation",
                             code="variation-on-orthophoto"))
        if base is not None:
            out += file_issue(src, "orthophoto", orthophoto_problem(resolve(base, src.file)))
    elif isinstance(src, m.ImageTexture):
        if base is not None:
            out += file_issue(src, "image", image_problem(resolve(base, src.file)))
    elif (not element_issues(tex) and src.texel_size_m > 0 and extent.width_m > 0
          and extent.length_m > 0):
        # (a texel size of 0 or less: the declared range, validate_declared)
        tile = max(extent.width_m / tex.repeat_X, extent.length_m / tex.repeat_Y)
        texels = tile / src.texel_size_m
        if texels > MAX_TEXTURE_TEXELS:
            out.append(Issue(src, "procedural", f"a {plain_m(tile)} m tile of "
                             f"{src.texel_size_m:g} m texels needs {texels:.0f} texels per side, "
                             f"more than {MAX_TEXTURE_TEXELS}; increase texel-size-m or repeat-X/Y",
                             attr="texel-size-m", code="texels",
                             value=(tile, src.texel_size_m, texels),
                             limits=(MIN_TEXTURE_TEXELS, MAX_TEXTURE_TEXELS)))
        elif texels < MIN_TEXTURE_TEXELS:
            out.append(Issue(src, "procedural", f"a {plain_m(tile)} m tile of "
                             f"{src.texel_size_m:g} m texels has only {texels:.3g} texels per "
                             f"side, fewer than {MIN_TEXTURE_TEXELS}; make texel-size-m smaller",
                             attr="texel-size-m", code="texels",
                             value=(tile, src.texel_size_m, texels),
                             limits=(MIN_TEXTURE_TEXELS, MAX_TEXTURE_TEXELS)))
    return out


def _targets(targets: m.Targets | None, extent: m.Extent) -> list[Issue]:
    if targets is None:
        return []
    out = []  # the survey's and the surveyed positions' ranges: validate_declared
    counts = Counter(t.id for t in targets.targets)
    reported = set()
    for t in targets.targets:
        out += finite_issues(t, t.true)
        if counts[t.id] > 1 and t.id not in reported:
            reported.add(t.id)
            out.append(Issue(t, "target", f"GCP id '{t.id}' is used by {counts[t.id]} targets; "
                                          "give each target its own id", attr="id"))
        # role, shape and size: their declared ranges (validate_declared)
        if is_ok(t.true.X) and is_ok(t.true.Y) and not extent.contains(t.true.X, t.true.Y):
            out.append(Issue(t.true, "true", f"GCP '{t.id}' at X {plain_m(t.true.X)}, Y "
                             f"{plain_m(t.true.Y)} lies outside the terrain extent "
                             f"({plain_extent(extent)}); move it "
                             "inside or enlarge the extent",
                             attr="X", code="outside-extent",
                             value=(f"GCP '{t.id}'", t.true.X, t.true.Y)))
        if t.surveyed is None:
            if targets.survey_accuracy is None:
                out.append(Issue(t, "target", f"GCP '{t.id}' has no surveyed position and "
                                 "the targets have no survey accuracy to simulate one; add "
                                 "either", code="no-survey"))
    return out


def _objects(objects: tuple[m.SceneObject, ...], base: Path | None) -> list[Issue]:
    out = []
    counts = Counter(o.name for o in objects)
    for i, obj in enumerate(objects):
        if counts[obj.name] > 1 and [o.name for o in objects].index(obj.name) == i:
            out.append(Issue(obj, "object", f"object name '{obj.name}' is used "
                             f"{counts[obj.name]} times; give each object its own name",
                             attr="name"))
        if base is not None:
            out += file_issue(obj, "object", mesh_problem(resolve(base, obj.file)))
    return out


def _lighting(light: m.Lighting) -> list[Issue]:
    out = []  # the strengths' ranges: validate_declared
    sun = light.sun  # the angles' ranges: validate_declared
    if isinstance(sun, m.Sun | m.SunOverTime):  # over time: with the time line (validate_world)
        return out
    try:
        moment = datetime.fromisoformat(sun.date_time)
    except ValueError:
        moment = None
        out.append(Issue(sun, "sun-position", f"the sun's date and time '{sun.date_time}' "
                         "is not an ISO 8601 date and time; write e.g. "
                         "2024-06-21T10:30:00+02:00",
                         attr="date-time"))
    if moment is not None and moment.tzinfo is None:
        out.append(Issue(sun, "sun-position", f"the sun's date and time '{sun.date_time}' "
                         "has no time zone; add one, e.g. +02:00 or Z for UTC",
                         attr="date-time"))
    elif moment is not None and -90 <= sun.latitude_deg <= 90 and \
            -180 <= sun.longitude_deg <= 180:  # ranges: validate_declared
        out += _sun_below_horizon(sun, moment)
    return out


def _sun_below_horizon(sun: m.SunPosition, moment: datetime) -> list[Issue]:
    """A sun at or below the horizon lights nothing directly: the light map would be sky
    only, shadowless, silently unlike the day the file names (docs/hard-cases.md)."""
    from astral import Observer
    from astral.sun import elevation

    observer = Observer(latitude=sun.latitude_deg, longitude=sun.longitude_deg)
    height_deg = float(elevation(observer, moment))
    if height_deg > 0:
        return []
    return [Issue(sun, "sun-position", f"the sun is {abs(height_deg):.1f}° below the horizon at "
                  f"{sun.date_time} ({sun.latitude_deg}°, {sun.longitude_deg}°); give a "
                  "moment in daylight, or give the sun by its direction (elevation above 0)",
                  attr="date-time", code="sun-below-horizon", value=height_deg)]
