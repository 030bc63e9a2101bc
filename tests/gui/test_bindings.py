"""Every field of every panel is bound to an element of the project model: a misspelt
path fails when it is bound; a path into an element the project lacks disables the
field (AbsentElement), and on a project that has every element no field is disabled
for want of one."""

from __future__ import annotations

import dataclasses

import pytest
from PySide6.QtWidgets import QDoubleSpinBox

from designer.gui.qt.widgets import Bindings, model_getter
from designer.gui.state import edits
from designer.gui.state.edits import AbsentElement, UnknownField
from designer.project import declare
from designer.project import model as m
from designer.project.templates import survey


def _filled_projects() -> list[m.Project]:
    """The survey template with every optional element present, in both variants of
    each union the panels show (procedural/flat terrain, procedural/image texture, sun
    direction/position, Brown–Conrady/fisheye distortion, height/given reference)."""
    base = survey().project
    effects = m.Effects(
        vignetting=m.Vignetting(0.2, 0.01, 0.001, True), sensor_noise=m.SensorNoise(1.5, 2),
        sensor=m.Sensor(20000.0, 3.0), blur=m.Blur(0.5), motion_blur=m.MotionBlur(0.001, 8.0),
        jpeg=m.Jpeg(90), defocus=m.Defocus(2.8, 50.0, 48.0))
    # every other (newer) effect as it is switched on
    effects = dataclasses.replace(effects, **{
        f.name: declare.switched_on(declare.field_class(m.Effects, f.name))
        for f in dataclasses.fields(effects) if getattr(effects, f.name) is None})
    processing = m.Processing(
        calibration=m.Calibration("full", m.PreCalibrationError(2.0, 1.0, 0.01, seed=4)),
        gcps=m.GcpProcessing("bundle", 0.5, 3, m.ControlSelection((), 4, "random", 9)),
        position_prior=m.PositionPrior("rtk", 0.02, 0.03, 5),
        matching=m.Matching(4096, "exhaustive", 2), dense="cpu")
    cam = dataclasses.replace(base.cameras[0], name="P4P",
                              distortion=m.BrownConradyDistortion(-0.01, 0.002),
                              rolling_shutter=m.RollingShutter(0.03))
    first = dataclasses.replace(base, effects=effects, processing=processing, cameras=(cam,),
                                trajectory=dataclasses.replace(base.trajectory, time_line=(
                                    m.TimeLine("2026-06-21T09:30:00Z", 5.0, 8.0, 2.0))))
    first = edits.replace_path(first, "scene.lighting.clouds", m.CloudShadows())
    E0, N0 = base.origin.E0, base.origin.N0
    first = edits.replace_path(first, "scene.moving_objects", (m.MovingObject(
        "car1", (m.PathPoint(E0 - 40, N0), m.PathPoint(E0 + 40, N0)), speed_m_s=3.0),))
    first = edits.replace_path(first, "scene.buildings", (m.Building(
        "house1", tuple(m.PathPoint(E0 + x, N0 + y) for x, y in ((5, 5), (15, 5), (15, 13),
                                                                  (5, 13))),
        "gable", 6.0, 9.0),))
    first = edits.replace_path(first, "scene.vegetation", m.Vegetation(
        (m.PlantGroup(0.05, "shrub", height_m=1.0, crown_m=1.2),), wind=m.Wind()))
    assert first.scene.targets.survey_accuracy is not None
    assert first.trajectory.flight_plan.pose_noise is not None
    second = edits.replace_path(first, "scene.terrain.source", m.FlatTerrain(1.5))
    second = edits.replace_path(second, "scene.texture.source", m.ImageTexture("grass.png"))
    second = edits.replace_path(second, "scene.lighting.sun",
                                m.SunPosition("2024-06-21T11:00:00+02:00", 46.5, 7.4))
    second = edits.replace_path(second, "cameras[0].distortion",
                                m.FisheyeEquidistantDistortion(0.01, 0.0, 0.0, 0.001))
    second = edits.set_flight(second, altitude_reference=12.0)
    return [first, second]


def test_a_misspelt_path_fails_when_bound(qtbot, window):
    bindings = Bindings(window.editor)
    with pytest.raises(UnknownField, match=r"cameras\[0\]\.focal_lenght_mm.*focal_lenght_mm"):
        bindings.bind(QDoubleSpinBox(), "cameras[0].focal_lenght_mm", "Camera focal length")
    with pytest.raises(UnknownField, match="sceen"):
        model_getter("sceen.terrain.extent.min_X")
    # a real path binds
    bindings.bind(QDoubleSpinBox(), "cameras[0].focal_length_mm", "Camera focal length")


def test_absent_elements_are_told_apart_from_errors():
    project = survey().project  # no <processing>, procedural terrain
    with pytest.raises(AbsentElement) as absent:
        edits.get_path(project, "processing.matching.max_features")
    assert absent.value.parent is None and absent.value.segment == "matching"
    with pytest.raises(AbsentElement) as variant:
        edits.get_path(project, "scene.terrain.source.height_m")  # flat terrain only
    assert isinstance(variant.value.parent, m.ProceduralTerrain)
    with pytest.raises(AbsentElement):
        edits.get_path(project, "cameras[3].focal_length_mm")
    with pytest.raises(AbsentElement):
        edits.replace_path(project, "processing.dense", "cpu")
    with pytest.raises(UnknownField, match="focal_lenght_mm"):
        edits.get_path(project, "cameras[0].focal_lenght_mm")


def test_every_binding_resolves_on_a_filled_project(qtbot, window):
    projects = _filled_projects()
    bound = [(title, widget, get) for title, panel in window.panels.items()
             for widget, get in panel.bindings.items]
    assert len(bound) > 80
    resolved_somewhere = set()
    for project in projects:
        for title, widget, get in bound:
            try:
                get(project)
            except AbsentElement as error:
                # only a union variant may lack a field: never a missing element
                assert error.parent is not None, f"{title}: {widget.objectName()}: {error}"
            else:
                resolved_somewhere.add(id(widget))
    missing = [f"{title}: {widget.objectName()}" for title, widget, _ in bound
               if id(widget) not in resolved_somewhere]
    assert not missing, missing

    # shown in the window: no field is disabled for want of an element
    window.editor.edit(projects[0], "everything")
    disabled = [f"{title}: {widget.objectName()}" for title, widget, get in bound
                if not widget.isEnabled() and _resolves(get, projects[0])]
    assert not disabled, disabled


def _resolves(get, project) -> bool:
    try:
        return get(project) is not None
    except AbsentElement:
        return False
