"""``designer check``'s hard-case warnings (designer.checks.hard_cases) and the guards
without a render: each warning appears on the project that walks into its case and not
on the same project a step away from it; the refusals name the case and the fix."""

from __future__ import annotations

import math
import re
import subprocess
import sys
from dataclasses import replace

import numpy as np
import pytest

from designer.checks.hard_cases import (
    collinear_control_warning,
    collinear_problem,
    distortion_warning,
    point_spread,
)
from designer.cli.main import main
from designer.core.heightfield import Heightfield
from designer.errors import DesignerError
from designer.project import model as m
from tests.hard_cases import scenes
from tests.synthetic import model_camera, write_project_file


def _check(tmp_path, project, capsys) -> list[str]:
    path = write_project_file(project, tmp_path)
    assert main(["check", str(path)]) == 0  # warnings never change the exit status
    err = capsys.readouterr().err.splitlines()
    assert all(line.startswith(f"warning: {path}: <") for line in err), err
    return err


# ------------------------------------------------------------------ collinear control
@pytest.mark.parametrize(("width_m", "warned"), [(0.0, True), (0.5, True), (4.0, False)])
def test_check_warns_when_control_is_nearly_collinear(tmp_path, capsys, width_m, warned):
    """Five control GCPs 20 m along a line, ±width_m off it: a strip of 2·width_m in
    plan; on the ±0.5 m terrain the 3-D strip is a little wider."""
    err = _check(tmp_path, scenes.collinear_control(width_m), capsys)
    found = [e for e in err if "<targets>:" in e]
    assert bool(found) == warned, err
    if warned:
        (line,) = found
        assert "nearly collinear" in line and "off the line" in line
        width, length, condition = map(float, re.search(
            r"a strip (\S+) m wide and (\S+) m long \(condition number (\S+)\)",
            line).groups())
        assert 2 * width_m <= width <= 2 * width_m + 0.3 and length == 20.0
        assert condition > 10


def test_collinear_control_on_a_terrain_mesh_is_warned_as_on_a_height_field(tmp_path,
                                                                          capsys):
    """The control's surveyed coordinates need no height field: ``designer check`` and
    the Flight panel's warnings (designer.gui.state.hard_cases) warn of nearly collinear
    control on a terrain mesh in the words they use on a height field."""
    from designer.gui.state.derived import compute_targets, compute_terrain
    from designer.gui.state.hard_cases import hard_case_lines
    from designer.project import load_project

    project = scenes.surveyed_at_true(scenes.collinear_control(0.5))
    on_field = [e for e in _check(tmp_path / "field", project, capsys) if "<targets>:" in e]
    assert len(on_field) == 1 and "nearly collinear" in on_field[0], on_field
    message = on_field[0].split("<targets>: ", 1)[1]
    mesh_path = scenes.on_a_terrain_mesh(project, tmp_path / "mesh")
    assert main(["check", str(mesh_path)]) == 0
    on_mesh = [e for e in capsys.readouterr().err.splitlines() if "<targets>:" in e]
    assert on_mesh == [f"warning: {mesh_path}: <targets>: {message}"]

    mesh_project = load_project(mesh_path)
    terrain = compute_terrain(mesh_project, mesh_path.parent)
    assert terrain.heightfield is None and terrain.mesh is not None
    lines = hard_case_lines(mesh_project, compute_targets(mesh_project, terrain.heightfield),
                            None)
    surveyed = [t.surveyed.position for t in project.targets[:5]]
    warning = collinear_control_warning(["G0", "G1", "G2", "G3", "G4"],
                                        [(p.X, p.Y, p.Z) for p in surveyed])
    assert lines == [f"{warning.message}; {warning.panel_fix or warning.fix}"]
    assert message == f"{warning.message}; {warning.fix}"


def test_point_spread_at_utm_size():
    xyz = np.array([[830000.0 + t, 9999000.0 + 0.01 * (-1) ** i, 250.0]
                    for i, t in enumerate(np.linspace(0, 100, 6))])
    s = point_spread(xyz)
    assert s.length_m == pytest.approx(100.0, abs=1e-5)
    assert 0.02 <= s.width_m <= 0.03  # the zigzag tilts the axis a little
    assert 2000 < s.condition < 8000
    assert point_spread(xyz[:, :] * [1, 0, 1] + [0, 5e6, 0]).condition == math.inf


def test_the_gcp_similarity_refuses_control_on_one_line(monkeypatch):
    """RANSAC's similarity on control 5 cm off a 100 m line is silently wrong by degrees
    (see docs/hard-cases.md); georeferencing refuses it with the condition number."""
    from designer.core.truth import GroundControlPoint
    from designer.sfm import process_free

    E = np.linspace(-50, 50, 5)
    surveyed = {f"G{k}": np.array([500000.0 + e, 5000000.0 + 0.05 * (-1) ** k, 250.0])
                for k, e in enumerate(E)}
    gcps = {g: GroundControlPoint(g, "control", xyz, xyz, [0.0, 0.0, 0.0])
            for g, xyz in surveyed.items()}
    offset = np.array([500000.0, 5000000.0, 250.0])
    rng = np.random.default_rng(3)
    local = {g: xyz - offset + rng.normal(0, 0.01, 3) for g, xyz in surveyed.items()}
    monkeypatch.setattr(process_free, "triangulate_gcps",
                        lambda rec, marks: (local, dict.fromkeys(local, 4)))
    with pytest.raises(DesignerError) as info:
        process_free._gcp_similarity(None, gcps, [], set(gcps), offset, lambda _: None,
                                     "run 1")
    message = str(info.value)
    assert message.startswith("run 1: the 5 control GCPs lie on one line")
    assert "condition number" in message and "add control off the line" in message
    assert "\n" not in message


def test_fewer_than_three_points_is_a_problem_too():
    assert "only 2" in collinear_problem(np.zeros((2, 3)), "control GCPs")


# ------------------------------------------------------------------ GSD and texel
@pytest.mark.parametrize(("texel_m", "expected"), [
    (0.002, "is below the texture's texel"),     # 1 mm GSD on 2 mm texels
    (0.0005, None),                              # texel = GSD / 2: as advised
])
def test_check_warns_when_the_gsd_is_below_the_texel(tmp_path, capsys, texel_m, expected):
    project = scenes.gsd_family(0.001)
    texture = replace(project.scene.texture, source=replace(project.scene.texture.source,
                                                            texel_size_m=texel_m))
    err = _check(tmp_path, replace(project, scene=replace(project.scene, texture=texture)),
                 capsys)
    found = [e for e in err if "<texture>:" in e]
    if expected is None:
        assert found == [], err
    else:
        (line,) = found
        assert expected in line and "GSD/2 (0.05 cm)" in line and "spans 2 pixels" in line


def test_check_repeats_the_plans_aliasing_warning_for_texels_finer_than_a_third(
        tmp_path, capsys):
    project = scenes.gsd_family(0.5)  # 50 cm GSD: 5 cm texels alias
    texture = replace(project.scene.texture, source=replace(project.scene.texture.source,
                                                            texel_size_m=0.05))
    err = _check(tmp_path, replace(project, scene=replace(project.scene, texture=texture)),
                 capsys)
    (line,) = [e for e in err if "<texture>:" in e]
    assert "finer than a third of the GSD" in line and "alias" in line


# ------------------------------------------------------------------ distortion
@pytest.mark.parametrize(("k1", "warned"), [(-0.19, True), (-0.1, False), (0.2, False)])
def test_distortion_close_to_its_fold_inside_the_image_is_warned(k1, warned):
    """640 × 480, f = 500 px: the corner at normalised radius 0.8. k1 = −0.19 reaches
    0.88 at its fold (r = 1.32); the corner's preimage r = 0.99 has g' = 0.45."""
    cam = model_camera(distortion=m.BrownConradyDistortion(k1=k1))
    warning = distortion_warning(cam)
    assert (warning is not None) == warned
    if warned:
        assert warning.element == "brown-conrady"
        assert "magnifies their radial error 2.2x" in warning.message
        assert "lens map stops being monotonic (442 px)" in warning.message


def test_check_prints_the_distortion_warning(tmp_path, capsys):
    project = scenes.strong_brown()
    err = _check(tmp_path, project, capsys)
    (line,) = [e for e in err if "<brown-conrady>:" in e]
    assert "camera 'cam'" in line and "reduce the distortion coefficients" in line


def test_distortion_beyond_its_fold_inside_the_image_is_refused(tmp_path, capsys):
    """k1 = −0.3 folds at normalised radius 0.58 (reaching 0.385); the corner is at 0.8."""
    project = scenes.strong_brown()
    cam = replace(project.cameras[0], distortion=m.BrownConradyDistortion(k1=-0.3))
    path = write_project_file(replace(project, cameras=(cam,)), tmp_path)
    assert main(["check", str(path)]) == 2
    err = capsys.readouterr().err
    assert "folds the lens map inside the image" in err and "Traceback" not in err


# ------------------------------------------------------------------ horizontal rays
def test_a_horizontal_ray_over_a_height_field_ends():
    """The principal ray of a camera at φ = 90° has z ~ 1e-17: it entered the height band
    at t ~ 1e17 m, where a half-cell step no longer changes t, and the march never ended.
    Run in a child process so a regression fails instead of hanging the suite."""
    code = (
        "import numpy as np\n"
        "from designer.core.heightfield import Heightfield\n"
        "from designer.core.rotation import rotation_from_opk\n"
        "hf = Heightfield(0.0, 0.0, 0.5, 0.5, np.full((81, 81), 250.0) "
        "+ np.random.default_rng(0).uniform(-0.5, 0.5, (81, 81)))\n"
        "R = rotation_from_opk(0.0, np.pi / 2, np.pi / 2)\n"
        "C = np.array([[50.0, 20.0, 256.0]])\n"
        "hit = hf.intersect_rays(C, -R[:, 2][None])\n"
        "down = hf.intersect_rays(C, np.array([[-1.0, 0.0, -0.3]]))\n"
        "print(np.isnan(hit).all(), np.isfinite(down).all())\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         timeout=60)
    assert out.stdout.split() == ["True", "True"], out.stderr


def test_heightfield_type_is_the_one_the_child_uses():
    assert Heightfield.__module__ == "designer.core.heightfield"


# ------------------------------------------------------------------ thin networks
def _thin(kind: str) -> m.Project:
    """One image; a flight plan over a 2 × 14 m strip (one line of 6 images); a plan with
    no overlap (2 images over the study template's 14 m block)."""
    if kind == "one image":
        return scenes.tiny_survey(n_photos=1)
    project = scenes.flat_tiny()
    plan = project.trajectory.flight_plan
    E0, N0 = project.origin.E0, project.origin.N0
    if kind == "one flight line":
        plan = replace(plan, area=((E0 - 1, N0 - 7), (E0 + 1, N0 - 7), (E0 + 1, N0 + 7),
                                   (E0 - 1, N0 + 7)))
    else:
        plan = replace(plan, front_overlap_percent=0.0, side_overlap_percent=0.0)
    return replace(project, trajectory=m.Trajectory(flight_plan=plan))


THIN = {
    "one image": ["<trajectory>: 1 image: structure from motion needs at least 3 "
                  "overlapping images"],
    "one flight line": ["<flight-plan>: all 6 images lie on one flight line: no side overlap"],
    "zero overlap": ["<trajectory>: 2 images: structure from motion needs at least 3",
                     "<flight-plan>: front overlap 0 %: consecutive images share less than "
                     "half their footprint"],
}


@pytest.mark.parametrize("kind", list(THIN))
def test_check_and_plan_warn_of_a_network_too_thin_for_sfm(tmp_path, capsys, kind):
    err = _check(tmp_path, _thin(kind), capsys)
    for expected in THIN[kind]:
        assert any(expected in line for line in err), err
    path = tmp_path / "project.xml"
    assert main(["plan", str(path)]) == 0
    out = capsys.readouterr().out
    for expected in THIN[kind]:
        assert f"  warning: {expected.split('>: ', 1)[1]}" in out, out


def test_a_thin_network_on_a_terrain_mesh_is_warned_as_on_a_height_field(tmp_path,
                                                                          capsys):
    """Counting images and lines needs no height field: two photos over a terrain mesh
    are warned of by designer check and by the Flight panel (before any analysis over
    the terrain, which a mesh does not have) in the words used on a height field."""
    from designer.gui.state.derived import compute_stations, compute_targets, compute_terrain
    from designer.gui.state.hard_cases import hard_case_lines
    from designer.project import load_project

    project = scenes.surveyed_at_true(scenes.tiny_survey(n_photos=2))
    on_field = [e.split(">: ", 1)[1] for e in _check(tmp_path / "field", project, capsys)
                if "<trajectory>:" in e]
    assert len(on_field) == 1 and on_field[0].startswith(THIN["zero overlap"][0][14:])
    mesh_path = scenes.on_a_terrain_mesh(project, tmp_path / "mesh")
    assert main(["check", str(mesh_path)]) == 0
    err = capsys.readouterr().err.splitlines()
    assert [e for e in err if "<trajectory>:" in e] == [
        f"warning: {mesh_path}: <trajectory>: {on_field[0]}"], err
    assert not [e for e in err if "<texture>:" in e], err  # the GSD needs a height field

    mesh_project = load_project(mesh_path)
    terrain = compute_terrain(mesh_project, mesh_path.parent)
    lines = hard_case_lines(mesh_project, compute_targets(mesh_project, None), None,
                            compute_stations(mesh_project, terrain))
    (panel,) = [x for x in lines if "2 images" in x]
    message = on_field[0].split("; ", 1)[0]
    assert panel.startswith(f"{message}; ") and "Flight panel" in panel, lines


def test_a_thick_network_has_no_network_warning(tmp_path, capsys):
    err = _check(tmp_path, scenes.tiny_survey(n_photos=6), capsys)
    assert not [e for e in err if "<trajectory>" in e or "<flight-plan>" in e], err
