"""``designer check`` names what lies beyond the terrain and would be placed on it
anyway, with the fix: a moving object's path point outside the terrain extent is refused
(the object would stand at the edge's height); GCPs, buildings and flight-area vertices
outside the ground a terrain mesh or DEM holds are warned."""

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
        "object has no ground to stand on; move the point inside the extent (the path of "
        "the object in the project file) or enlarge the terrain extent"), lines
    assert len(lines) == 2


def test_gcps_and_the_flight_area_off_a_terrain_mesh_are_warned_with_the_fix(tmp_path,
                                                                           capsys):
    """The survey's terrain as a mesh that holds only the west half of the extent (local
    X −50..0): the GCPs east of it, a building there and the flight area's eastern
    vertices are named."""
    import dataclasses

    import numpy as np

    from designer.core.heightfield import Heightfield
    from designer.project import model as m
    from designer.project.templates import _house, template
    from designer.scene.mesh import heightfield_to_mesh, write_mesh_ply
    from tests.synthetic import write_project_file

    p = template("survey").project
    terrain = dataclasses.replace(p.scene.terrain, source=m.MeshTerrain("ground.ply"))
    shed = _house("shed", p.origin.E0 + 30, p.origin.N0 - 10, 6.0, 4.0, "flat", 3.0)
    p = dataclasses.replace(p, scene=dataclasses.replace(p.scene, terrain=terrain,
                                                         buildings=(shed,)))
    path = write_project_file(p, tmp_path)
    write_mesh_ply(heightfield_to_mesh(Heightfield(-50.0, -50.0, 50.0, 100.0,
                                                   np.zeros((2, 2)))), tmp_path / "ground.ply")
    capsys.readouterr()
    assert main(["check", str(path)]) == 0  # warned, not refused
    lines = capsys.readouterr().err.splitlines()
    east = [t for t in p.targets if t.true.X > p.origin.E0]
    assert east
    gcps = [line for line in lines if line.startswith(f"warning: {path}: <target>: ")]
    assert len(gcps) == 1, lines
    assert f"GCP {east[0].id} (X " in gcps[0]
    assert (") lie outside the terrain mesh ground.ply, which holds ground only over "
            "X 511950..512000, Y 5405950..5406050: the scene has no ground there; move the "
            "GCPs onto the terrain (GCPs panel), or use a terrain file that covers them"
            ) in gcps[0], gcps[0]
    area = [line for line in lines if line.startswith(f"warning: {path}: <area>: ")]
    assert len(area) == 1 and "flight area vertex 2 (X 512" in area[0], lines
    assert "draw the flight area over the terrain (Flight panel)" in area[0]
    shed_lines = [line for line in lines if line.startswith(f"warning: {path}: <footprint>: ")]
    assert len(shed_lines) == 1 and "building 'shed' corner 1 (X 512027, Y 5405988)" in \
        shed_lines[0], lines
    assert "move the buildings onto the terrain (Buildings panel)" in shed_lines[0]


def test_gcps_over_a_dem_s_no_data_are_warned(tmp_path, capsys):
    """The survey on an ESRI ASCII DEM whose eastern half is no-data: the GCPs there lie
    inside the declared extent but outside the ground the DEM holds."""
    import dataclasses

    import numpy as np

    from designer.project import model as m
    from designer.project.templates import template
    from tests.synthetic import write_project_file

    p = template("survey").project
    e = p.scene.terrain.extent
    z = np.full((21, 21), 100.0)
    z[:, 11:] = -9999  # east of the extent's middle
    (tmp_path / "dem.asc").write_text(
        f"ncols 21\nnrows 21\nxllcorner {e.min_X - 2.5}\nyllcorner {e.min_Y - 2.5}\n"
        "cellsize 5\nNODATA_value -9999\n"
        + "\n".join(" ".join(f"{v:g}" for v in row) for row in z) + "\n")
    terrain = dataclasses.replace(p.scene.terrain, source=m.DemTerrain("dem.asc"))
    path = write_project_file(
        dataclasses.replace(p, scene=dataclasses.replace(p.scene, terrain=terrain)), tmp_path)
    capsys.readouterr()
    assert main(["check", str(path)]) == 0
    lines = capsys.readouterr().err.splitlines()
    gcps = [line for line in lines if line.startswith(f"warning: {path}: <target>: ")]
    assert len(gcps) == 1, lines
    assert "GCP GCP03 (X 512038, Y 5405962)" in gcps[0]
    assert "lie outside the DEM dem.asc, which holds ground only over X 511950..512000" \
        in gcps[0], gcps[0]
