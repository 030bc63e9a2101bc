import json
import subprocess
import sys
from pathlib import Path

import cv2
import numpy as np

from designer.cli.main import main
from designer.project import load_project
from designer.survey.project_poses import project_poses

EXAMPLE = "resources/examples/survey/survey.xml"


def test_plan_json_parses_and_reports_the_example(capsys):
    assert main(["plan", EXAMPLE, "--json"]) == 0
    figures = json.loads(capsys.readouterr().out)
    assert figures["n_images"] > 50
    assert 0.75 <= figures["front_overlap_median"] <= 0.85
    assert 0.65 <= figures["side_overlap_median"] <= 0.75
    assert len(figures["gcps"]) == 10 and all(g["images"] >= 3 for g in figures["gcps"])
    g = figures["gsd_terrain_m"]
    assert g["min"] < g["mean"] < g["max"]


def test_plan_maps_are_pictures(tmp_path, capsys):
    assert main(["plan", EXAMPLE, "--maps", str(tmp_path)]) == 0
    for name in ("coverage.png", "gsd.png"):
        image = cv2.imread(str(tmp_path / name))
        assert image is not None and image.shape[0] > 300 and image.std() > 10


def test_written_poses_reproduce_the_planned_stations(tmp_path, capsys):
    out = tmp_path / "explicit.xml"
    assert main(["plan", EXAMPLE, "--write-poses", str(out)]) == 0
    from designer.scene.build import build_heightfield

    original = load_project(EXAMPLE)
    hf = build_heightfield(original.scene.terrain, tmp_path)
    planned, _ = project_poses(original, hf)
    explicit, _ = project_poses(load_project(out), None)
    assert [p.image_name for p in explicit] == [p.image_name for p in planned]
    for a, b in zip(explicit, planned, strict=True):
        assert np.allclose(a.C_world, b.C_world, atol=1e-9)
        assert np.allclose(a.R_cam_to_world, b.R_cam_to_world, atol=1e-12)


def test_plan_of_a_broken_file_is_a_one_line_error(tmp_path):
    bad = tmp_path / "bad.xml"
    bad.write_text("<project>")
    out = subprocess.run([sys.executable, "-m", "designer", "plan", str(bad)],
                         capture_output=True, text=True)
    assert out.returncode == 2
    assert "bad.xml:" in out.stderr and "Traceback" not in out.stderr


def _texture_warnings(project, tmp_path, capsys) -> list[str]:
    from designer.project import write_project

    path = tmp_path / "p.xml"
    write_project(project, path)
    assert main(["plan", str(path), "--json"]) == 0
    return [w for w in json.loads(capsys.readouterr().out)["warnings"]
            if w.startswith("texture repeats")]


def test_plan_warns_when_the_tiled_texture_repeats_inside_the_footprint(tmp_path, capsys):
    import dataclasses

    example = load_project(EXAMPLE)
    assert example.scene.texture.variation is not None
    assert _texture_warnings(example, tmp_path, capsys) == []

    def with_texture(**changes):
        tex = dataclasses.replace(example.scene.texture, **changes)
        return dataclasses.replace(example, scene=dataclasses.replace(example.scene,
                                                                      texture=tex))

    # without the variation the 20 m tiles repeat inside the 76.1 x 50.7 m footprint
    # (at the median GSD of the stations, as `designer plan` prints it)
    (warning,) = _texture_warnings(with_texture(variation=None), tmp_path, capsys)
    assert warning.startswith("texture repeats every 20 m, shorter than the 50.7 m")
    assert "give the texture a variation" in warning
    # one tile over the 100 m terrain: longer than the footprint, no repeat in an image
    assert _texture_warnings(with_texture(variation=None, repeat_X=1, repeat_Y=1),
                             tmp_path, capsys) == []
    # 50 m tiles: just shorter than the 50.7 m short side of the footprint
    (warning,) = _texture_warnings(with_texture(variation=None, repeat_X=2, repeat_Y=2),
                                   tmp_path, capsys)
    assert warning.startswith("texture repeats every 50 m, shorter than the 50.7 m")
    (warning,) = _texture_warnings(with_texture(variation=None, repeat_X=3, repeat_Y=3),
                                   tmp_path, capsys)
    assert warning.startswith("texture repeats every 33.3333 m")


def test_a_reader_that_stops_early_gets_no_traceback():
    """``designer plan P.xml | head -1``: the program stops quietly when the pipe closes."""
    proc = subprocess.Popen([sys.executable, "-m", "designer", "plan", EXAMPLE],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    first = proc.stdout.readline()
    proc.stdout.close()  # the reader goes away after one line
    err = proc.stderr.read().decode()
    proc.stderr.close()
    proc.wait(timeout=300)
    assert first.startswith(b"resources/examples/survey/survey.xml:")
    assert "Traceback" not in err and "BrokenPipe" not in err, err


def _images_seeing_each_gcp(project, base_dir) -> dict[str, int]:
    """Counted image by image, each with its own pose and camera: the GCP inside the
    picture and not behind the terrain."""
    from designer.core.projection import project_points
    from designer.core.raycast import TerrainRaycaster
    from designer.project.interiors import render_interior
    from designer.scene.build import build_heightfield, build_targets
    from designer.survey.project_poses import project_images

    hf = build_heightfield(project.scene.terrain, base_dir, project.crs)
    rc = TerrainRaycaster(hf)
    targets = build_targets(project, hf)
    xyz = np.array([t.true_xyz for t in targets])
    images = project_images(project, hf)
    counts = np.zeros(len(targets), dtype=int)
    for k, station in enumerate(images.stations):
        interior = render_interior(project.camera(images.camera_ids[k]),
                                   project.render.resolution_scale)
        g = np.flatnonzero(project_points(xyz, station.C_world, station.R_cam_to_world,
                                          interior).in_image[0])
        hidden = rc.occluded(xyz[g], np.repeat(np.reshape(station.C_world, (1, 3)), len(g),
                                               axis=0), tol_m=0.01)
        counts[g[~hidden]] += 1
    return {t.target.id: int(c) for t, c in zip(targets, counts, strict=True)}


def test_plan_counts_every_image_of_a_rig_that_sees_a_gcp(tmp_path, capsys):
    from designer.project import write_project
    from tests.synthetic import rig_survey, two_camera_survey

    for name, project in (("rig", rig_survey()), ("duo", two_camera_survey())):
        path = tmp_path / f"{name}.xml"
        write_project(project, path)
        assert main(["plan", str(path), "--json"]) == 0
        figures = json.loads(capsys.readouterr().out)
        said = {g["id"]: g["images"] for g in figures["gcps"]}
        expected = _images_seeing_each_gcp(project, tmp_path)
        assert sum(expected.values()) > 0, name
        assert said == expected, name
        assert figures["gcp_views_min"] == min(expected.values()), name


def test_the_estimate_counts_its_workers_in_words(tmp_path, capsys):
    """'with 1 worker', 'with 2 workers': the report's estimate line, as a reader says it."""
    text = Path(EXAMPLE).read_text()
    for workers, words in ((1, "with 1 worker on"), (2, "with 2 workers on")):
        path = tmp_path / f"w{workers}.xml"
        path.write_text(text.replace("<workers>1</workers>", f"<workers>{workers}</workers>"))
        assert main(["plan", str(path)]) == 0
        line = next(x for x in capsys.readouterr().out.splitlines()
                    if "estimated render time" in x)
        assert words in line and "(s)" not in line, line
