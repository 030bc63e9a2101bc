"""Studies end to end: a tiny study (160 x 120 px images) killed, resumed and finished;
its caching (a processing-only factor renders once) and bad study files."""

from __future__ import annotations

import csv
import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from designer.project.problems import ProjectError
from designer.study.design import plan_study
from designer.study.run import run_study
from designer.study.templates import write_template
from designer.study.xml import parse_study, read_study

ROOT = Path(__file__).resolve().parents[2]

pytestmark = [pytest.mark.blender]


def _designer(*args, **kw) -> subprocess.Popen:
    return subprocess.Popen([sys.executable, "-m", "designer", *args], cwd=ROOT,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, **kw)


@pytest.fixture(scope="module")
def killed_and_resumed(tmp_path_factory):
    """The tiny study run in a process killed (SIGKILL, whole process group) once its first
    run finished, then resumed to the end; and resumed a second time."""
    folder = tmp_path_factory.mktemp("study")
    study = folder / "tiny.xml"
    write_template("tiny", study)
    out = folder / "out"
    proc = subprocess.Popen(
        [sys.executable, "-m", "designer", "study", "run", str(study), "-o", str(out),
         "--workers", "2", "--progress", "none"], cwd=ROOT, stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL, start_new_session=True)
    deadline = time.monotonic() + 600
    while time.monotonic() < deadline and proc.poll() is None:
        if list(out.glob("runs/*/result.json")):
            break
        time.sleep(0.2)
    finished = {p.parent.name: p.read_bytes() for p in out.glob("runs/*/result.json")}
    assert proc.poll() is None, "the study ended before it could be killed"
    os.killpg(proc.pid, signal.SIGKILL)
    proc.wait()
    finished = {p.parent.name: p.read_bytes() for p in out.glob("runs/*/result.json")}
    assert finished, "no run had finished when the study was killed"
    plan = plan_study(read_study(study))
    first = run_study(plan, out, workers=2, resume=True)
    second = run_study(plan, out, workers=2, resume=True)
    return out, finished, first, second


def test_a_killed_study_resumes_without_losing_or_redoing_a_run(killed_and_resumed):
    out, finished, first, second = killed_and_resumed
    for run, content in finished.items():  # finished before the kill: kept as they were
        assert (out / "runs" / run / "result.json").read_bytes() == content
    assert first.counts["reconstructions_this_session"] <= 4 - len(finished)
    assert second.counts["renders_this_session"] == 0
    assert second.counts["reconstructions_this_session"] == 0
    assert [r["status"] for r in second.rows] == ["ok"] * 4


def test_a_processing_only_factor_renders_once(killed_and_resumed):
    out, *_ = killed_and_resumed
    with (out / "results.csv").open() as table:
        rows = list(csv.DictReader(table))
    assert len(rows) == 4
    marking = {r["factor:marking-sigma-px"]: r for r in rows
               if r["factor:sun-elevation-deg"] == "55"}
    assert set(marking) == {"0.5", "0.2", "2"}
    # three variants differing only in processing share one image set; the sun another
    assert len({r["image_hash"] for r in marking.values()}) == 1
    assert len({r["image_hash"] for r in rows}) == 2
    assert len({r["processing_hash"] for r in rows}) == 4
    summary = json.loads((out / "summary.json").read_text())
    assert (summary["variants"], summary["renders"], summary["reconstructions"]) == (4, 2, 4)
    assert summary["cache_hits"] == 2 and summary["failed"] == 0
    assert len(list((out / "cache" / "renders").iterdir())) == 2
    # runs of the same images extract features and match pairs once (an extraction by
    # the killed session is reused too): one database per image set, the others reuse it
    assert [r["features_reused"] for r in marking.values()].count("True") >= 2
    assert [r["matches_reused"] for r in marking.values()].count("True") >= 2
    assert len(list((out / "cache" / "features").glob("features-*/database.db"))) == 2
    assert len(list((out / "cache" / "features").glob("matches-*/database.db"))) == 2
    # a run's share of the study's cost: the shared render divided among its runs
    owners = [r for r in rows if r["render_reused"] == "False"]
    spent = sum(float(r["render_s"]) for r in owners) + sum(
        float(r["reconstruct_s"]) + float(r["compare_s"]) for r in rows)
    assert sum(float(r["amortised_s"]) for r in rows) == pytest.approx(spent, rel=1e-4)
    assert all(float(r["amortised_s"]) < float(r["total_s"]) for r in marking.values())
    # the marking error shows in the check points: 2 px marks worse than 0.2 px
    assert float(marking["2"]["check_rmse_z_m"]) > float(marking["0.2"]["check_rmse_z_m"])
    for r in rows:
        assert int(r["registered"]) == int(r["images"]) > 3
        assert float(r["cloud_nmad_m"]) > 0
        # nothing stands on this ground: the bare earth is the surface, one truth
        assert r["dtm_cloud_nmad_m"] == r["cloud_nmad_m"]


def test_each_run_costs_flight_minutes_images_gcps_and_cpu_seconds(killed_and_resumed):
    out, *_ = killed_and_resumed
    with (out / "results.csv").open() as table:
        rows = list(csv.DictReader(table))
    cpus = os.cpu_count() or 1
    # no time line: the same path for every run (the sun and the marks leave it), at the
    # default speed; every GCP target surveyed, 4 of them control
    assert {r["flight_min_source"] for r in rows} == {"path at 8 m/s"}
    assert len({r["flight_min"] for r in rows}) == 1 and 0.05 < float(rows[0]["flight_min"])
    assert {(r["images"], r["gcps"], r["control_gcps"]) for r in rows} == {("18", "10", "4")}
    for r in rows:
        # CPU seconds of the work, not of the machine: more than nothing, and at most
        # every core busy for the stage's wall time (the render's Blender workers count:
        # at least the Cycles seconds its manifest records)
        assert float(r["render_cpu_s"]) >= float(r["render_cycles_cpu_s"]) * 0.999 > 0
        assert 0 < float(r["reconstruct_cpu_spent_s"]) <= \
            float(r["reconstruct_s"]) * cpus * 1.05 + 0.5
        assert 0 < float(r["compare_cpu_s"]) <= float(r["compare_s"]) * cpus * 1.05 + 0.5
        assert float(r["reconstruct_cpu_s"]) >= float(r["reconstruct_cpu_spent_s"])
        assert float(r["cpu_s"]) == pytest.approx(sum(float(r[k]) for k in (
            "render_cpu_s", "reconstruct_cpu_s", "compare_cpu_s")), rel=1e-4)
    # a reconstruction that took its features, matches or SfM model from the cache counts
    # what computing them cost the run that did (recorded as each step ended, so even a
    # run of the killed session counts)
    by_image = {}
    for r in rows:
        by_image.setdefault(r["image_hash"], []).append(r)
    for group in by_image.values():
        on_its_own = [float(r["reconstruct_cpu_s"]) for r in group]
        for r in group:
            if r["features_reused"] == "True":
                assert float(r["reconstruct_cpu_s"]) > float(r["reconstruct_cpu_spent_s"])
        # the same work on its own: within a factor of two of each other
        assert max(on_its_own) < 2 * min(on_its_own)
    # the study's CPU: each render once, each reconstruction's own spending
    owners = [r for r in rows if r["render_reused"] == "False"]
    spent = sum(float(r["render_cpu_s"]) for r in owners) + sum(
        float(r["reconstruct_cpu_spent_s"]) + float(r["compare_cpu_s"]) for r in rows)
    assert sum(float(r["cpu_amortised_s"]) for r in rows) == pytest.approx(spent, rel=1e-4)
    summary = json.loads((out / "summary.json").read_text())
    cost = summary["cost"]
    assert (cost["axis"], cost["column"], cost["metric"]) == (
        "flight-minutes", "flight_min", "check_rmse_z_m")
    # one replicate and one flight for all: the most accurate variant is the front
    best = min(cost["variants"], key=lambda v: v["error"]["mean"])
    assert [v["label"] for v in cost["variants"] if v["front"]] == [best["label"]]


def test_the_report_labels_variants_by_their_levels(killed_and_resumed):
    out, *_ = killed_and_resumed
    md = (out / "report.md").read_text()
    section = md.split("## Accuracy against cost", 1)[1].split("## Which factors", 1)[0]
    for label in ("base: marking-sigma 0.5 px, sun-elevation 55°", "marking-sigma 0.2 px",
                  "marking-sigma 2 px", "sun-elevation 40°"):
        assert f"| {label} | 1 |" in section, section
    assert "Cost: **flight minutes per survey**" in section
    assert "front: variants no other beats in both cost and error" in section.lower()
    assert "| v0" not in section and "- v0" not in section


def test_the_report_and_every_run_project_stand_on_their_own(killed_and_resumed):
    out, *_ = killed_and_resumed
    html = (out / "report.html").read_text()
    assert "figures/factor-marking-sigma-px.png" in html and "figures/pareto.png" in html
    for name in ("factor-marking-sigma-px.png", "factor-sun-elevation-deg.png", "pareto.png"):
        assert (out / "figures" / name).stat().st_size > 5000
    summary = json.loads((out / "summary.json").read_text())
    levels = summary["factors"]["marking-sigma-px"]["levels"]
    assert [lv["level"] for lv in levels] == ["0.2", "0.5", "2"]
    check = subprocess.run([sys.executable, "-m", "designer", "check",
                            str(out / "runs" / "v003-r00" / "project.xml")], cwd=ROOT,
                           capture_output=True, text=True)
    assert check.returncode == 0, check.stderr


STUDY = """<?xml version="1.0"?>
<study xmlns="urn:designer:project:1" schema-version="1.0" name="bad">
  <base-project file="tiny-base.xml"/>
{body}
</study>
"""


@pytest.mark.parametrize("body, where, message", [
    ('  <factor name="altitude">\n    <values>20 30</values>\n  </factor>', "4:11",
     "unknown factor 'altitude'; did you mean “flight height above ground (m)” "
     "(altitude-m)?"),
    ('  <factor name="altitude-m">\n    <values>20 -5</values>\n  </factor>', "5:5",
     "(altitude-m): the level '-5' makes a project that is not valid"),
    ('  <factor name="calibration">\n    <values>fixed sometimes</values>\n  </factor>',
     "5:5", "value 'sometimes' is not usable: use one of: fixed"),
    ("", "2:1", "the design is empty"),
    ('  <factor name="k1">\n    <range start="0" stop="0.1" step="-1"/>\n  </factor>', "5:",
     "must be greater than 0"),
    ('  <factr name="k1"/>', "4:3", "unknown element <factr>"),
    ('  <factor name="k1"><values>0 0.1</values></factor>\n  <replicates count="2" '
     'vary="weather"/>', "5:", "vary"),
    # a level that is not a number, in words and not Python's
    ('  <factor name="jpeg-quality">\n    <values>90 abc</values>\n  </factor>', "5:5",
     "value 'abc' is not usable: not a whole number; write one such as 3"),
    ('  <factor name="k1">\n    <values>0 x</values>\n  </factor>', "5:5",
     "value 'x' is not usable: not a number; write a number such as 0.5"),
])
def test_bad_study_files_are_located_one_line_errors(tmp_path, body, where, message):
    write_template("tiny", tmp_path / "tiny.xml")
    path = tmp_path / "bad.xml"
    path.write_text(STUDY.format(body=body))
    with pytest.raises(ProjectError) as info:
        plan_study(read_study(path))
    line = str(info.value).splitlines()[0]
    assert line.startswith(f"{path}:{where}"), line
    assert message in line, line
    assert not (tmp_path / "out").exists()


def test_a_missing_base_project_and_an_inline_one(tmp_path):
    path = tmp_path / "s.xml"
    path.write_text(STUDY.format(body='  <factor name="k1"><values>0.1</values></factor>')
                    .replace("tiny-base.xml", "nowhere.xml"))
    with pytest.raises(ProjectError,
                       match=r"s.xml:3:3: <base-project>: the base project 'nowhere.xml'"):
        plan_study(read_study(path))
    write_template("tiny", tmp_path / "tiny.xml")
    base = (tmp_path / "tiny-base.xml").read_text().split("?>", 1)[1].strip()
    bad = base.replace('<sun azimuth-deg="150.0"', '<sun azimuth-deg="-500"')
    inline = ('<?xml version="1.0"?>\n<study xmlns="urn:designer:project:1" '
              'schema-version="1.0" name="inline">\n  <base-project>\n' + bad
              + '\n  </base-project>\n  <factor name="k1"><values>0.1</values></factor>\n'
              '</study>\n')
    with pytest.raises(ProjectError, match="azimuth"):
        plan_study(parse_study(inline.encode(), "inline.xml", tmp_path / "inline.xml"))
    good = parse_study(inline.replace(bad, base).encode(), "inline.xml",
                       tmp_path / "inline.xml")
    assert len(plan_study(good).runs) == 2


def test_the_cli_reports_a_bad_study_with_exit_code_2(tmp_path):
    path = tmp_path / "bad.xml"
    path.write_text("<study/>")
    proc = _designer("study", "run", str(path), "-o", str(tmp_path / "out"))
    _, err = proc.communicate()
    assert proc.returncode == 2
    assert f"{path}:1:1: <study>: the root element must be" in err
    assert not (tmp_path / "out").exists()


def test_the_packaged_study_schema_is_the_canonical_one_and_compiles():
    import filecmp

    import xmlschema

    from designer.study.xml import study_schema_path

    canonical = ROOT / "schema" / "designer-study-1.0.xsd"
    assert filecmp.cmp(study_schema_path(), canonical, shallow=False)
    assert xmlschema.XMLSchema10(str(canonical)).target_namespace == "urn:designer:project:1"


def test_every_example_study_plans(tmp_path):
    from designer.study.templates import TEMPLATE_NAMES

    for name in TEMPLATE_NAMES:
        plan = plan_study(read_study(write_template(name, tmp_path / name / "s.xml")[0]))
        assert plan.n_variants >= 3


def test_a_folder_given_as_the_study_file_is_a_clear_error(tmp_path):
    with pytest.raises(ProjectError, match=r"<study>: this is not a regular file"):
        read_study(tmp_path)


def test_a_study_whose_runs_failed_exits_3_after_writing_every_result(killed_and_resumed,
                                                                      tmp_path):
    import shutil

    out, _, _, second = killed_and_resumed
    copy = tmp_path / "out"
    shutil.copytree(out, copy)
    study = out.parent / "tiny.xml"
    done = _designer("study", "run", str(study), "-o", str(copy), "--resume",
                     "--progress", "none")
    stdout, stderr = done.communicate(timeout=300)
    assert done.returncode == 0, stderr
    # a finished run that failed stays finished: the resumed study reports it
    first_run = sorted((copy / "runs").iterdir())[1]
    result = json.loads((first_run / "result.json").read_text())
    result["status"] = "failed: georeferencing needs at least 3 control GCPs, got 1"
    (first_run / "result.json").write_text(json.dumps(result))
    failed = _designer("study", "run", str(study), "-o", str(copy), "--resume",
                       "--progress", "none")
    stdout, stderr = failed.communicate(timeout=300)
    assert failed.returncode == 3, stderr
    assert "failed 1" in stdout
    last = stderr.strip().splitlines()[-1]
    assert last.startswith(f"designer: 1 of {len(second.rows)} runs failed (first: "
                           f"{first_run.name}: georeferencing needs at least 3")
    with open(copy / "results.csv", newline="") as f:  # every result written first
        rows = list(csv.DictReader(f))
    assert len(rows) == len(second.rows)
    assert sum(r["status"] != "ok" for r in rows) == 1
    assert "--resume --retry-failed redoes the failed ones" in last
    # --retry-failed redoes it (its reconstruction was fine: the row is written again)
    retried = _designer("study", "run", str(study), "-o", str(copy), "--resume",
                        "--retry-failed", "--progress", "none")
    stdout, stderr = retried.communicate(timeout=300)
    assert retried.returncode == 0, stderr
    assert json.loads((first_run / "result.json").read_text())["status"] == "ok"
    assert "failed 0" in stdout
    alone = _designer("study", "run", str(study), "-o", str(copy), "--retry-failed",
                      "--progress", "none")
    _, stderr = alone.communicate(timeout=300)
    assert alone.returncode == 2
    assert stderr.strip().splitlines()[-1] == ("designer: error: --retry-failed redoes the failed "
                                               "runs of a study folder; give it with --resume")
