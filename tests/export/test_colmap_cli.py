"""OUT/README.txt's COLMAP steps run verbatim with the colmap command line (Debian's
COLMAP 3.8, CPU only, no display, default thread counts) and give a triangulated model
whose poses are the ground truth — also when the extraction runs on other threads."""

from __future__ import annotations

import os
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest

from designer.render.pipeline import render_project
from tests.synthetic import small_survey, write_project_file

pytestmark = [pytest.mark.blender, pytest.mark.slow,
              pytest.mark.skipif(shutil.which("colmap") is None,
                                 reason="the colmap command line is not installed "
                                        "(scripts/install-system-packages.sh installs it)")]


def readme_commands(out: Path) -> list[str]:
    """The command lines README.txt gives for COLMAP without CUDA, as written."""
    lines = (out / "README.txt").read_text().splitlines()
    start = next(i for i, x in enumerate(lines) if "run in this folder" in x)
    commands = []
    for line in lines[start + 1:]:
        if not line.startswith("    ") or "where COLMAP has CUDA" in line:
            if commands:
                break
            continue
        commands.append(line.strip())
    return commands


@pytest.fixture(scope="module")
def rendered(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("colmap-cli")
    project = write_project_file(small_survey(n_photos=6, samples=4, size_px=(640, 480)),
                                 tmp / "p")
    return render_project(project, tmp / "out", workers=1).out_dir


def _run(out: Path, commands: list[str]) -> None:
    env = {k: v for k, v in os.environ.items() if k != "DISPLAY"}  # no display at all
    for command in commands:
        done = subprocess.run(command, shell=True, cwd=out, env=env, capture_output=True,
                              text=True, timeout=600)
        assert done.returncode == 0, (command, done.stdout[-2000:], done.stderr[-2000:])


def _poses(folder: Path) -> dict[str, tuple[int, np.ndarray, np.ndarray]]:
    import pycolmap

    rec = pycolmap.Reconstruction(str(folder))
    out = {}
    for image_id, image in rec.images.items():
        pose = image.cam_from_world()
        out[image.name] = (image_id, pose.rotation.matrix(), pose.translation)
    return out, rec.num_points3D()


@pytest.mark.parametrize("threads", [None, 1])
def test_readme_colmap_steps_give_the_true_model(rendered, tmp_path, threads):
    out = tmp_path / "out"
    shutil.copytree(rendered, out, symlinks=True)
    commands = readme_commands(out)
    assert [c.split()[:2] for c in commands if c.startswith("colmap")] == [
        ["colmap", "feature_extractor"], ["colmap", "matches_importer"],
        ["colmap", "point_triangulator"], ["colmap", "image_undistorter"]]
    if threads is not None:  # the same steps on one thread: the same IDs, the same model
        commands = [c + (f" --SiftExtraction.num_threads {threads}"
                         if "feature_extractor" in c else
                         f" --SiftMatching.num_threads {threads}"
                         if "matches_importer" in c else "") for c in commands]
    _run(out, commands)
    truth, _ = _poses(out / "ground-truth" / "colmap")
    model, n_points = _poses(out / "triangulated")
    assert sorted(model) == sorted(truth)
    for name, (image_id, R, t) in model.items():
        true_id, true_R, true_t = truth[name]
        assert image_id == true_id
        assert np.abs(R - true_R).max() < 1e-9 and np.abs(t - true_t).max() < 1e-6
    assert n_points > 100
    assert (out / "dense" / "images").is_dir()
    # the ground truth itself is untouched (the steps work on a copy of the database)
    assert (out / "ground-truth" / "colmap" / "database.db").read_bytes() == (
        rendered / "ground-truth" / "colmap" / "database.db").read_bytes()


def test_every_designer_command_in_readme_is_one_designer_takes(rendered):
    """README.txt's designer lines parse with designer's own command line."""
    from designer.cli.main import build_parser

    parser = build_parser()
    lines = [x.split("   ")[0].strip() for x in (rendered / "README.txt").read_text()
             .splitlines() if x.strip().startswith("designer ")]
    assert {x.split()[1] for x in lines} >= {"reconstruct", "compare", "check-output"}
    for line in lines:
        args = parser.parse_args(line.split()[1:])
        assert callable(args.func), line
