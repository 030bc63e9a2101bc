"""``designer new`` and ``designer check``, in-process and as a separate process."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from designer.cli.main import main
from designer.project.templates import TEMPLATE_NAMES

ROOT = Path(__file__).resolve().parents[2]


@pytest.mark.parametrize("name", TEMPLATE_NAMES)
def test_new_then_check_succeeds_for_every_template(name, tmp_path, capsys):
    path = tmp_path / name / "x.xml"
    assert main(["new", str(path), "--template", name]) == 0
    assert main(["check", str(path)]) == 0
    out = capsys.readouterr().out.splitlines()
    assert out[-1].startswith(f"{path}: valid designer project 1.0 — terrain ")


def test_the_summary_line_of_the_survey(tmp_path, capsys):
    path = tmp_path / "x.xml"
    main(["new", str(path), "--template", "survey"])
    capsys.readouterr()
    assert main(["check", str(path)]) == 0
    assert capsys.readouterr().out == (
        f"{path}: valid designer project 1.0 — terrain procedural 100 x 100 m, 1 camera, "
        "flight plan, 10 GCPs (7 control, 3 check)\n")


def test_new_refuses_to_overwrite_without_force(tmp_path, capsys):
    path = tmp_path / "x.xml"
    path.write_text("mine")
    assert main(["new", str(path), "--template", "psf"]) == 2
    assert "exists; choose another name or add --force" in capsys.readouterr().err
    assert path.read_text() == "mine"
    assert main(["new", str(path), "--template", "psf", "--force"]) == 0
    assert main(["check", str(path)]) == 0


def test_new_refuses_when_a_companion_file_exists(tmp_path, capsys):
    (tmp_path / "cube.obj").write_text("mine")
    assert main(["new", str(tmp_path / "x.xml"), "--template", "validation-cube"]) == 2
    assert not (tmp_path / "x.xml").exists()
    assert (tmp_path / "cube.obj").read_text() == "mine"


def test_new_needs_an_xml_name(tmp_path, capsys):
    assert main(["new", str(tmp_path / "x.txt")]) == 2
    assert "must end in .xml" in capsys.readouterr().err


def test_check_of_a_missing_file(tmp_path, capsys):
    assert main(["check", str(tmp_path / "none.xml")]) == 2
    assert f"{tmp_path / 'none.xml'}:1:1: <project>: no such file" in capsys.readouterr().err


def test_check_of_a_folder(tmp_path, capsys):
    assert main(["check", str(tmp_path)]) == 2
    assert "not a regular file" in capsys.readouterr().err


def test_no_files_skips_the_file_checks(tmp_path, capsys):
    path = tmp_path / "x.xml"
    main(["new", str(path), "--template", "texture"])
    (tmp_path / "texture.png").unlink()
    assert main(["check", str(path)]) == 2
    assert "texture.png' does not exist" in capsys.readouterr().err
    assert main(["check", "--no-files", str(path)]) == 0


def test_new_and_check_as_separate_processes(tmp_path):
    env = {**os.environ, "PYTHONPATH": str(ROOT)}

    def run(*args):
        return subprocess.run([sys.executable, "-m", "designer", *args], cwd=tmp_path,
                              capture_output=True, text=True, env=env, timeout=120)

    made = run("new", "x.xml", "--template", "survey")
    assert made.returncode == 0, made.stderr
    checked = run("check", "x.xml")
    assert checked.returncode == 0, checked.stderr
    assert checked.stdout.startswith("x.xml: valid designer project 1.0 — terrain procedural")


def test_a_gcp_outside_a_utm_extent_is_reported_in_plain_metres(tmp_path, capsys):
    path = tmp_path / "s.xml"
    main(["new", str(path), "--template", "survey"])
    text = path.read_text()
    first = '<true X="511962.0" Y="5405962.0"/>'
    assert first in text
    path.write_text(text.replace(first, '<true X="512100.5" Y="5405962.0"/>', 1))
    capsys.readouterr()
    assert main(["check", str(path)]) == 2
    said = "".join(capsys.readouterr())
    assert "GCP 'GCP01' at X 512100.5, Y 5405962 lies outside" in said, said
    assert "(X 511950..512050, Y 5405950..5406050)" in said, said
    assert "e+0" not in said, said


def test_a_texture_tile_the_scene_builder_refuses_is_refused_by_check(tmp_path, capsys):
    """The example's 20 m tiles at 2.4 mm texels: 8333 texels a side, more than a texture
    the scene builder makes. 'designer check' says so (the limit is the builder's), not
    the render afterwards."""
    from designer.scene.build import MAX_TEXTURE_PX

    path = tmp_path / "s.xml"
    main(["new", str(path), "--template", "survey"])
    text = path.read_text()
    assert 'texel-size-m="0.025"' in text
    path.write_text(text.replace('texel-size-m="0.025"', 'texel-size-m="0.0024"', 1))
    capsys.readouterr()
    assert main(["check", str(path)]) == 2
    said = "".join(capsys.readouterr())
    assert f"more than {MAX_TEXTURE_PX}" in said and "8333" in said, said
