"""read → model → write is lossless; writing is stable after one normalisation."""

from __future__ import annotations

from hypothesis import HealthCheck, given, settings

from designer.project.model_to_xml import project_to_bytes
from designer.project.validate import semantic_issues
from designer.project.xml_read import parse_project
from tests.project.strategies import projects

SETTINGS = settings(max_examples=150, deadline=None,
                    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])


@SETTINGS
@given(projects())
def test_random_valid_projects_round_trip(project):
    assert semantic_issues(project) == []  # the strategy builds valid projects
    data = project_to_bytes(project)
    again, _ = parse_project(data, "random.xml")
    assert again == project
    assert project_to_bytes(again) == data


NON_NORMAL = b"""<?xml version="1.0"?>
<!-- hand written: extra spaces, "1" for true, "+5", omitted defaults -->
<project schema-version="1.0" xmlns="urn:designer:project:1">
  <name>  Hand written  </name>
  <crs>local</crs>
  <origin H0="0" N0="+0" E0="0"/>
  <scene>
    <terrain>
      <extent min-X="-10" min-Y="-10" max-X="10" max-Y="1e1"/>
      <flat height-m="0"/>
    </terrain>
    <texture interpolation="closest">
      <procedural pattern="checkerboard" seed="007" texel-size-m=".5"/>
      <tiling repeat-X="+2" repeat-Y="2"/>
    </texture>
    <lighting sky-strength="1" sun-strength="3">
      <sun azimuth-deg="10" elevation-deg="45"/>
    </lighting>
  </scene>
  <cameras>
    <camera id="c">
      <focal-length-mm>
        8.8
      </focal-length-mm>
      <sensor width-mm="13.2" height-mm="8.8"/>
      <image width-px="5472" height-px="3648"/>
    </camera>
  </cameras>
  <trajectory>
    <exterior-orientations>
      <photo name="a" camera="c" X="0" Y="0" Z="30" omega="0" phi="0" kappa="0"/>
    </exterior-orientations>
  </trajectory>
  <render>
    <preset>draft</preset>
    <pixel-filter type="box" width-px="1"/>
    <resolution-scale>1</resolution-scale>
    <workers>1</workers>
    <output format="png" bit-depth="8"/>
  </render>
  <outputs directory="out"/>
</project>
"""


def test_a_hand_written_file_is_stable_after_one_normalisation():
    first, _ = parse_project(NON_NORMAL, "hand.xml")
    assert first.name == "Hand written"
    assert first.scene.texture.source.seed == 7
    once = project_to_bytes(first)
    second, _ = parse_project(once, "once.xml")
    assert second == first
    assert project_to_bytes(second) == once
