"""Pure edits of the immutable project model, one function per thing a person does.

Each function takes a :class:`~designer.project.model.Project` and returns a new one
(the input is never modified); the GUI pushes the result onto its undo stack. World
coordinates in metres (X east, Y north, Z up), angles in degrees, as in the model.
"""

from __future__ import annotations

import dataclasses
import re
from typing import Any

import numpy as np

from designer.core.rig import PENTA_MOUNTS
from designer.project import model as m

_INDEX = re.compile(r"^(\w+)\[(\d+)\]$")
#: an id the project file accepts (the schema's Identifier): cameras, GCPs, rigs
IDENTIFIER = re.compile(r"[A-Za-z0-9][A-Za-z0-9_.+\-]{0,127}")


def identifier_problem(value: str) -> str:
    """Why ``value`` is no id the project file accepts ("" when it is one)."""
    if not value:
        return "an id is required"
    if not IDENTIFIER.fullmatch(value):
        return (f"“{value}” is not an id: letters, digits, '_', '.', '-' and '+', "
                "starting with a letter or digit, at most 128 characters")
    return ""


class AbsentElement(LookupError):
    """A model path leads through an element the project does not have: an optional
    element that is None (``effects`` off), an index past the end of a list, or a union
    whose variant lacks the field (a DEM terrain has no ``seed``). ``parent`` is the
    object the ``segment`` was looked up on (None for an absent element)."""

    def __init__(self, path: str, segment: str, parent: Any) -> None:
        self.path, self.segment, self.parent = path, segment, parent
        where = "absent" if parent is None else f"a {type(parent).__name__}"
        super().__init__(f"{path}: {segment} is not there ({where})")


class UnknownField(ValueError):
    """A model path names a field that no dataclass of the project model has."""


def _model_field_names() -> frozenset[str]:
    from designer.project import processing

    names = set()
    for module in (m, processing):
        for value in vars(module).values():
            if dataclasses.is_dataclass(value) and isinstance(value, type):
                names.update(f.name for f in dataclasses.fields(value))
    return frozenset(names)


#: every field name of every dataclass of designer.project.model (and .processing)
MODEL_FIELDS = _model_field_names()


def _segments(path: str) -> list[tuple[str, int | None]]:
    out = []
    for head in path.split("."):
        match = _INDEX.match(head)
        out.append((match.group(1), int(match.group(2))) if match else (head, None))
    return out


def check_path(path: str) -> str:
    """``path`` itself when every segment names a field of some model dataclass; else
    :class:`UnknownField` naming the path and the first bad segment."""
    for name, _index in _segments(path):
        if name not in MODEL_FIELDS:
            raise UnknownField(f"model path {path!r}: no element of the project model is "
                               f"called {name!r}; check the spelling")
    return path


def _child(obj: Any, name: str, index: int | None, path: str) -> Any:
    """``obj.name`` (``[index]``), or :class:`AbsentElement` where the model lacks it."""
    if obj is None or not hasattr(obj, name):
        if obj is not None and name not in MODEL_FIELDS:
            raise UnknownField(f"model path {path!r}: {type(obj).__name__} has no {name!r}")
        raise AbsentElement(path, name, obj)
    value = getattr(obj, name)
    if index is None:
        return value
    if value is None or not 0 <= index < len(value):
        raise AbsentElement(path, f"{name}[{index}]", value)
    return value[index]


def replace_path(obj: Any, path: str, value: Any, _full: str | None = None) -> Any:
    """``obj`` with the field at a dotted ``path`` (``"scene.terrain.source.seed"``,
    ``"cameras[0].focal_length_mm"``) set to ``value``; every level is copied.
    :class:`AbsentElement` when the path leads through an element that is not there."""
    full = _full or path
    head, _, rest = path.partition(".")
    (name, index), = _segments(head)
    current = _child(obj, name, None, full)
    if index is None:
        new = replace_path(current, rest, value, full) if rest else value
    else:
        item = _child(obj, name, index, full)
        items = list(current)
        items[index] = replace_path(item, rest, value, full) if rest else value
        new = tuple(items)
    return dataclasses.replace(obj, **{name: new})


def get_path(obj: Any, path: str) -> Any:
    """The value at a dotted ``path`` (see :func:`replace_path`); :class:`AbsentElement`
    when the path leads through an element that is not there."""
    for name, index in _segments(path):
        obj = _child(obj, name, index, path)
    return obj


# ---------------------------------------------------------------------- targets
def _targets(project: m.Project) -> m.Targets:
    return project.scene.targets or m.Targets()


#: survey σ given to new targets when the project has none: RTK GNSS, 1 cm / 2 cm
DEFAULT_SURVEY_ACCURACY = m.SurveyAccuracy(m.Sigma3(0.01, 0.01, 0.02), seed=0)


def set_targets(project: m.Project, targets: tuple[m.Target, ...],
                survey_accuracy: m.SurveyAccuracy | str | None = "keep") -> m.Project:
    """The project with this target list and survey accuracy: ``"keep"`` keeps it, or
    gives the default σ when a target without a measured position would have none."""
    current = _targets(project)
    accuracy = current.survey_accuracy if survey_accuracy == "keep" else survey_accuracy
    if (survey_accuracy == "keep" and accuracy is None
            and any(t.surveyed is None for t in targets)):
        accuracy = DEFAULT_SURVEY_ACCURACY
    new = m.Targets(tuple(targets), accuracy)
    if not new.targets and new.survey_accuracy is None:
        return replace_path(project, "scene.targets", None)
    return replace_path(project, "scene.targets", new)


def next_target_id(project: m.Project, prefix: str = "GCP") -> str:
    """The first free id ``GCP01``, ``GCP02``, …"""
    used = {t.id for t in project.targets}
    k = 1
    while f"{prefix}{k:02d}" in used:
        k += 1
    return f"{prefix}{k:02d}"


def default_target_size_m(project: m.Project) -> float:
    """The size of the last target, or 1 % of the terrain's shorter side (0.2–2 m)."""
    if project.targets:
        return project.targets[-1].size_m
    e = project.scene.terrain.extent
    return float(np.clip(0.01 * min(e.width_m, e.length_m), 0.2, 2.0))


#: decimals of coordinates placed or typed in the window (0.1 mm)
COORDINATE_DECIMALS = 4


def _coordinate(value: float) -> float:
    return round(float(value), COORDINATE_DECIMALS)


def add_target(project: m.Project, X: float, Y: float, role: m.Role = "control",
               target_id: str | None = None, size_m: float | None = None) -> m.Project:
    """A new checker target draped on the terrain at (X, Y)."""
    target = m.Target(
        id=target_id or next_target_id(project), role=role, shape="checker",
        size_m=size_m if size_m is not None else default_target_size_m(project),
        true=m.TruePosition(_coordinate(X), _coordinate(Y)))
    return set_targets(project, (*project.targets, target))


def rename_target_references(project: m.Project, old_id: str, new_id: str) -> m.Project:
    """The project with the processing's control selection naming ``new_id`` where it
    named ``old_id`` (the target itself is renamed by the caller)."""
    control = project.processing.gcps.control if project.processing is not None else None
    if control is None or old_id not in control.ids:
        return project
    ids = tuple(new_id if i == old_id else i for i in control.ids)
    return replace_path(project, "processing.gcps.control.ids", ids)


def move_target(project: m.Project, target_id: str, X: float, Y: float) -> m.Project:
    """Move a target's true position to (X, Y), keeping a given Z only if it had one."""
    out = []
    for t in project.targets:
        if t.id == target_id:
            t = dataclasses.replace(t, true=dataclasses.replace(t.true, X=_coordinate(X),
                                                                Y=_coordinate(Y)))
        out.append(t)
    return set_targets(project, tuple(out))


def delete_targets(project: m.Project, target_ids) -> m.Project:
    """The project without the targets ``target_ids``, and without their ids in the
    processing's control selection."""
    gone = set(target_ids)
    return _drop_control_ids(
        set_targets(project, tuple(t for t in project.targets if t.id not in gone)))


def _drop_control_ids(project: m.Project) -> m.Project:
    """The project without the control selection's ids that name no target."""
    control = project.processing.gcps.control if project.processing is not None else None
    known = {t.id for t in project.targets}
    if control is None or set(control.ids) <= known:
        return project
    return replace_path(project, "processing.gcps.control.ids",
                        tuple(i for i in control.ids if i in known))


def deletion_problem(project: m.Project, target_ids) -> str:
    """Why deleting the targets ``target_ids`` would break the control selection (the
    file would be refused), in the window's words; "" when it would not."""
    gone = [t.id for t in project.targets if t.id in set(target_ids)]
    return control_problem(project, delete_targets(project, target_ids),
                           f"{', '.join(gone)} not deleted")


def control_problem(before: m.Project, after: m.Project, what: str) -> str:
    """Why ``after`` (``before`` with targets deleted or replaced) breaks the control
    selection that ``before`` has (the file would be refused): "``what``: why, and
    where to fix it"; "" when it does not."""
    from designer.project.validate_processing import processing_issues

    control = before.processing.gcps.control if before.processing is not None else None
    if control is None:
        return ""
    if control.ids and not after.processing.gcps.control.ids:
        named = (f"{control.ids[0]} is the only control GCP" if len(control.ids) == 1 else
                 f"{', '.join(control.ids)} are the only control GCPs")
        return (f"{what}: {named} named in the Processing panel; name others there "
                "(ground control, by id), or untick “a subset of the targets as control” "
                "first")
    old = {i.message for i in processing_issues(before)}
    new = [i.message for i in processing_issues(after) if i.message not in old]
    if not new:
        return ""
    return f"{what}: {new[0].replace('the project has', 'the project would have')}"


def replace_target(project: m.Project, index: int, target: m.Target) -> m.Project:
    items = list(project.targets)
    items[index] = target
    return set_targets(project, tuple(items))


def layout_targets(project: m.Project, xy: np.ndarray, roles, size_m: float,
                   prefix: str = "GCP") -> m.Project:
    """Replace every target by targets at ``xy`` (N, 2) with ``roles`` (N,); the
    control selection keeps the ids the new targets still have."""
    targets = tuple(
        m.Target(id=f"{prefix}{k + 1:02d}", role=str(roles[k]), shape="checker",
                 size_m=float(size_m), true=m.TruePosition(_coordinate(x), _coordinate(y)))
        for k, (x, y) in enumerate(np.asarray(xy, dtype=float)))
    return _drop_control_ids(set_targets(project, targets))


# ---------------------------------------------------------------------- flight
def terrain_rectangle(project: m.Project) -> tuple[tuple[float, float], ...]:
    """The terrain extent as an area polygon (counter-clockwise from south-west)."""
    e = project.scene.terrain.extent
    return ((e.min_X, e.min_Y), (e.max_X, e.min_Y), (e.max_X, e.max_Y), (e.min_X, e.max_Y))


def ensure_flight_plan(project: m.Project, reference_height_m: float | None = None
                       ) -> m.Project:
    """The project with a flight plan: a 50 m, 80/70 % grid over the terrain if none,
    flown above the terrain's mean height — or above ``reference_height_m`` (m), which a
    mesh terrain needs (the planner takes mean/highest/lowest from height fields only)."""
    if project.trajectory.flight_plan is not None:
        return project
    camera = project.cameras[0].id if project.cameras else "camera"
    reference = "mean" if reference_height_m is None else round(float(reference_height_m), 3)
    plan = m.FlightPlan(camera=camera, image_prefix="IMG_", area=terrain_rectangle(project),
                        altitude_agl_m=50.0, altitude_reference=reference)
    return replace_path(project, "trajectory.flight_plan", plan)


def set_flight(project: m.Project, **fields) -> m.Project:
    """Replace flight plan fields (creating the default plan first if there is none)."""
    project = ensure_flight_plan(project)
    plan = dataclasses.replace(project.trajectory.flight_plan, **fields)
    return replace_path(project, "trajectory.flight_plan", plan)


# ---------------------------------------------------------------------- camera
def set_camera(project: m.Project, camera: m.Camera, index: int = 0) -> m.Project:
    """Replace camera ``index`` (add it when there is none); a new id is followed by the
    flight plan, every exterior orientation, rig mount and orbit or facade flight that
    used the old one."""
    cameras = list(project.cameras)
    old_id = cameras[index].id if index < len(cameras) else None
    if index < len(cameras):
        cameras[index] = camera
    else:
        cameras.append(camera)
    project = dataclasses.replace(project, cameras=tuple(cameras))
    if old_id is not None and old_id != camera.id:
        traj = project.trajectory
        eos = tuple(dataclasses.replace(eo, camera=camera.id) if eo.camera == old_id else eo
                    for eo in traj.exterior_orientations)
        plan = traj.flight_plan
        if plan is not None and plan.camera == old_id:
            plan = dataclasses.replace(plan, camera=camera.id)
        rigs = tuple(dataclasses.replace(rig, mounts=tuple(
            dataclasses.replace(mt, camera=camera.id) if mt.camera == old_id else mt
            for mt in rig.mounts)) for rig in traj.rigs)
        patterns = tuple(dataclasses.replace(p, camera=camera.id) if p.camera == old_id else p
                         for p in traj.patterns)
        project = dataclasses.replace(project, trajectory=dataclasses.replace(
            traj, exterior_orientations=eos, flight_plan=plan, rigs=rigs, patterns=patterns))
    return project


# ---------------------------------------------------------------------- effects
def set_effect(project: m.Project, name: str, value) -> m.Project:
    """Turn effect ``name`` (a field of Effects) on with ``value`` or off with None."""
    effects = project.effects or m.Effects()
    effects = dataclasses.replace(effects, **{name: value})
    if all(getattr(effects, f.name) is None for f in dataclasses.fields(effects)):
        effects = None
    return dataclasses.replace(project, effects=effects)


# ---------------------------------------------------------------------- rigs
def add_oblique_rig(project: m.Project, name: str = "penta") -> m.Project:
    """The project with a nadir + four 45° oblique rig of its first camera, flown by the
    flight plan (created if there is none)."""
    camera = project.cameras[0].id if project.cameras else "camera"
    taken = {r.name for r in project.trajectory.rigs} | {c.id for c in project.cameras}
    base, k = name, 1
    while name in taken:
        k += 1
        name = f"{base}{k}"
    rig = m.Rig(name, tuple(m.Mount(camera, s, o, p, kp) for s, o, p, kp in PENTA_MOUNTS))
    project = replace_path(project, "trajectory.rigs", (*project.trajectory.rigs, rig))
    return set_flight(project, camera=name)


def set_mount(project: m.Project, rig_index: int, mount_index: int, **fields) -> m.Project:
    """Replace fields (camera, suffix, omega_deg, phi_deg, kappa_deg) of one mount."""
    rigs = list(project.trajectory.rigs)
    mounts = list(rigs[rig_index].mounts)
    mounts[mount_index] = dataclasses.replace(mounts[mount_index], **fields)
    rigs[rig_index] = dataclasses.replace(rigs[rig_index], mounts=tuple(mounts))
    return replace_path(project, "trajectory.rigs", tuple(rigs))
