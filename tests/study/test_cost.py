"""A run's cost in a surveyor's units (flight minutes, images, GCPs) as planned, the cost
axis of a study file, the variants' labels and the front rule of the accuracy-against-cost
figure. No rendering: the tiny study's base is planned, never rendered."""

from __future__ import annotations

import subprocess
import sys
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from designer.project import model as m
from designer.project.problems import ProjectError
from designer.study.cost import (
    COSTS,
    DEFAULT_SPEED_M_S,
    StageClock,
    accuracy_metric,
    add_reused_cpu,
    flight_minutes,
    path_length_m,
)
from designer.study.front import Spread, VariantPoint, dominates, front, front_rule
from designer.study.labels import level_label, short_labels, variant_labels
from designer.study.templates import template_base, write_template
from designer.study.xml import parse_study, read_study

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def tiny_platform():
    """The tiny base project and its platform stations (the flight, in order)."""
    from designer.gui.state import derived
    from designer.survey.project_poses import project_images

    project = template_base("tiny")
    hf = derived.compute_terrain(project, ROOT).heightfield
    return project, project_images(project, hf).platform


def test_flight_minutes_without_a_time_line_are_the_path_at_the_default_speed(
        tmp_path, tiny_platform):
    from designer.study.stages import plan_run

    project, platform = tiny_platform
    info = plan_run(project, tmp_path / "run")
    path_m = path_length_m(np.array([s.C_world for s in platform]))
    assert path_m > 30  # 3 lines over a 14 m square, with the legs between them
    assert info["flight_min_source"] == f"path at {DEFAULT_SPEED_M_S:g} m/s"
    assert info["flight_min"] == pytest.approx(path_m / DEFAULT_SPEED_M_S / 60, rel=1e-9)
    assert len(info["images"]) == len(platform)
    # every target is surveyed; the processing takes 4 of the 10 as control
    assert (info["gcps"], info["control_gcps"]) == (10, 4)


def test_flight_minutes_with_a_time_line_are_its_last_photo_time(tmp_path, tiny_platform):
    from designer.study.stages import plan_run
    from designer.survey.timeline import station_times_s

    project, platform = tiny_platform
    time_line = m.TimeLine("2026-06-21T09:30:00Z", speed_m_s=4.0, turn_s=5.0)
    timed = replace(project, trajectory=replace(project.trajectory, time_line=time_line))
    info = plan_run(timed, tmp_path / "run")
    assert info["flight_min_source"] == "time line"
    seconds = station_times_s(platform, time_line)[-1]
    assert info["flight_min"] == pytest.approx(seconds / 60, rel=1e-9)
    # slower than the default speed, and the turns between the lines count
    lines = len({s.line_index for s in platform})
    path_m = path_length_m(np.array([s.C_world for s in platform]))
    assert seconds == pytest.approx(path_m / 4.0 + 5.0 * (lines - 1), rel=1e-9)


def test_a_rig_multiplies_the_images_not_the_flight(tmp_path, tiny_platform):
    from designer.core.rig import PENTA_MOUNTS
    from designer.study.stages import plan_run

    project, platform = tiny_platform
    rig = m.Rig("penta", tuple(m.Mount("cam", s, o, ph, k) for s, o, ph, k in PENTA_MOUNTS))
    rigged = replace(project, trajectory=replace(
        project.trajectory, rigs=(rig,),
        flight_plan=replace(project.trajectory.flight_plan, camera="penta")))
    info = plan_run(rigged, tmp_path / "run")
    assert len(info["images"]) == 5 * len(platform)
    path_m = path_length_m(np.array([s.C_world for s in platform]))
    assert info["flight_min"] == pytest.approx(path_m / DEFAULT_SPEED_M_S / 60, rel=1e-9)


def test_flight_minutes_of_plain_numbers():
    centres = np.array([[0, 0, 10], [30, 40, 10], [30, 40, 10], [30, 40, 22]], float)
    assert path_length_m(centres) == pytest.approx(62.0)
    assert flight_minutes(centres, None) == (pytest.approx(62.0 / DEFAULT_SPEED_M_S / 60),
                                             f"path at {DEFAULT_SPEED_M_S:g} m/s")
    assert flight_minutes(centres, [0.0, 30.0, 30.0, 120.0]) == (2.0, "time line")


def test_gcp_counts_follow_the_processing():
    from designer.study.cost import gcp_counts

    p = template_base("tiny")
    assert gcp_counts(p) == (10, 4)
    gcps = p.processing.gcps
    ids = replace(p, processing=replace(p.processing, gcps=replace(
        gcps, control=m.ControlSelection(ids=("G00", "G01", "G02")))))
    assert gcp_counts(ids) == (10, 3)
    roles = replace(p, processing=replace(p.processing, gcps=replace(gcps, control=None)))
    assert gcp_counts(roles) == (10, 10)  # every target of the template is control
    none = replace(p, processing=replace(p.processing, gcps=replace(gcps, mode="none")))
    assert gcp_counts(none) == (10, 0)


STUDY = """<?xml version="1.0"?>
<study xmlns="urn:designer:project:1" schema-version="1.0" name="c">
  <base-project file="tiny-base.xml"/>
  <factor name="marking-sigma-px"><values>0.2 2</values></factor>
  <metrics>check_rmse_z_m</metrics>
{cost}</study>
"""


def test_the_cost_axis_is_read_written_back_and_defaults_to_flight_minutes(tmp_path):
    from designer.study.writer import study_to_xml

    assert parse_study(STUDY.format(cost="").encode()).cost == "flight-minutes"
    for name in COSTS:
        study = parse_study(STUDY.format(cost=f"  <cost>{name}</cost>\n").encode())
        assert study.cost == name
        again = parse_study(study_to_xml(study).encode())
        assert again.cost == name
    # the default is not written: files without <cost> stay as they were
    assert "<cost>" not in study_to_xml(parse_study(STUDY.format(cost="").encode()))


def test_the_schema_lists_every_cost_axis():
    from lxml import etree

    from designer.study.xml import study_schema_path

    tree = etree.parse(str(study_schema_path()))
    ns = {"xs": "http://www.w3.org/2001/XMLSchema"}
    cost = tree.find(".//xs:element[@name='cost']", ns)
    assert cost.get("type") == "d:Cost"  # the named type the generator makes of COSTS
    cost_type = tree.find("xs:simpleType[@name='Cost']", ns)
    values = [e.get("value") for e in cost_type.iterfind(".//xs:enumeration", ns)]
    assert values == list(COSTS)


def test_a_bad_cost_is_a_located_one_line_error_and_exit_2(tmp_path):
    write_template("tiny", tmp_path / "tiny.xml")
    path = tmp_path / "bad.xml"
    path.write_text(STUDY.format(cost="  <cost>dollars</cost>\n"))
    with pytest.raises(ProjectError) as info:
        read_study(path)
    lines = str(info.value).splitlines()
    assert len(lines) == 1
    assert lines[0].startswith(f"{path}:6:3: <cost>: value 'dollars' is not allowed; use one "
                               "of: flight-minutes, images, gcps"), lines[0]
    proc = subprocess.run([sys.executable, "-m", "designer", "study", "run", str(path), "-o",
                           str(tmp_path / "out")], cwd=ROOT, capture_output=True, text=True)
    assert proc.returncode == 2
    assert f"{path}:6:3: <cost>: value 'dollars' is not allowed" in proc.stderr
    assert not (tmp_path / "out").exists()


def test_levels_read_as_a_surveyor_says_them():
    assert level_label("altitude-m", "80") == "altitude 80 m"
    assert level_label("control-count", "5") == "control-count 5"
    assert level_label("gcp-mode", "bundle") == "gcp-mode bundle"
    assert level_label("sun-elevation-deg", "40") == "sun-elevation 40°"
    assert level_label("flight-speed-m-s", "8") == "flight-speed 8 m/s"
    assert level_label("front-overlap-percent", "80") == "front-overlap 80 %"
    assert level_label("vegetation-density-per-m2", "0.5") == "vegetation-density 0.5 /m²"
    assert level_label("k1", "0.1") == "k1 0.1"


def _rows(levels: list[dict]) -> list[dict]:
    return [{"variant": v, **{f"factor:{k}": x for k, x in lv.items()}}
            for v, lv in enumerate(levels)]


def test_variants_are_labelled_by_the_levels_that_set_them_apart():
    oat = _rows([{"altitude-m": "30", "control-count": "5"},
                 {"altitude-m": "40", "control-count": "5"},
                 {"altitude-m": "30", "control-count": "8"}])
    assert variant_labels(oat, ["altitude-m", "control-count"], "one-at-a-time") == {
        0: "base: altitude 30 m, control-count 5", 1: "altitude 40 m", 2: "control-count 8"}
    ff = _rows([{"control-count": c, "gcp-mode": g, "k1": "0"}
                for c in ("3", "5") for g in ("similarity", "bundle")])
    labels = variant_labels(ff, ["control-count", "gcp-mode", "k1"], "full-factorial")
    assert labels[3] == "control-count 5, gcp-mode bundle"  # k1 never changes
    short, key = short_labels(ff, ["control-count", "gcp-mode", "k1"])
    assert (short[3], key) == ("5 · bundle", "control-count · gcp-mode")


def _point(v, cost, error) -> VariantPoint:
    c = cost if isinstance(cost, tuple) else (cost, cost)
    e = error if isinstance(error, tuple) else (error, error)
    return VariantPoint(v, f"v{v}", 3, Spread((c[0] + c[1]) / 2, *c), Spread((e[0] + e[1]) / 2,
                                                                               *e))


def test_the_front_holds_only_differences_beyond_the_replicate_spread():
    # equal costs (a count no factor changes): the clearly more accurate variant wins,
    # the overlapping ones stay
    a, b, c = _point(0, 2.0, (0.05, 0.06)), _point(1, 2.0, (0.03, 0.04)), \
        _point(2, 2.0, (0.035, 0.045))
    assert dominates(b, a) and not dominates(b, c) and not dominates(c, b)
    assert [p.variant for p in front([a, b, c])] == [1, 2]
    # wall seconds spread from 63 to 110 s for the same work: no cost difference, so
    # accuracy beyond its spread decides, whichever ran while the machine was quiet
    slow, quick = _point(0, (90, 110), (0.02, 0.03)), _point(1, (63, 95), (0.035, 0.05))
    assert dominates(slow, quick) and not dominates(quick, slow)
    # cheaper beyond the spread and not less accurate beyond it; cheaper but clearly
    # less accurate: both stay
    cheap = _point(2, (40, 50), (0.036, 0.045))
    assert dominates(cheap, quick) and not dominates(cheap, slow)
    assert not dominates(slow, cheap)
    assert [p.variant for p in front([slow, quick, cheap])] == [2, 0]


def test_a_measured_cost_without_replicates_draws_no_front():
    one = [replace(_point(v, 60.0 + v, 0.05 - 0.01 * v), runs=1) for v in range(3)]
    drawn, rule = front_rule(one, planned_cost=False)
    assert not drawn and "give replicates" in rule
    assert front_rule(one, planned_cost=True)[0]
    assert front_rule([_point(0, 60.0, 0.05)], planned_cost=False)[0]


def test_reused_features_and_models_count_what_their_computation_cost():
    rows = [{"features_group": "g", "sfm_group": "s", "reconstruct_cpu_spent_s": 30.0,
             "features_cpu_s": 12.0, "matching_cpu_s": 6.0, "sfm_cpu_s": 4.0,
             "features_reused": False, "matches_reused": False, "sfm_reused": False},
            {"features_group": "g", "sfm_group": "s", "reconstruct_cpu_spent_s": 9.0,
             "features_reused": "True", "matches_reused": "True", "sfm_reused": "True"},
            # another calibration: the same features and matches, its own SfM
            {"features_group": "g", "sfm_group": "t", "reconstruct_cpu_spent_s": 14.0,
             "sfm_cpu_s": 5.0, "features_reused": True, "matches_reused": True,
             "sfm_reused": False},
            {"features_group": "h", "sfm_group": "u", "reconstruct_cpu_spent_s": 20.0,
             "matching_cpu_s": 5.0, "features_reused": True, "matches_reused": False},
            {"features_group": "g", "reconstruct_cpu_spent_s": None}]
    add_reused_cpu(rows)
    assert [r["reconstruct_cpu_s"] for r in rows] == [30.0, 31.0, 32.0, 20.0, None]


def test_the_stage_clock_splits_at_the_reconstruction_log_lines():
    clock = StageClock()
    clock.marks = [("features: 18 images", 1.0), ("matching: 40 image pairs", 4.0),
                   ("incremental SfM", 6.5), ("georeferenced on 4 control GCPs", 8.0)]
    assert clock.step_cpu_s("features", 9.0) == 3.0
    assert clock.step_cpu_s("matching", 9.0) == 2.5
    assert clock.step_cpu_s("sfm", 9.0) == 1.5
    clock.marks = [("SfM model reused from the feature cache", 1.0)]  # all from the cache
    assert clock.step_cpu_s("features", 9.0) is None
    assert clock.step_cpu_s("sfm", 9.0) is None


def test_the_accuracy_metric_is_never_a_cost():
    assert accuracy_metric(["registered", "flight_min", "check_rmse_z_m"]) == "check_rmse_z_m"
    assert accuracy_metric(["registered"]) == "registered"


def test_a_computed_step_is_recorded_as_it_ends_for_the_runs_that_reuse_it(tmp_path):
    """The reconstruction that extracted the features may be killed before it finishes:
    what the extraction cost is kept as soon as it ends."""
    from designer.study.cost import record_step_cpu, recorded_step_cpu

    heard = []
    clock = StageClock(lambda step, cpu_s: heard.append((step, cpu_s)))
    clock("features: 18 images")
    sum(k * k for k in range(200_000))  # some CPU for the step
    clock("matching: 40 image pairs")
    assert [s for s, _ in heard] == ["features"] and heard[0][1] > 0
    clock("incremental SfM")
    assert [s for s, _ in heard] == ["features", "matching"]
    root = tmp_path / "step-cpu"
    record_step_cpu(root / "g", "proc1", "features", 12.0)
    record_step_cpu(root / "g", "proc1", "matching", 6.0)
    record_step_cpu(root / "g", "proc2", "features", 14.0)
    recorded = recorded_step_cpu(root)
    assert recorded == {("g", "features"): [12.0, 14.0], ("g", "matching"): [6.0]}
    rows = [{"features_group": "g", "reconstruct_cpu_spent_s": 1.0, "features_reused": True,
             "matches_reused": True}]
    assert add_reused_cpu(rows, recorded)[0]["reconstruct_cpu_s"] == 1.0 + 13.0 + 6.0
    assert recorded_step_cpu(tmp_path / "nowhere") == {}
