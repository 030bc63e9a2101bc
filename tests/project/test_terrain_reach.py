"""``designer check`` refuses what lies beyond the terrain and would be placed on it
anyway: a moving object's path point outside the terrain extent (the object would stand
at the edge's height), naming the object, the point and the fix."""

from __future__ import annotations

from designer.cli.main import main


def test_a_moving_object_path_point_off_the_terrain_is_named_with_its_fix(tmp_path,
                                                                           capsys):
    path = tmp_path / "x.xml"
    assert main(["new", str(path), "--template", "survey-dynamic"]) == 0
    text = path.read_text()
    on = '<point X="512045.0" Y="5406010.0"/>'
    assert on in text
    path.write_text(text.replace(on, '<point X="512145.0" Y="5406010.0"/>'))
    capsys.readouterr()
    assert main(["check", str(path)]) == 2
    lines = capsys.readouterr().err.splitlines()
    assert lines[0] == (
        f"{path}:59:11: <point>: moving object 'car1': path point 2 (X 512145, Y 5406010) "
        "lies outside the terrain extent (X 511950..512050, Y 5405950..5406050), where the "
        "object has no ground to stand on; move the point inside the extent (the <path> of "
        "the object in the project file) or enlarge the terrain extent (Terrain panel)"), lines
    assert len(lines) == 2
