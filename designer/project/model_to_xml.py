"""Write the project model as XML, in the schema's element order.

Numbers are written with ``repr`` (the shortest text that reads back to the same
float64), so ``read(write(project)) == project``. Every value with a default is
written explicitly, so a written file documents itself.
"""

from __future__ import annotations

import dataclasses
import os

from lxml import etree

from designer.atomic import write_bytes_atomic
from designer.project import model as m
from designer.project.schema import NAMESPACE, q, schema_filename

_HEADER = """
  designer project (schema {xsd}); validate it with: designer check FILE
  World frame: X = Easting, Y = Northing, Z = up, metres. Paths are relative to this file.
  Orientation: omega, phi, kappa in degrees; R = Rx(omega) Ry(phi) Rz(kappa), camera to world.
"""


def _num(value: float | int) -> str:
    if isinstance(value, bool):
        raise TypeError("a boolean is not a number")
    if isinstance(value, int):
        return str(value)
    return repr(float(value))


def _bool(value: bool) -> str:
    return "true" if value else "false"


def _sub(parent: etree._Element, tag: str, text: str | None = None, **attrs) -> etree._Element:
    el = etree.SubElement(parent, q(tag))
    for name, value in attrs.items():
        el.set(name.replace("_", "-"), value)
    if text is not None:
        el.text = text
    return el


def write_declared(parent: etree._Element, obj, lead: dict[str, str] | None = None
                   ) -> etree._Element:
    """The element of a declared model object (designer.project.declare) under
    ``parent``: ``lead`` attributes first (fields that are not declared), then the
    declared ones in declaration order (None left out, and a default that is not to be
    written); an attribute declared on a child element goes on that child (made here,
    the first child), a text value in its own child element, in declaration order."""
    from designer.project.declare import attributes, element_of
    from designer.project.declare import holder as holder_of

    decl = element_of(type(obj))
    el = etree.SubElement(parent, q(decl.tag), lead or {})
    for group, d in sorted(attributes(type(obj)), key=lambda a: a[1].name not in decl.first):
        value = getattr(holder_of(obj, group), d.name)
        if value is None or (not d.attr.write_default and value == d.default):
            continue
        holder = el
        if d.attr.child is not None:
            holder = el.find(q(d.attr.child))
            if holder is None:
                holder = etree.SubElement(el, q(d.attr.child))
        text = (_bool(value) if d.base is bool else
                _num(value) if d.base in (int, float) else str(value))
        if d.attr.text:
            etree.SubElement(holder, q(d.xml)).text = text
        else:
            holder.set(d.xml, text)
    return el


def _scene(parent: etree._Element, scene: m.Scene) -> None:
    el = _sub(parent, "scene")
    terrain = write_declared(el, scene.terrain)  # <surroundings>, if any, goes last
    for i, part in enumerate((scene.terrain.extent, scene.terrain.source)):
        terrain.insert(i, write_declared(terrain, part))

    tex = scene.texture
    tex_el = write_declared(el, tex)  # <tiling>; the source goes first
    # an image, a generated pattern or an orthophoto
    tex_el.insert(0, write_declared(tex_el, tex.source))
    if isinstance(tex.source, m.OrthophotoTexture):  # placed by its geotransform
        tex_el.remove(tex_el.find(q("tiling")))
    elif tex.variation is not None:
        write_declared(tex_el, tex.variation)

    if scene.targets is not None:
        targets_el = _sub(el, "targets")
        if scene.targets.survey_accuracy is not None:
            write_declared(targets_el, scene.targets.survey_accuracy)
        for t in scene.targets.targets:
            t_el = write_declared(targets_el, t)
            write_declared(t_el, t.true)
            if t.surveyed is not None:
                write_declared(t_el, t.surveyed)
    if scene.objects:
        objects_el = _sub(el, "objects")
        for obj in scene.objects:
            write_declared(write_declared(objects_el, obj), obj.placement)
    if scene.moving_objects:
        moving_el = _sub(el, "moving-objects")
        for obj in scene.moving_objects:
            o_el = write_declared(moving_el, obj)  # id, shape, file; speed … on <path>
            path_el = o_el.find(q("path"))
            if obj.size_m is not None:
                for name, value in zip(m.MOVING_SIZE_XML, obj.size_m,
                                       strict=True):
                    if value is not None:
                        o_el.set(name, _num(value))
            if obj.albedo_rgb != m.MovingObject.albedo_rgb:
                o_el.set("albedo-rgb", " ".join(_num(v) for v in obj.albedo_rgb))
            for point in obj.path:
                write_declared(path_el, point)

    if scene.buildings:
        _buildings(_sub(el, "buildings"), scene.buildings)

    if scene.vegetation is not None:
        _vegetation(el, scene.vegetation)
    light = scene.lighting
    light_el = write_declared(el, light)
    write_declared(light_el, light.sun)  # a direction, a moment and place, or over time
    if light.clouds is not None:
        write_declared(light_el, light.clouds)


def _vegetation(parent: etree._Element, veg: m.Vegetation) -> None:
    el = write_declared(parent, veg)
    for g in veg.plants:
        g_el = write_declared(el, g)
        if g.albedo_rgb is not None:
            g_el.set("albedo-rgb", " ".join(_num(v) for v in g.albedo_rgb))
    if veg.wind is not None:
        write_declared(el, veg.wind)


def _camera(parent: etree._Element, cam: m.Camera) -> None:
    el = write_declared(parent, cam)
    if cam.distortion is not None:
        write_declared(el, cam.distortion)
    if cam.rolling_shutter is not None:
        write_declared(el, cam.rolling_shutter)


def _trajectory(parent: etree._Element, traj: m.Trajectory) -> None:
    el = _sub(parent, "trajectory")
    for rig in traj.rigs:
        rig_el = write_declared(el, rig)
        for mount in rig.mounts:
            write_declared(rig_el, mount)
    if traj.exterior_orientations:
        eo_el = _sub(el, "exterior-orientations")
        for eo in traj.exterior_orientations:
            # attribute order as a surveyor reads a pose: name, camera, X Y Z, ω φ κ
            write_declared(eo_el, eo)
    if traj.flight_plan is not None:
        _flight_plan(el, traj.flight_plan)
    for pattern in traj.patterns:
        _pattern(el, pattern)
    if traj.time_line is not None:
        write_declared(el, traj.time_line)


def _pattern(el: etree._Element, p: m.FlightPattern) -> None:
    if isinstance(p, m.OrbitPattern):
        write_declared(el, p)
        return
    # the facade's ends and its rows' heights: the hand-written part of <facade>
    write_declared(el, p, {"X1": _num(p.start[0]), "Y1": _num(p.start[1]),
                           "X2": _num(p.end[0]), "Y2": _num(p.end[1]),
                           "heights-m": " ".join(_num(h) for h in p.heights_m)})


def _flight_plan(el: etree._Element, fp: m.FlightPlan) -> None:
    fp_el = write_declared(el, fp)  # camera, image-prefix; the values as child elements
    area = etree.Element(q("area"))
    fp_el.insert(0, area)
    for X, Y in fp.area:
        _sub(area, "vertex", X=_num(X), Y=_num(Y))
    reference = fp.altitude_reference
    fp_el.find(q("tilt-deg")).addprevious(etree.Element(q("altitude-reference")))
    fp_el.find(q("altitude-reference")).text = (reference if isinstance(reference, str)
                                                else _num(reference))
    if fp.pose_noise is not None:
        noise = write_declared(fp_el, fp.pose_noise)
        fp_el.find(q("random-seed")).addprevious(noise)


def _effects(parent: etree._Element, fx: m.Effects) -> None:
    el = _sub(parent, "effects")
    for f in dataclasses.fields(fx):  # in the schema's order, the model's field order
        if getattr(fx, f.name) is not None:
            write_declared(el, getattr(fx, f.name))

def _processing(parent: etree._Element, p: m.Processing) -> None:
    el = write_declared(parent, p)  # <dense>
    cal = write_declared(el, p.calibration)
    if p.calibration.pre_calibration_error is not None:
        write_declared(cal, p.calibration.pre_calibration_error)
    gcps = write_declared(el, p.gcps)
    c = p.gcps.control
    if c is not None:
        write_declared(gcps, c, {"ids": " ".join(c.ids)} if c.ids else None)
    write_declared(el, p.position_prior)
    write_declared(el, p.matching)
    if p.sfm != m.Sfm():  # the default stays implicit: files of before stay the same
        write_declared(el, p.sfm)


def project_to_tree(project: m.Project) -> etree._Element:
    """The ``<project>`` element of ``project`` (schema order, defaults explicit)."""
    root = etree.Element(q("project"), nsmap={None: NAMESPACE})
    root.set("schema-version", project.schema_version)
    _sub(root, "name", project.name)
    if project.description is not None:
        _sub(root, "description", project.description)
    _sub(root, "crs", project.crs)
    write_declared(root, project.origin)
    _scene(root, project.scene)
    cameras = _sub(root, "cameras")
    for cam in project.cameras:
        _camera(cameras, cam)
    _trajectory(root, project.trajectory)
    if project.effects is not None:
        _effects(root, project.effects)
    write_declared(root, project.render)
    outputs = write_declared(root, project.outputs)
    for fmt in project.outputs.ground_truth:
        _sub(outputs, "ground-truth", format=fmt)
    if project.processing is not None:
        _processing(root, project.processing)
    return root


def project_to_bytes(project: m.Project) -> bytes:
    """UTF-8 XML text of ``project``, indented, with a comment naming frames and schema."""
    root = project_to_tree(project)
    root.addprevious(etree.Comment(_HEADER.format(xsd=schema_filename(project.schema_version))))
    etree.indent(root, space="  ")
    doc = etree.ElementTree(root)
    return etree.tostring(doc, xml_declaration=True, encoding="UTF-8", pretty_print=True)


def write_project(project: m.Project, path: str | os.PathLike) -> None:
    """Write ``project`` to ``path`` atomically (temporary file + rename). No validation."""
    write_bytes_atomic(path, project_to_bytes(project))


def _buildings(parent: etree._Element, buildings: tuple[m.Building, ...]) -> None:
    for b in buildings:
        b_el = _sub(parent, "building", id=b.id)
        if b.file is not None:
            b_el.set("file", b.file)
            if b.position is not None:
                b_el.set("X", _num(b.position.X))
                b_el.set("Y", _num(b.position.Y))
            b_el.set("heading-deg", _num(b.heading_deg))
        else:
            b_el.set("roof", b.roof)
            b_el.set("eave-height-m", _num(b.eave_height_m))
            if b.ridge_height_m is not None:
                b_el.set("ridge-height-m", _num(b.ridge_height_m))
            if b.ridge_direction_deg is not None:
                b_el.set("ridge-direction-deg", _num(b.ridge_direction_deg))
        if b.footprint:
            _sub(b_el, "footprint", " ".join(f"{_num(p.X)} {_num(p.Y)}" for p in b.footprint))
