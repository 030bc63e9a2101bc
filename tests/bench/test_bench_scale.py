"""``designer bench scale``: the block sizes, the growth exponents and a small run of
the whole command (two tiny blocks end to end, real Blender and COLMAP)."""

from __future__ import annotations

import json
import math
import subprocess
import sys
from pathlib import Path

import pytest

from designer.bench import scale

ROOT = Path(__file__).resolve().parents[2]


def test_a_block_of_240_images_is_planned_with_about_240_images_and_its_gcps():
    from designer.scene.build import build_heightfield
    from designer.survey.project_poses import project_stations

    project = scale.block_project(240, 0.5)
    hf = build_heightfield(project.scene.terrain, Path("."), project.crs)
    n = len(project_stations(project, hf)[0])
    assert abs(n - 240) <= 0.05 * 240
    assert project.render.resolution_scale == 0.125
    roles = [t.role for t in project.scene.targets.targets]
    # the 3 x 3 control grid of a 200 m block and the 2 x 2 check points between
    assert (roles.count("control"), roles.count("check")) == (9, 4)
    # the 60-image block is the example itself
    from designer.project.templates import template

    example = template("survey").project
    assert scale.block_project(60).scene == example.scene


def test_the_exponent_is_the_slope_between_the_two_largest_blocks():
    rows = [{"images": n, "stage": "block"} for n in (60, 240, 720)]
    rows += [{"images": n, "stage": "render", "wall_s": 2.0 * n} for n in (60, 240, 720)]
    rows += [{"images": n, "stage": "matching", "wall_s": 0.01 * n ** 1.5}
             for n in (60, 240, 720)]
    rows += [{"images": n, "stage": "plan", "wall_s": 3.0 if n < 720 else None}
             for n in (60, 240, 720)]
    e = scale.exponents(rows)
    assert e["render"] == pytest.approx(1.0)
    assert e["matching"] == pytest.approx(1.5)
    assert "plan" not in e


def test_the_exponent_counts_the_images_a_block_rendered():
    """A block laid out for 240 images whose plan rendered 230: the ratio is 720 / 230."""
    rows = [{"images": 240, "stage": "block", "rendered": 230},
            {"images": 720, "stage": "block", "rendered": 720},
            {"images": 240, "stage": "render", "wall_s": 230.0},
            {"images": 720, "stage": "render", "wall_s": 720.0}]
    assert scale.exponents(rows)["render"] == pytest.approx(1.0)


@pytest.mark.blender
@pytest.mark.slow
def test_bench_scale_runs_two_small_blocks_end_to_end(tmp_path):
    proc = subprocess.run([sys.executable, "-m", "designer", "bench", "scale",
                           "--sizes", "12,24", "--scale", "0.25"], cwd=tmp_path,
                          capture_output=True, text=True, timeout=900)
    assert proc.returncode == 0, proc.stderr[-2000:]
    table = proc.stdout
    for stage in scale.STAGES:
        assert any(line.startswith(stage + " ") for line in table.splitlines()), stage
    assert "between the 12 and 24 blocks" in table
    assert "render estimated by designer plan before it ran: 12 images" in table
    data = json.loads((tmp_path / "bench-scale" / "scale.json").read_text())
    rows = data["rows"]
    for n in (12, 24):
        stages = {r["stage"]: r for r in rows if r["images"] == n}
        for stage in scale.STAGES:
            assert stages[stage]["wall_s"] > 0, (n, stage)
        for stage in ("render", "features", "matching", "mapping", "fusion", "compare"):
            assert stages[stage]["peak_mb"] > 50, (n, stage)  # Python and COLMAP at least
        assert stages["render"]["estimate_s"] > 0  # designer plan's, before the render
        block = stages["block"]
        assert block["registered"] >= 0.9 * n
        assert math.isfinite(block["check_rmse_z_gsd"]) and block["check_rmse_z_gsd"] < 3
        assert block["dense_points"] > 1000
    assert set(data["exponents"]) == set(scale.STAGES)
    assert (tmp_path / "bench-scale" / "scale.png").stat().st_size > 10_000
    # each block's files stay for the user to open
    assert (tmp_path / "bench-scale" / "block-24" / "reconstruction" / "dense.ply").is_file()


def test_bad_sizes_are_refused_with_the_fix(tmp_path):
    proc = subprocess.run([sys.executable, "-m", "designer", "bench", "scale",
                           "--sizes", "60,abc"], cwd=tmp_path, capture_output=True, text=True)
    assert proc.returncode == 2
    assert "--sizes 60,abc" in proc.stderr and "e.g. 60,240,720" in proc.stderr
    assert not (tmp_path / "bench-scale").exists()
    other = subprocess.run([sys.executable, "-m", "designer", "bench", "core",
                            "--sizes", "60"], cwd=tmp_path, capture_output=True, text=True)
    assert other.returncode == 2 and "only 'designer bench scale'" in other.stderr


def test_the_block_side_factor_gives_the_bench_blocks():
    """A study's ``block-side-m`` and the scale bench make the same blocks."""
    from designer.study.factors import FACTORS
    from designer.study.templates import template_base

    factor = FACTORS["block-side-m"]
    base = template_base("block-size")
    assert factor.get(base) == 70.0
    big = factor.set(base, 352.0)
    bench = scale.block_project(720, 0.25)
    assert factor.get(big) == 352.0
    assert big.scene.terrain == bench.scene.terrain
    assert big.scene.targets.targets == bench.scene.targets.targets
    assert big.trajectory.flight_plan.area == bench.trajectory.flight_plan.area
    assert big.render.resolution_scale == bench.render.resolution_scale
