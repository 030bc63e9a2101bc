"""The study writer (study model → study file) read back by the study reader, and the
Study panel's Qt-free planning figures against the example studies' measured counts."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import pytest

from designer.study.design import plan_study
from designer.study.spec import BaseProject, FactorSpec, Replicates, Study
from designer.study.templates import write_template
from designer.study.writer import study_to_xml, write_study
from designer.study.xml import parse_study, read_study

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = sorted((ROOT / "resources" / "studies").glob("*.xml"))


def _content(study: Study) -> Study:
    """The study without the positions of its elements."""
    return replace(study, where=None, base=replace(study.base, where=None),
                   replicates=replace(study.replicates, where=None),
                   factors=tuple(replace(f, where=None, values_where=None)
                                 for f in study.factors))


@pytest.mark.parametrize("path", [p for p in EXAMPLES if not p.stem.endswith("-base")],
                         ids=lambda p: p.stem)
def test_every_example_study_round_trips(path):
    study = read_study(path)
    again = parse_study(study_to_xml(study).encode(), "again.xml", study.source)
    assert _content(again) == _content(study)


def test_a_study_built_in_code_round_trips_with_an_inline_base(tmp_path):
    write_template("tiny", tmp_path / "tiny.xml")
    base_xml = (tmp_path / "tiny-base.xml").read_bytes()
    study = Study(
        name="marks+sun", base=BaseProject(inline_xml=base_xml),
        factors=(FactorSpec("marking-sigma-px", ("0.2", "2"), "how well <GCPs> are marked"),
                 FactorSpec("sun-elevation-deg", ("30", "40"))),
        design="full-factorial", replicates=Replicates(3, ("marking-error", "survey-error")),
        metrics=("check_rmse_z_m", "cloud_nmad_m"), description="a & b < c")
    path = write_study(study, tmp_path / "sub" / "study.xml")
    again = read_study(path)
    assert again.name == "marks+sun" and again.description == "a & b < c"
    assert again.factors[0].description == "how well <GCPs> are marked"
    assert _content(replace(again, base=BaseProject(), source=None)) == \
        _content(replace(study, base=BaseProject()))
    plan = plan_study(again)  # the inline project is a valid, runnable base
    assert plan.n_variants == 4 and len(plan.runs) == 12
    assert plan.base == plan_study(read_study(tmp_path / "tiny.xml")).base


def test_a_base_file_is_written_relative_to_the_study(tmp_path):
    write_template("tiny", tmp_path / "projects" / "tiny.xml")
    study = read_study(tmp_path / "projects" / "tiny.xml")
    path = write_study(study, tmp_path / "studies" / "copy.xml",
                       base_path=tmp_path / "projects" / "tiny-base.xml")
    again = read_study(path)
    assert again.base.file == "../projects/tiny-base.xml"
    assert len(plan_study(again).runs) == len(plan_study(study).runs)


def test_levels_with_spaces_are_refused():
    study = Study("s", BaseProject(file="b.xml"), (FactorSpec("texture-file", ("a b.png",)),))
    with pytest.raises(ValueError, match="has a space"):
        study_to_xml(study)


def test_typed_levels_and_ranges_match_the_reader():
    from designer.gui.state.study_data import parse_levels

    assert parse_levels("3 4, 6;8") == ("3", "4", "6", "8")
    xml = ('<study xmlns="urn:designer:project:1" schema-version="1.0" name="r">'
           '<base-project file="b.xml"/><factor name="k1"><range start="-0.1" stop="0.25" '
           'step="0.05"/></factor></study>')
    assert parse_levels("-0.1:0.25:0.05") == parse_study(xml.encode()).factors[0].values
    for bad, message in (("", "no levels"), ("1:2", "START:STOP:STEP"),
                         ("5:1:1", "below start"), ("0:1:0", "greater than 0"),
                         ("a:b:c", "three numbers"), ("0:1e6:0.1", "too many")):
        with pytest.raises(ValueError, match=message):
            parse_levels(bad)


@pytest.mark.parametrize("name, counts", [
    # measured runs (docs/studies.md; tests/study/test_study.py for tiny):
    # (variants, runs, renders, reconstructions)
    ("gcp-count", (5, 15, 1, 15)), ("flight-geometry", (12, 24, 3, 24)),
    ("altitude", (4, 8, 4, 8)), ("rolling-shutter", (4, 4, 2, 4)),
    ("rig-obliques", (4, 4, 2, 4)), ("tiny", (4, 4, 2, 4))])
def test_the_panel_counts_renders_as_the_study_run_does(tmp_path, name, counts):
    from dataclasses import replace

    from designer.gui.state import derived
    from designer.gui.state.study_data import plan_cost
    from designer.render_time.model import REFERENCE

    path = ROOT / "resources" / "studies" / f"{name}.xml"
    if name == "tiny":
        path = write_template("tiny", tmp_path / "tiny.xml")[0]
    plan = plan_study(read_study(path))
    hf = derived.compute_terrain(plan.base, plan.base_dir).heightfield
    cost = plan_cost(plan, hf, speed=REFERENCE)
    assert (cost.variants, cost.runs, cost.renders, cost.reconstructions) == counts
    assert cost.render_s > cost.renders * REFERENCE.fixed_s
    # a machine half as fast: every coefficient doubled, the render estimate doubles
    slow = replace(REFERENCE, **{k: 2 * getattr(REFERENCE, k) for k in (
        "terrain_cpu_s_per_mp_sample", "background_cpu_s_per_mp_sample", "post_s_per_mp",
        "fixed_s", "bake_s_per_mp")})
    twice = plan_cost(plan, hf, speed=slow)
    assert twice.render_s == pytest.approx(2 * cost.render_s)
    assert twice.reconstruct_s == cost.reconstruct_s


def test_the_estimate_counts_shared_features_and_models_once():
    """gcp-count: 15 processings of one image set that differ only in the GCPs used —
    the first extracts, matches and runs the mapper, the other 14 reuse its SfM model
    (what follows the mapper only)."""
    from designer.gui.state import derived
    from designer.gui.state.study_data import (
        AFTER_SFM_SHARE,
        plan_cost,
        reconstruct_seconds_per_image,
    )
    from designer.project.interiors import interior_from_camera
    from designer.survey.project_poses import project_stations

    plan = plan_study(read_study(ROOT / "resources" / "studies" / "gcp-count.xml"))
    hf = derived.compute_terrain(plan.base, plan.base_dir).heightfield
    project = plan.runs[0].project
    stations, camera_id = project_stations(project, hf)
    per_run = len(stations) * reconstruct_seconds_per_image(
        project, interior_from_camera(project.camera(camera_id)))
    cost = plan_cost(plan, hf)
    assert cost.reconstruct_s == pytest.approx(per_run * (1 + 14 * AFTER_SFM_SHARE))
    # altitude: 4 image sets, each processed twice (the replicates re-draw the marking
    # error): the second processing of each altitude reuses the first one's SfM model
    plan = plan_study(read_study(ROOT / "resources" / "studies" / "altitude.xml"))
    hf = derived.compute_terrain(plan.base, plan.base_dir).heightfield
    per_altitude = {}
    for run in plan.runs:
        stations, camera_id = project_stations(run.project, hf)
        per_altitude[len(stations), run.project.trajectory] = len(stations) * \
            reconstruct_seconds_per_image(run.project,
                                          interior_from_camera(run.project.camera(camera_id)))
    assert len(per_altitude) == 4 and len(plan.runs) == 8
    cost = plan_cost(plan, hf)
    assert cost.reconstruct_s == pytest.approx(
        sum(per_altitude.values()) * (1 + AFTER_SFM_SHARE))


def test_a_range_is_written_back_as_the_range_while_it_still_is_one():
    xml = ('<study xmlns="urn:designer:project:1" schema-version="1.0" name="r">'
           '<base-project file="b.xml"/><factor name="k1"><range start="-0.1" stop="0.25" '
           'step="0.05"/></factor></study>')
    study = parse_study(xml.encode())
    assert study.factors[0].range_spec == (-0.1, 0.25, 0.05)
    text = study_to_xml(study)
    assert '<range start="-0.1" stop="0.25" step="0.05"/>' in text and "<values>" not in text
    again = parse_study(text.encode())
    assert again.factors[0].values == study.factors[0].values
    assert again.factors[0].range_spec == study.factors[0].range_spec
    # levels edited away from the range are written as values
    edited = replace(study, factors=(replace(study.factors[0], values=("0", "0.1")),))
    text = study_to_xml(edited)
    assert "<values>0 0.1</values>" in text and "<range" not in text


def test_the_estimate_counts_shared_features_once_when_the_models_differ(tmp_path):
    """tiny with the mapper varied: the runs share features and matches but each runs its
    own mapper."""
    from designer.gui.state import derived
    from designer.gui.state.study_data import (
        FEATURE_SHARE,
        plan_cost,
        reconstruct_seconds_per_image,
    )
    from designer.project.interiors import interior_from_camera
    from designer.survey.project_poses import project_stations

    write_template("tiny", tmp_path / "tiny.xml")
    path = tmp_path / "calibration.xml"
    path.write_text(
        '<study xmlns="urn:designer:project:1" schema-version="1.0" name="c">'
        '<base-project file="tiny-base.xml"/>'
        '<factor name="mapper"><values>global</values></factor>'
        "<design>one-at-a-time</design><metrics>check_rmse_z_m</metrics></study>")
    plan = plan_study(read_study(path))
    hf = derived.compute_terrain(plan.base, plan.base_dir).heightfield
    project = plan.runs[0].project
    stations, camera_id = project_stations(project, hf)
    per_run = len(stations) * reconstruct_seconds_per_image(
        project, interior_from_camera(project.camera(camera_id)))
    cost = plan_cost(plan, hf)
    assert (cost.runs, cost.renders, cost.reconstructions) == (2, 1, 2)
    assert cost.reconstruct_s == pytest.approx(per_run * (1 + (1 - FEATURE_SHARE)))
