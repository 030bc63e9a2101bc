"""Weak networks end to end (docs/hard-cases.md), on one tiny render of flat ground (the
study template "tiny": 18 images of 160 × 120 px from 12 m, GSD 10 cm, 10 GCP targets,
made flat): self-calibration on flat terrain measures its dome and does not fail;
control on one line is refused by the reconstruction, naming the case and the fix; one
image, one flight line and images without overlap get clear messages from ``designer
reconstruct``, as from ``designer plan`` / ``check`` before any render."""

from __future__ import annotations

import json
import math
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from designer.render.pipeline import render_project
from tests.hard_cases.scenes import flat_tiny
from tests.synthetic import write_project_file

pytestmark = [pytest.mark.blender, pytest.mark.slow]

ROOT = Path(__file__).resolve().parents[2]
#: the tiny template's targets G01 (0, −6), G06 (0, 0) and G04 (0, 6) m: on one line
COLLINEAR = "G01,G04,G06"
#: five targets around the block: good control
SPREAD = "G00,G02,G03,G05,G06"


def designer(*args, timeout=600) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "designer", *map(str, args)], cwd=ROOT,
                          capture_output=True, text=True, timeout=timeout)


@pytest.fixture(scope="module")
def flat_survey(tmp_path_factory):
    folder = tmp_path_factory.mktemp("flat")
    path = write_project_file(flat_tiny(), folder)
    summary = render_project(path, folder / "out", workers=1)
    return path, summary.out_dir


def _errors(run: subprocess.CompletedProcess) -> list[str]:
    """designer's own lines on stderr (COLMAP logs there too)."""
    return [x for x in run.stderr.splitlines() if x.startswith("designer: ")]


def _subset(survey: Path, folder: Path, names) -> Path:
    shutil.copytree(survey / "ground-truth", folder / "ground-truth")
    (folder / "images").mkdir()
    for name in names:
        shutil.copy(survey / "images" / name, folder / "images" / name)
    return folder


def test_flat_terrain_under_radial_self_calibration_measures_its_dome(flat_survey, tmp_path):
    """Free network, k1 and k2 estimated, five control GCPs: the reconstruction succeeds,
    the dense cloud's DoD is fitted with a quadratic surface and its amplitude reported
    (stdout and summary.json, finite, within ±1 m on a 14 m block), and `designer
    compare` measures the cloud against the truth."""
    project, survey = flat_survey
    rec = designer("reconstruct", survey, "-o", tmp_path / "r", "--mode", "free",
                   "--calibration", "radial", "--gcps", "similarity", "--control", SPREAD,
                   "--dense", "cpu", "--max-features", "4096")
    assert rec.returncode == 0 and "Traceback" not in rec.stderr, rec.stderr
    reported = re.search(r"dome amplitude ([+-]\d+\.\d+) m", rec.stdout)
    assert reported, rec.stdout
    summary = json.loads((tmp_path / "r" / "summary.json").read_text())
    dome = summary["dense"]["dome_amplitude_m"]
    assert dome is not None and math.isfinite(dome) and abs(dome) < 1.0, summary["dense"]
    assert float(reported.group(1)) == pytest.approx(dome, abs=5e-4)
    print(f"flat terrain, radial self-calibration: dome amplitude {dome * 1000:+.1f} mm, "
          f"{summary['dense'].get('dome_amplitude_gsd')} GSD")
    cmp = designer("compare", tmp_path / "r" / "dense.ply", project, "-o", tmp_path / "c")
    assert cmp.returncode == 0 and "Traceback" not in cmp.stderr, cmp.stderr
    d = json.loads((tmp_path / "c" / "summary.json").read_text())["distances"]
    assert d["n"] > 1000 and abs(d["median"]) < 0.3, d


def test_control_on_one_line_is_refused_by_the_reconstruction(flat_survey, tmp_path):
    _, survey = flat_survey
    rec = designer("reconstruct", survey, "-o", tmp_path / "r", "--mode", "free",
                   "--gcps", "similarity", "--control", COLLINEAR)
    assert rec.returncode == 2 and "Traceback" not in rec.stderr, rec.stderr
    (line,) = _errors(rec)
    assert "the 3 control GCPs lie on one line" in line and "condition number" in line
    assert "add control off the line" in line


def test_one_image_and_images_without_overlap_are_clear_errors(flat_survey, tmp_path):
    _, survey = flat_survey
    one = _subset(survey, tmp_path / "one", ["IMG_00001.png"])
    rec = designer("reconstruct", one, "-o", tmp_path / "r1", "--mode", "free")
    assert rec.returncode == 2 and "Traceback" not in rec.stderr, rec.stderr
    (line,) = _errors(rec)
    assert "at least 3" in line
    # the ends and the middle of the block: 14 m apart, 10 × 7.5 m footprints
    apart = _subset(survey, tmp_path / "apart",
                    ["IMG_00001.png", "IMG_00006.png", "IMG_00013.png", "IMG_00018.png"])
    rec = designer("reconstruct", apart, "-o", tmp_path / "r2", "--mode", "free")
    assert rec.returncode == 2 and "Traceback" not in rec.stderr, rec.stderr
    (line,) = _errors(rec)
    assert "overlap" in line, line


def test_one_flight_line_reconstructs(flat_survey, tmp_path):
    """The first line of the flight alone (IMG_00001…6, one strip along N): SfM registers
    every image and the similarity onto the control it sees holds to 5 cm (GSD 10 cm)."""
    _, survey = flat_survey
    strip = _subset(survey, tmp_path / "strip", [f"IMG_{k:05d}.png" for k in range(1, 7)])
    rec = designer("reconstruct", strip, "-o", tmp_path / "r", "--mode", "free")
    assert rec.returncode == 0 and "Traceback" not in rec.stderr, rec.stderr
    summary = json.loads((tmp_path / "r" / "summary.json").read_text())
    assert summary["registered"] == 6
    assert summary["control"]["n"] >= 3 and summary["control"]["rmse_z_m"] <= 0.05
