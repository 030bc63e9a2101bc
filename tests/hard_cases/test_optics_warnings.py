"""A pinhole camera wider than any survey camera, or a flight whose GSD is coarser than
any survey flies, is warned of by ``designer check`` and the window (issue #53, finding
2: a focal length of 0.001 mm — 172° across, a GSD of 12,061 cm — passed silently)."""

from __future__ import annotations

import contextlib
import dataclasses
import io
import re

import pytest

from designer.cli.main import main


def _survey(tmp_path, focal_mm: float):
    path = tmp_path / "s.xml"
    with contextlib.redirect_stdout(io.StringIO()):
        assert main(["new", str(path), "--template", "survey"]) == 0
    text = re.sub(r"<focal-length-mm>[^<]*<", f"<focal-length-mm>{focal_mm}<",
                  path.read_text())
    out = tmp_path / "fov.xml"
    out.write_text(text)
    return out


def test_check_warns_of_a_0_001_mm_lens(tmp_path, capsys):
    path = _survey(tmp_path, 0.001)
    assert main(["check", str(path)]) == 0
    err = capsys.readouterr().err
    assert (f"warning: {path}: <camera>: camera 'p4p': a 0.001 mm lens on a 13.2 × 8.8 mm "
            "sensor sees 172° across the diagonal (172° × 172°), wider than any survey "
            "camera's (at most 120° for a pinhole lens)") in err, err
    assert "check the focal length (focal-length-mm: the lens's real focal length in mm" \
        in err, err
    assert (f"warning: {path}: <flight-plan>: the flight's GSD is 12,061 cm (50 m above the "
            "ground with camera 'p4p'), coarser than any survey flies (at most 100 cm)") \
        in err, err


def test_the_windows_warnings_name_the_panels(tmp_path):
    from designer.gui.state.hard_cases import hard_case_lines
    from designer.project import load_project

    project = load_project(_survey(tmp_path, 0.001))
    lines = hard_case_lines(project, None, None)
    fov = [w for w in lines if "across the diagonal" in w]
    gsd = [w for w in lines if "coarser than any survey" in w]
    assert fov and fov[0].endswith("check the focal length in the Camera panel (the lens's "
                                   "real focal length in mm, not its 35 mm equivalent)"), lines
    assert gsd and "lower the height above ground in the Flight panel" in gsd[0], lines


@pytest.mark.parametrize("key", [p.key for p in __import__(
    "designer.project.camera_presets", fromlist=["PRESETS"]).PRESETS])
def test_no_survey_camera_preset_is_warned_of(key):
    """Every real camera designer knows, the GoPro as a pinhole (104° across) among them,
    flown at 120 m (the usual ceiling for drones) is silent."""
    from designer.checks.hard_cases import optics_warnings
    from designer.project import model as m
    from designer.project.camera_presets import preset

    camera = preset(key).camera()
    plan = m.FlightPlan(camera=camera.id, image_prefix="I", area=((0, 0), (1, 0), (1, 1)),
                        altitude_agl_m=120.0)
    project = dataclasses.replace(_minimal(), cameras=(camera,),
                                  trajectory=m.Trajectory(flight_plan=plan))
    assert optics_warnings(project) == []


def _minimal():
    from designer.gui.state.files import blank_project

    return blank_project()
