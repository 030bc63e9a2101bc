"""Cloud shadows on real Cycles renders: they drift by wind × Δt between two photos of
the same spot, dim the direct sun by the set depth, reach the ground truth, and a
project without them renders byte for byte as before."""

from __future__ import annotations

import json
import math
from dataclasses import replace
from pathlib import Path

import cv2
import numpy as np
import pytest

from designer.project import model as m
from designer.render.pipeline import render_project
from tests.synthetic import write_project_file
from tests.world.helpers import timed_survey

WIND_M_S, DT_S = 2.0, 0.5
CLOUDS = m.CloudShadows(cover=0.5, size_m=8.0, softness_m=0.3, depth=0.7,
                        wind_speed_m_s=WIND_M_S, wind_direction_deg=60.0, seed=3)


def _project(clouds: m.CloudShadows | None) -> m.Project:
    p = timed_survey((0.0, DT_S), sun_over_time=False, pixel_pitch_mm=0.02)
    lighting = replace(p.scene.lighting, clouds=clouds)
    return replace(p, scene=replace(p.scene, lighting=lighting, targets=None),
                   render=replace(p.render, samples=4))


def _render(project: m.Project, folder: Path) -> Path:
    out = folder / "out"
    render_project(write_project_file(project, folder), out)
    return out


def _linear(path: Path) -> np.ndarray:
    v = cv2.imread(str(path), cv2.IMREAD_UNCHANGED).astype(np.float64)
    v = v / (65535.0 if v.max() > 255 else 255.0)
    v = np.where(v <= 0.04045, v / 12.92, ((v + 0.055) / 1.055) ** 2.4)
    return v.mean(axis=2)


@pytest.fixture(scope="module")
def rendered(tmp_path_factory):
    root = tmp_path_factory.mktemp("clouds")
    return _render(_project(CLOUDS), root / "cloudy"), _render(_project(None), root / "clear")


def _ratios(rendered):
    cloudy, clear = rendered
    return [_linear(cloudy / "images" / f"IMG_{k:03d}.png") / np.maximum(
        _linear(clear / "images" / f"IMG_{k:03d}.png"), 1e-3) for k in (0, 1)]


def test_a_shadow_drifts_by_wind_times_the_time_between_photos(rendered):
    r0, r1 = _ratios(rendered)
    window = cv2.createHanningWindow(r0.shape[::-1], cv2.CV_64F)
    (du, dv), _ = cv2.phaseCorrelate(r0, r1, window)
    gsd_m = json.loads((rendered[0] / ".designer-job/job.json").read_text())["frames"][0][
        "gsd_m"]
    az = math.radians(CLOUDS.wind_direction_deg)
    # nadir, kappa 0: image right = east, image down = south
    expected_u = WIND_M_S * DT_S * math.sin(az) / gsd_m
    expected_v = -WIND_M_S * DT_S * math.cos(az) / gsd_m
    assert math.hypot(expected_u, expected_v) > 5  # a shift worth measuring
    assert abs(du - expected_u) < 1.0 and abs(dv - expected_v) < 1.0, (du, dv, expected_u,
                                                                       expected_v)


def test_full_shadow_removes_the_depth_share_of_the_direct_sun(rendered):
    r0, _ = _ratios(rendered)
    sun = math.sin(math.radians(55.0)) * 4.0  # small_survey's sun: 55 deg, strength 4
    direct_share = sun / (sun + 1.0)
    expected = 1.0 - CLOUDS.depth * direct_share
    core = np.percentile(r0, 2)  # deep inside the shadows
    open_ground = np.percentile(r0, 98)
    assert abs(open_ground - 1.0) < 0.03, open_ground
    assert abs(core - expected) < 0.03, (core, expected)
    # both states are common: cover 0.5 leaves a real share of the view in shadow
    assert 0.1 < np.mean(r0 < (1 + expected) / 2) < 0.9


def test_the_ground_truth_lists_each_images_drift(rendered):
    text = (rendered[0] / "ground-truth/cloud_shadows.csv").read_text().splitlines()
    assert text[0].startswith("image,time_s,shift_east_m,shift_north_m,cover")
    row = text[2].split(",")
    assert row[0] == "IMG_001.png" and float(row[1]) == DT_S
    az = math.radians(CLOUDS.wind_direction_deg)
    assert float(row[2]) == pytest.approx(WIND_M_S * DT_S * math.sin(az), abs=1e-6)
    assert float(row[3]) == pytest.approx(WIND_M_S * DT_S * math.cos(az), abs=1e-6)
    assert not (rendered[1] / "ground-truth/cloud_shadows.csv").exists()


def test_without_clouds_the_images_and_ground_truth_are_byte_identical(tmp_path):
    """The clear project's files equal those of a project file written without the
    lighting's new child (the static ideal)."""
    project = _project(None)
    a = _render(project, tmp_path / "a")
    folder = tmp_path / "b"
    path = write_project_file(project, folder)
    assert "cloud-shadows" not in path.read_text()
    b = folder / "out"
    render_project(path, b)
    names = sorted(p.relative_to(a).as_posix() for p in a.rglob("*")
                   if p.is_file() and ".designer-job" not in p.parts and p.name != "manifest.json")
    assert any(n.endswith(".png") for n in names)
    for name in names:
        assert (a / name).read_bytes() == (b / name).read_bytes(), name


def test_resume_renders_again_when_the_clouds_change(tmp_path):
    project = _project(CLOUDS)
    path = write_project_file(project, tmp_path)
    out = tmp_path / "out"
    render_project(path, out)
    same = render_project(path, out, resume=True)
    changed = replace(project, scene=replace(project.scene, lighting=replace(
        project.scene.lighting, clouds=replace(CLOUDS, seed=4))))
    write_project_file(changed, tmp_path)
    again = render_project(path, out, resume=True)
    assert same.report.skipped == [0, 1]
    assert again.report.skipped == [] and set(again.stale) == {0, 1}
    assert all(parts == ["lighting"] for parts in again.stale.values())  # the clouds
