"""A study whose variants differ only in camera effects renders in Cycles once: the
other image sets are effect passes over the kept raw renders, and the summary counts
both."""

from __future__ import annotations

import json

import pytest

from designer.study.design import plan_study
from designer.study.run import run_study
from designer.study.templates import write_template
from designer.study.xml import read_study

pytestmark = [pytest.mark.blender, pytest.mark.slow]

STUDY = """<?xml version="1.0"?>
<study xmlns="urn:designer:project:1" schema-version="1.0" name="noise">
  <base-project file="tiny-base.xml"/>
  <factor name="sensor-noise-dn">
    <values>0 2 4</values>
  </factor>
  <design>full-factorial</design>
  <replicates count="2" vary="sensor-noise"/>
  <metrics>check_rmse_z_m registered</metrics>
</study>
"""


def test_a_sensor_noise_study_renders_once(tmp_path):
    write_template("tiny", tmp_path / "tiny.xml")  # its base project, tiny-base.xml
    path = tmp_path / "noise.xml"
    path.write_text(STUDY)
    plan = plan_study(read_study(path))
    assert len(plan.runs) == 6
    events = []
    report = run_study(plan, tmp_path / "out", workers=2, progress=events.append)
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())
    # noise 0 draws nothing: its two replicates are one image set; 2 and 4 DN two each
    assert summary["renders"] == 5
    assert summary["raw_renders"] == 1 and summary["effect_passes"] == 4
    kinds = [e.get("kind") for e in events if e.get("event") == "render_done"]
    assert kinds.count("cycles") == 1 and kinds.count("effects pass") == 4, kinds
    assert all(r["status"] == "ok" for r in report.rows), [r["status"] for r in report.rows]
    # the image sets really differ: no two noise draws give the same images
    renders = tmp_path / "out" / "cache" / "renders"
    first_images = {h.name: next((h / "images").iterdir()).read_bytes()
                    for h in renders.iterdir()}
    assert len(set(first_images.values())) == 5
