"""The window words validation issues from their structured fields (designer.gui.state.
wording.issue_text), never by reading their messages: each time-line issue a window user
can meet reads as a panel and a control, not as an element to add; a range reads with the
field as its panel labels it (the declaration's label) and its limits; and a message
reworded in the library, its fields unchanged, changes nothing the window says (Qt-free)."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from designer.gui.state.files import blank_project
from designer.gui.state.plan_figures import void_text
from designer.gui.state.wording import issue_text, problem_text
from designer.project import model as m
from designer.project.problems import SourceMap
from designer.project.validate import semantic_issues
from designer.project.validate_declared import element_issues
from designer.project.validate_scene import scene_issues
from designer.project.validate_trajectory import trajectory_issues
from designer.project.validate_world import world_issues
from designer.survey.surroundings import void_images


def _projects_without_a_time_line() -> list[m.Project]:
    p = blank_project()
    cam = dataclasses.replace(p.cameras[0], rolling_shutter=m.RollingShutter(readout_s=0.02))
    photo = m.ExteriorOrientation("A.png", cam.id, 0.0, 0.0, 50.0, 0.0, 0.0, 0.0, time_s=1.0)
    car = m.MovingObject("car1", (m.PathPoint(-10, 0), m.PathPoint(10, 0)), speed_m_s=2.0,
                         shape="car")
    lighting = dataclasses.replace(p.scene.lighting, sun=m.SunOverTime())
    return [
        dataclasses.replace(p, cameras=(cam,)),
        dataclasses.replace(p, trajectory=dataclasses.replace(
            p.trajectory, exterior_orientations=(photo,))),
        dataclasses.replace(p, scene=dataclasses.replace(p.scene, moving_objects=(car,))),
        dataclasses.replace(p, scene=dataclasses.replace(p.scene, lighting=lighting)),
        dataclasses.replace(p, render=dataclasses.replace(p.render, image_metadata="exif",
                                                          output_format="jpeg")),
    ]


def _time_line_issues():
    for project in _projects_without_a_time_line():
        issues = [i for i in world_issues(project) if i.code == "needs-time-line"]
        assert issues, project
        yield from issues


def test_every_missing_time_line_issue_points_to_the_flight_panel():
    tags = set()
    for issue in _time_line_issues():
        said = issue_text(issue)
        assert "<time-line>" not in said and "Flight panel" in said, issue.message
        tags.add(issue.tag)
    assert tags == {"rolling-shutter", "photo", "object", "sun-over-time", "output"}


def test_the_words_come_from_the_fields_not_the_message():
    """The library rewords its message (or translates it): the window says the same, from
    the issue's code, element and value. Reading the message with patterns, as the window
    once did, would show the new message with its element to add."""
    issues = list(_time_line_issues())
    issues += [i for i in trajectory_issues(blank_project()) if i.code == "no-photos"]
    for issue in issues:
        reworded = dataclasses.replace(issue, message="die Flugbahn hat keine <time-line>")
        assert issue_text(reworded) == issue_text(issue), issue.message
        assert "<" not in issue_text(reworded)
    shutter = next(i for i in issues if i.tag == "rolling-shutter")
    assert "0.02 s" in issue_text(shutter)  # the value, from the field


def test_the_object_named_in_the_words_is_the_issue_s_own():
    car = next(i for i in _time_line_issues() if i.tag == "object")
    assert "'car1'" in issue_text(car)
    renamed = dataclasses.replace(car, obj=dataclasses.replace(car.obj, id="van7"))
    assert "'van7'" in issue_text(renamed) and "car1" not in issue_text(renamed)


def test_no_photos_points_to_the_flight_panel():
    (issue,) = [i for i in trajectory_issues(blank_project()) if i.code == "no-photos"]
    said = issue_text(issue)
    assert "<" not in said and "Flight panel" in said, issue.message


@pytest.mark.parametrize(("element", "field_label", "limits"), [
    (m.RollingShutter(readout_s=0.9), "readout 0.9", "from 0 to 0.5 s"),
    (m.Sun(azimuth_deg=400.0, elevation_deg=50.0), "azimuth 400",
     "at least 0 and below 360 °"),
    (m.Sun(azimuth_deg=10.0, elevation_deg=-5.0), "elevation -5",
     "greater than 0 and at most 90 °"),
])
def test_a_range_reads_with_the_declared_label_and_its_limits(element, field_label, limits):
    (issue,) = element_issues(element)
    assert issue.code == "range" and issue.limits is not None
    said = issue_text(issue)
    assert said == f"{field_label} must be {limits}", said
    # the label and limits come from the declaration and the fields, not the message
    assert issue_text(dataclasses.replace(issue, message="?")) == said


def test_a_choice_reads_with_its_label_and_choices():
    shutter = dataclasses.replace(m.RollingShutter(readout_s=0.02), direction="sideways")
    (issue,) = element_issues(shutter)
    assert issue.code == "choice" and issue.value == "sideways"
    said = issue_text(issue)
    assert said.startswith("rows read “sideways” is not one of "), said
    assert all(c in said for c in issue.choices)


def test_a_problems_line_keeps_its_place_and_names_its_panel():
    """A located problem keeps FILE:LINE:COL and names the panel of its element, the one
    a click on the line opens, in place of the element; the words after it come from the
    fields."""
    from designer.gui.state.files import panel_for_problem

    p = _projects_without_a_time_line()[0]
    smap = SourceMap("")
    (issue,) = [i for i in semantic_issues(p) if i.code == "needs-time-line"]
    line = problem_text(smap.locate(issue), "p.xml")
    assert line.startswith("p.xml:1:1: Camera › a camera reads its rows out"), line
    assert "Camera panel" in line and "<" not in line
    assert panel_for_problem(line) == "Camera"


def test_the_surroundings_fixes_point_to_the_terrain_panel():
    void = void_images(("A.png", "B.png"), np.array([0.0, 0.3]), "none")
    said = void_text(void)
    assert "<" not in said and "Terrain panel" in said and "“auto”" in said, said
    assert said.startswith("1 of 2 images sees past the terrain"), said
    assert "worst B.png: 30.0 %" in said

    p = blank_project()
    mesh = dataclasses.replace(p.scene.terrain, source=m.MeshTerrain("ground.ply"),
                               surroundings="auto")
    (issue,) = [i for i in scene_issues(dataclasses.replace(p.scene, terrain=mesh), None)
                if i.code == "surroundings-need-height-field"]
    said = issue_text(issue)
    assert "mode=" not in said and "Terrain panel" in said and "“none”" in said, issue.message
