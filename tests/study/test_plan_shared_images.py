"""Planning a study prepares each image set's render job once: runs that differ only in
their processing copy the first one's ground truth and keep its image-set figures —
the same plan as preparing each run on its own. No rendering."""

from __future__ import annotations

import filecmp
from dataclasses import replace

from designer.project import load_project
from designer.project import model as m
from designer.study import stages
from designer.study.design import plan_study
from designer.study.run import _plan_runs
from designer.study.templates import write_template
from designer.study.xml import read_study


def _same_tree(a, b) -> bool:
    cmp = filecmp.dircmp(a, b)
    if cmp.left_only or cmp.right_only or cmp.diff_files or cmp.funny_files:
        return False
    _, mismatch, errors = filecmp.cmpfiles(a, b, cmp.common_files, shallow=False)
    return not mismatch and not errors and all(
        _same_tree(a / d, b / d) for d in cmp.common_dirs)


def test_runs_that_differ_in_processing_share_one_prepared_job(tmp_path, monkeypatch):
    plan = plan_study(read_study(write_template("tiny", tmp_path / "tiny.xml")[0]))
    prepared = []
    real = stages._plan_images

    def counting(project, run_dir):
        prepared.append(run_dir.name)
        return real(project, run_dir)

    monkeypatch.setattr(stages, "_plan_images", counting)
    infos = _plan_runs(plan, tmp_path / "out", lambda _e: None)
    # the tiny study: 3 runs of the base images (marking sigma 0.5, 0.2, 2 px) and one
    # with another sun: two image sets, each prepared once
    assert len(infos) == 4 and len(prepared) == 2
    by_images = {}
    for rid, info in infos.items():
        by_images.setdefault(info["image_hash"], []).append(rid)
    assert sorted(len(v) for v in by_images.values()) == [1, 3]
    shared = next(v for v in by_images.values() if len(v) == 3)
    runs = tmp_path / "out" / "runs"
    first = runs / shared[0] / "survey" / "ground-truth"
    for rid in shared[1:]:
        assert _same_tree(first, runs / rid / "survey" / "ground-truth")
        assert infos[rid]["processing_hash"] != infos[shared[0]]["processing_hash"]

    # a run planned on its own gives the same figures as the copied plan
    rid = shared[-1]
    alone = stages.plan_run(load_project(runs / rid / "project.xml"), tmp_path / "alone")
    for key in (*stages.IMAGE_KEYS, "processing_hash", "features_group", "sfm_group",
                "gcps", "control_gcps"):
        assert alone[key] == infos[rid][key], key
    assert _same_tree(tmp_path / "alone" / "survey" / "ground-truth",
                      runs / rid / "survey" / "ground-truth")


def test_images_key_ignores_processing_alone():
    from designer.study.templates import template_base

    base = template_base("tiny")
    processing = base.processing or m.Processing()
    other = replace(base, processing=replace(processing, gcps=replace(
        processing.gcps, marking_sigma_px=2.0, seed=7)))
    assert other.processing != base.processing
    assert stages.images_key(base) == stages.images_key(other)
    moved = replace(base, name=base.name + " (renamed)")
    assert stages.images_key(moved) != stages.images_key(base)
