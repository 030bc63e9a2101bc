"""The window's table of directions (designer.gui.state.wording.PANEL_DIRECTIONS) matches the
messages validation gives today: each time-line message a window user can meet reads
as a panel and a control, not as an element to add (Qt-free)."""

from __future__ import annotations

import dataclasses

from designer.gui.state.files import blank_project
from designer.gui.state.wording import panel_directions
from designer.project import model as m
from designer.project.validate_trajectory import trajectory_issues
from designer.project.validate_world import world_issues


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


def test_every_missing_time_line_message_points_to_the_flight_panel():
    for project in _projects_without_a_time_line():
        messages = [i.message for i in world_issues(project) if "time-line" in i.message]
        assert messages, project
        for message in messages:
            said = panel_directions(message)
            assert "<time-line>" not in said and "Flight panel" in said, message


def test_no_photos_points_to_the_flight_panel():
    (issue,) = [i for i in trajectory_issues(blank_project()) if "no photos" in i.message]
    said = panel_directions(issue.message)
    assert "<" not in said and "Flight panel" in said, issue.message


def test_the_surroundings_fixes_point_to_the_terrain_panel():
    import numpy as np

    from designer.project.validate_scene import scene_issues
    from designer.survey.surroundings import void_warning

    warning = void_warning(("A.png", "B.png"), np.array([0.0, 0.3]), "none")
    said = panel_directions(warning)
    assert "<" not in said and "Terrain panel" in said and "“auto”" in said, warning
    assert said.startswith("1 of 2 images sees past the terrain"), said

    p = blank_project()
    mesh = dataclasses.replace(p.scene.terrain, source=m.MeshTerrain("ground.ply"),
                               surroundings="auto")
    (issue,) = [i for i in scene_issues(dataclasses.replace(p.scene, terrain=mesh), None)
                if "mesh terrain" in i.message]
    said = panel_directions(issue.message)
    assert "mode=" not in said and "Terrain panel" in said and "“none”" in said, issue.message
