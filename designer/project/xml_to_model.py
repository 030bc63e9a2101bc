"""Build the project model from a schema-valid XML tree, noting where each part came from.

Only called on a tree that passed the XSD, so required elements and attributes exist
and numbers parse; the semantic checks come afterwards (``validate.py``).
"""

from __future__ import annotations

import dataclasses

from lxml import etree

from designer.project import declare
from designer.project import model as m
from designer.project.declare import element_of
from designer.project.problems import SourceMap
from designer.project.schema import q


def _f(el: etree._Element, name: str) -> float:
    return float(el.get(name))


def _opt_f(el: etree._Element, name: str) -> float | None:
    value = el.get(name)
    return None if value is None else float(value)


def _numbers(text: str) -> tuple[float, ...]:
    """Space-separated numbers; NaN for each word that is not one (validation names it)."""
    out = []
    for word in text.split():
        try:
            out.append(float(word))
        except ValueError:
            out.append(float("nan"))
    return tuple(out)


def _text(el: etree._Element | None) -> str | None:
    return None if el is None else (el.text or "").strip()


def _bool(text: str) -> bool:
    return text.strip() in ("true", "1")


def read_declared(cls, el: etree._Element, **given):
    """An instance of the declared element class ``cls`` from the attributes of ``el``
    (designer.project.declare) and the texts of its declared text children: absent ones
    take their defaults; ``given`` supplies the fields that are not declared (children)."""
    from designer.project.declare import declared, groups

    values = dict(given)
    for name, group_cls in groups(cls):  # an attribute group's attributes sit on ``el``
        if name not in values:
            values[name] = read_declared(group_cls, el)
    for d in declared(cls):
        holder = el if d.attr.child is None else el.find(q(d.attr.child))
        if holder is None:
            raw = None
        elif d.attr.text:
            raw = _text(holder.find(q(d.xml)))
        else:
            raw = holder.get(d.xml)
        if d.name in values:
            continue
        if raw is None:
            if d.attr.has_absent:
                values[d.name] = d.attr.absent
            continue
        if d.base is bool:
            values[d.name] = _bool(raw)
        elif d.base is int:
            values[d.name] = int(raw)
        elif d.base is float:
            values[d.name] = float(raw)
        else:
            values[d.name] = raw.strip()
    return cls(**values)


class _Reader:
    def __init__(self, smap: SourceMap) -> None:
        self.smap = smap

    def note(self, obj, el: etree._Element, key: str | None = None):
        self.smap.add(obj, key or etree.QName(el).localname, el.sourceline)
        return obj

    def child_lines(self, obj, parent: etree._Element) -> None:
        """Register the lines of the text-only children of ``parent`` under ``obj``."""
        for child in parent.iterchildren(tag=etree.Element):
            self.smap.add(obj, etree.QName(child).localname, child.sourceline)

    # ----------------------------------------------------------------- project
    def project(self, root: etree._Element) -> m.Project:
        origin_el = root.find(q("origin"))
        origin = self.note(read_declared(m.Origin, origin_el), origin_el)
        effects_el = root.find(q("effects"))
        processing_el = root.find(q("processing"))
        project = m.Project(
            name=_text(root.find(q("name"))),
            description=_text(root.find(q("description"))),
            crs=_text(root.find(q("crs"))),
            origin=origin,
            scene=self.scene(root.find(q("scene"))),
            cameras=tuple(self.camera(el) for el in root.find(q("cameras"))
                          .iterchildren(q("camera"))),
            trajectory=self.trajectory(root.find(q("trajectory"))),
            effects=None if effects_el is None else self.effects(effects_el),
            render=self.render(root.find(q("render"))),
            outputs=self.outputs(root.find(q("outputs"))),
            processing=None if processing_el is None else self.processing(processing_el),
            schema_version=root.get("schema-version"),
        )
        self.note(project, root)
        self.child_lines(project, root)
        return project

    # ----------------------------------------------------------------- scene
    def scene(self, el: etree._Element) -> m.Scene:
        targets_el = el.find(q("targets"))
        objects_el = el.find(q("objects"))
        moving_el = el.find(q("moving-objects"))
        buildings_el = el.find(q("buildings"))
        vegetation_el = el.find(q("vegetation"))
        scene = m.Scene(
            terrain=self.terrain(el.find(q("terrain"))),
            texture=self.texture(el.find(q("texture"))),
            lighting=self.lighting(el.find(q("lighting"))),
            targets=None if targets_el is None else self.targets(targets_el),
            objects=() if objects_el is None else tuple(
                self.scene_object(o) for o in objects_el.iterchildren(q("object"))),
            moving_objects=() if moving_el is None else tuple(
                self.moving_object(o) for o in moving_el.iterchildren(q("object"))),
            buildings=() if buildings_el is None else tuple(
                self.building(b) for b in buildings_el.iterchildren(q("building"))),
            vegetation=None if vegetation_el is None else self.vegetation(vegetation_el),
        )
        return self.note(scene, el)

    def terrain(self, el: etree._Element) -> m.Terrain:
        ext_el = el.find(q("extent"))
        extent = self.note(read_declared(m.Extent, ext_el), ext_el)
        src_el = ext_el.getnext()
        while not isinstance(src_el.tag, str):
            src_el = src_el.getnext()
        kind = etree.QName(src_el).localname
        if kind == "flat":
            source = read_declared(m.FlatTerrain, src_el)
        elif kind == "procedural":
            source = read_declared(m.ProceduralTerrain, src_el)
        else:
            source = read_declared(m.DemTerrain if kind == "dem" else m.MeshTerrain, src_el)
        self.note(source, src_el)
        return self.declared(m.Terrain, el, extent=extent, source=source)

    def texture(self, el: etree._Element) -> m.Texture:
        image_el = el.find(q("image"))
        ortho_el = el.find(q("orthophoto"))
        if ortho_el is not None:  # placed by its geotransform: no tiling
            source = self.note(read_declared(m.OrthophotoTexture, ortho_el), ortho_el)
            return self.declared(m.Texture, el, source=source, repeat_X=1, repeat_Y=1)
        if image_el is not None:
            source = self.note(read_declared(m.ImageTexture, image_el), image_el)
        else:
            p = el.find(q("procedural"))
            source = self.note(read_declared(m.ProceduralTexture, p), p)
        var_el = el.find(q("variation"))
        variation = None
        if var_el is not None:
            variation = self.note(read_declared(m.TextureVariation, var_el), var_el)
        return self.declared(m.Texture, el, source=source, variation=variation)

    def targets(self, el: etree._Element) -> m.Targets:
        acc_el = el.find(q(element_of(m.SurveyAccuracy).tag))
        accuracy = None if acc_el is None else self.declared(m.SurveyAccuracy, acc_el)
        targets = tuple(self.target(t) for t in el.iterchildren(q(element_of(m.Target).tag)))
        return self.note(m.Targets(targets, accuracy), el)

    def declared(self, cls, el: etree._Element, **given):
        """:func:`read_declared`, noted at ``el`` together with its attribute groups."""
        from designer.project.declare import declared, groups

        obj = self.note(read_declared(cls, el, **given), el)
        for name, _ in groups(cls):
            self.note(getattr(obj, name), el)
        for child in {d.attr.child for d in declared(cls)} - {None}:
            if (child_el := el.find(q(child))) is not None:
                self.note(obj, child_el)
        return obj

    def target(self, el: etree._Element) -> m.Target:
        true_el = el.find(q("true"))
        true = self.note(read_declared(m.TruePosition, true_el), true_el)
        s_el = el.find(q(element_of(m.SurveyedPosition).tag))
        surveyed = None if s_el is None else self.declared(m.SurveyedPosition, s_el)
        target = read_declared(m.Target, el, true=true, surveyed=surveyed)
        return self.note(target, el)

    def moving_object(self, el: etree._Element) -> m.MovingObject:
        path_el = el.find(q("path"))
        points = tuple(self.declared(m.PathPoint, p)
                       for p in path_el.iterchildren(q(element_of(m.PathPoint).tag)))
        size = tuple(_opt_f(el, k) for k in m.MOVING_SIZE_XML)
        albedo = el.get("albedo-rgb")
        obj = read_declared(
            m.MovingObject, el, path=points,
            size_m=None if all(v is None for v in size) else size,
            albedo_rgb=m.MovingObject.albedo_rgb if albedo is None else _numbers(albedo))
        self.note(obj, path_el, "path")
        return self.note(obj, el)

    def building(self, el: etree._Element) -> m.Building:
        fp_el = el.find(q("footprint"))
        footprint = ()
        if fp_el is not None:
            xy = _numbers(_text(fp_el))
            xy += (float("nan"),) * (len(xy) % 2)  # an odd count: a NaN Y validation names
            footprint = tuple(m.PathPoint(x, y) for x, y in zip(xy[::2], xy[1::2], strict=True))
        X, Y = _opt_f(el, "X"), _opt_f(el, "Y")
        building = read_declared(
            m.Building, el, footprint=footprint,
            position=None if X is None and Y is None else m.PathPoint(
                float("nan") if X is None else X, float("nan") if Y is None else Y))
        if fp_el is not None:
            self.note(building, fp_el, "footprint")
        return self.note(building, el)

    def vegetation(self, el: etree._Element) -> m.Vegetation:
        groups = []
        for g in el.iterchildren(q("plants")):
            albedo = g.get("albedo-rgb")
            groups.append(self.note(read_declared(
                m.PlantGroup, g,
                albedo_rgb=None if albedo is None else _numbers(albedo)), g))
        wind_el = el.find(q("wind"))
        wind = None
        if wind_el is not None:
            wind = self.note(read_declared(m.Wind, wind_el), wind_el)
        veg = read_declared(m.Vegetation, el, plants=tuple(groups), wind=wind)
        return self.note(veg, el)

    def scene_object(self, el: etree._Element) -> m.SceneObject:
        placement = self.declared(m.Placement, el.find(q(element_of(m.Placement).tag)))
        return self.note(read_declared(m.SceneObject, el, placement=placement), el)

    def lighting(self, el: etree._Element) -> m.Lighting:
        sun_el, kind = next((c, k) for k in (m.Sun, m.SunPosition, m.SunOverTime)
                            if (c := el.find(q(element_of(k).tag))) is not None)
        sun = read_declared(kind, sun_el)
        self.note(sun, sun_el)
        clouds = None
        c = el.find(q("cloud-shadows"))
        if c is not None:
            clouds = self.note(read_declared(m.CloudShadows, c), c)
        lighting = read_declared(m.Lighting, el, sun=sun, clouds=clouds)
        return self.note(lighting, el)

    # ----------------------------------------------------------------- cameras
    def camera(self, el: etree._Element) -> m.Camera:
        distortion = None
        bc = el.find(q("brown-conrady"))
        fe = el.find(q("fisheye-equidistant"))
        if bc is not None:
            distortion = self.note(read_declared(m.BrownConradyDistortion, bc), bc)
        elif fe is not None:
            distortion = self.note(read_declared(m.FisheyeEquidistantDistortion, fe), fe)
        camera = self.declared(
            m.Camera, el, distortion=distortion,
            rolling_shutter=self.rolling_shutter(el.find(q("rolling-shutter"))))
        self.child_lines(camera, el)
        return camera

    def rolling_shutter(self, el: etree._Element | None) -> m.RollingShutter | None:
        if el is None:
            return None
        return self.note(read_declared(m.RollingShutter, el), el)

    # ----------------------------------------------------------------- trajectory
    def trajectory(self, el: etree._Element) -> m.Trajectory:
        eo_el = el.find(q("exterior-orientations"))
        photos: tuple[m.ExteriorOrientation, ...] = ()
        if eo_el is not None:
            photos = tuple(self.photo(p) for p in eo_el.iterchildren(q("photo")))
        fp_el = el.find(q("flight-plan"))
        plan = None if fp_el is None else self.flight_plan(fp_el)
        tl_el = el.find(q("time-line"))
        time_line = None
        if tl_el is not None:
            time_line = self.note(read_declared(m.TimeLine, tl_el), tl_el)
        rigs = tuple(self.rig(r) for r in el.iterchildren(q("rig")))
        patterns = tuple(self.pattern(p) for p in el.iterchildren(q("orbit"), q("facade")))
        trajectory = self.note(m.Trajectory(photos, plan, time_line, rigs, patterns), el)
        if eo_el is not None:
            self.note(trajectory, eo_el)
        return trajectory

    def rig(self, el: etree._Element) -> m.Rig:
        mounts = []
        for mount_el in el.iterchildren(q("mount")):
            mount = read_declared(m.Mount, mount_el)
            self.smap.add(mount, "mount", mount_el.sourceline)
            mounts.append(mount)
        return self.note(read_declared(m.Rig, el, mounts=tuple(mounts)), el)

    def pattern(self, el: etree._Element) -> m.FlightPattern:
        if etree.QName(el).localname == element_of(m.OrbitPattern).tag:
            return self.declared(m.OrbitPattern, el)
        # the facade's ends and its rows' heights: the hand-written part of <facade>
        return self.declared(m.FacadePattern, el, start=(_f(el, "X1"), _f(el, "Y1")),
                             end=(_f(el, "X2"), _f(el, "Y2")),
                             heights_m=_numbers(el.get("heights-m")))

    def photo(self, el: etree._Element) -> m.ExteriorOrientation:
        return self.declared(m.ExteriorOrientation, el)

    def flight_plan(self, el: etree._Element) -> m.FlightPlan:
        area_el = el.find(q("area"))
        vertices = []
        plan_key_lines = []
        for i, v in enumerate(area_el.iterchildren(q("vertex"))):
            vertices.append((_f(v, "X"), _f(v, "Y")))
            plan_key_lines.append((f"vertex:{i}", v.sourceline))
        noise_el = el.find(q("pose-noise"))
        noise = None
        if noise_el is not None:
            noise = self.note(read_declared(m.PoseNoise, noise_el), noise_el)
        reference = _text(el.find(q("altitude-reference")))
        if reference is not None and reference not in ("mean", "max", "min"):
            reference = float(reference)
        plan = read_declared(m.FlightPlan, el, area=tuple(vertices), pose_noise=noise,
                             altitude_reference="mean" if reference is None else reference)
        self.note(plan, el)
        self.child_lines(plan, el)
        for key, line in plan_key_lines:
            self.smap.add(plan, key, line)
        return plan

    # ----------------------------------------------------------------- effects, render
    def effects(self, el: etree._Element) -> m.Effects:
        def one(tag, build):
            child = el.find(q(tag))
            return None if child is None else self.note(build(child), child)

        effects = m.Effects(**{
            f.name: one(element_of(declare.field_class(m.Effects, f.name)).tag,
                        lambda c, f=f: read_declared(declare.field_class(m.Effects, f.name), c))
            for f in dataclasses.fields(m.Effects)})
        return self.note(effects, el)

    def render(self, el: etree._Element) -> m.Render:
        render = read_declared(m.Render, el)
        self.note(render, el)
        self.child_lines(render, el)
        return render

    def outputs(self, el: etree._Element) -> m.Outputs:
        formats = tuple(g.get("format") for g in el.iterchildren(q("ground-truth")))
        outputs = self.note(read_declared(m.Outputs, el, ground_truth=formats), el)
        for i, g in enumerate(el.iterchildren(q("ground-truth"))):
            self.smap.add(outputs, f"ground-truth:{i}", g.sourceline)
        return outputs

    def processing(self, el: etree._Element) -> m.Processing:
        """``<processing>``; absent children and attributes take the model's defaults."""
        def part(tag: str, cls, **given):
            child = el.find(q(tag))
            return cls(**given) if child is None else self.note(
                read_declared(cls, child, **given), child)

        cal_el = el.find(q("calibration"))
        pre = None
        if cal_el is not None and cal_el.find(q("pre-calibration-error")) is not None:
            pre_el = cal_el.find(q("pre-calibration-error"))
            pre = self.note(read_declared(m.PreCalibrationError, pre_el), pre_el)
        calibration = part("calibration", m.Calibration, pre_calibration_error=pre)
        gcps_el = el.find(q("gcps"))
        control = None
        if gcps_el is not None and gcps_el.find(q("control")) is not None:
            control_el = gcps_el.find(q("control"))
            control = self.note(read_declared(
                m.ControlSelection, control_el,
                ids=tuple((control_el.get("ids") or "").split())), control_el)
        gcps = part("gcps", m.GcpProcessing, control=control)
        prior = part("position-prior", m.PositionPrior)
        matching = part("matching", m.Matching)
        sfm = part("sfm", m.Sfm)
        return self.declared(m.Processing, el, calibration=calibration, gcps=gcps,
                             position_prior=prior, matching=matching, sfm=sfm)


def project_from_tree(root: etree._Element, smap: SourceMap) -> m.Project:
    """The model of a schema-valid ``<project>`` element; fills ``smap`` with lines."""
    project = _Reader(smap).project(root)
    smap.keep_alive = project
    return project
