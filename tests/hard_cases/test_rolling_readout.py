"""A rolling-shutter readout as long as the frame interval (docs/hard-cases.md): the rows
of one image would still be read when the next exposure starts. With a declared
trigger-interval-s validation refuses it (tests/world/test_rolling_shutter.py); without
one, the interval is the time line's — two photos 1 m apart at 10 m/s, 0.1 s — and
``designer render`` refuses it before Blender starts, in one line naming the images and
the fix; a readout a little shorter is prepared as usual."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from designer.project.load import load_project
from designer.render.job import prepare_job
from tests.synthetic import write_project_file
from tests.world.rolling_helpers import rolling_project

ROOT = Path(__file__).resolve().parents[2]
FRAME_INTERVAL_S = 0.1  # rolling_project: 1 m between its photos at 10 m/s


def test_a_readout_as_long_as_the_frame_interval_is_refused_before_rendering(tmp_path):
    path = write_project_file(rolling_project(readout_s=FRAME_INTERVAL_S), tmp_path)
    run = subprocess.run([sys.executable, "-m", "designer", "render", str(path), "-o",
                          str(tmp_path / "out"), "--progress", "none"], cwd=ROOT,
                         capture_output=True, text=True, timeout=300)
    assert run.returncode == 2, run.stderr
    (line,) = run.stderr.strip().splitlines()
    assert "camera 'cam': readout-s 0.1 s is not shorter than the 0.1 s between " \
           "IMG_000.png and IMG_001.png on the time line" in line
    assert "shorten the readout, fly slower or space the photos further" in line
    assert not list((tmp_path / "out").glob("images/*.png"))


@pytest.mark.parametrize("readout_s", [0.099, 0.03])
def test_a_readout_shorter_than_the_frame_interval_is_prepared(tmp_path, readout_s):
    path = write_project_file(rolling_project(readout_s=readout_s, samples=1), tmp_path)
    prepared = prepare_job(load_project(path), tmp_path, tmp_path / "out")
    assert [rs.readout_s for rs in prepared.frame_shutters] == [readout_s, readout_s]
