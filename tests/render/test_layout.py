"""The output folder's layout with real renders: OUT/images holds the images and nothing
else, even while rendering; README.txt names files that exist; folders rendered in the
old layout (images at the top) are still checked and move into images/ on --resume."""

from __future__ import annotations

import dataclasses
import json
import os
import re
import textwrap

import cv2
import pytest

from designer.core.layout import images_dir, move_old_layout_images, uses_old_layout
from designer.project import model as m
from designer.render.check_output import check_output
from designer.render.pipeline import render_project
from designer.render.readme import readme_text
from tests.synthetic import small_survey, write_project_file

pytestmark = [pytest.mark.blender]

#: logs, from inside every render worker (Python audit hooks), each file the worker opens
#: for writing, creates with mkstemp or renames: {"event", "args"} per line
AUDIT_HOOK = textwrap.dedent("""
    import json, os, sys

    _log = os.environ.get("DESIGNER_TEST_AUDIT_LOG")

    def _hook(event, args):
        if not _log or not sys.argv or not sys.argv[0].endswith("worker.py"):
            return
        if event == "open" and isinstance(args[0], (str, bytes, os.PathLike)):
            mode = args[1] or "r"
            if not any(c in mode for c in "wax+") or os.fsdecode(args[0]) == _log:
                return
            row = {"event": "write", "path": os.fsdecode(args[0])}
        elif event == "tempfile.mkstemp":
            row = {"event": "mkstemp", "path": os.fsdecode(args[0])}
        elif event == "os.rename":
            row = {"event": "rename", "src": os.fsdecode(args[0]), "dst": os.fsdecode(args[1])}
        else:
            return
        with open(_log, "a") as f:
            f.write(json.dumps(row) + chr(10))

    sys.addaudithook(_hook)
""")


def test_the_images_folder_only_ever_holds_finished_images(tmp_path, monkeypatch):
    """Every write of the real workers, seen from inside them: nothing is created in
    OUT/images; each image arrives there by one rename from the job's partial/ folder."""
    hooks = tmp_path / "hooks"
    hooks.mkdir()
    (hooks / "sitecustomize.py").write_text(AUDIT_HOOK)
    log = tmp_path / "audit.jsonl"
    monkeypatch.setenv("PYTHONPATH", os.pathsep.join(
        [str(hooks), *filter(None, [os.environ.get("PYTHONPATH")])]))
    monkeypatch.setenv("DESIGNER_TEST_AUDIT_LOG", str(log))
    project = write_project_file(small_survey(n_photos=3, samples=2, size_px=(96, 72)),
                                 tmp_path / "p")
    out = tmp_path / "out"
    seen: list[list[str]] = []  # the images folder each time an image is reported done

    def look(event):
        if event["event"] == "frame_done":
            seen.append(sorted(p.name for p in (out / "images").iterdir()))

    summary = render_project(project, out, workers=1, progress=look)
    names = sorted(p.image_name for p in summary.prepared.poses)
    images = (out / "images").resolve()
    partial = (out / ".designer-job" / "partial").resolve()
    rows = [json.loads(line) for line in log.read_text().splitlines()]
    inside = str(images) + os.sep
    renames = [r for r in rows if r["event"] == "rename"
               and os.path.realpath(r["dst"]).startswith(inside)]
    assert sorted(os.path.basename(r["dst"]) for r in renames) == names
    assert all(os.path.dirname(os.path.realpath(r["src"])) == str(partial) for r in renames)
    created = [r["path"] for r in rows if r["event"] in ("write", "mkstemp")]
    assert created, "the audit hook saw no write at all"
    assert not [p for p in created if os.path.realpath(p).startswith(inside)]
    # after the render: exactly the images, complete; the partial folder is empty
    assert sorted(p.name for p in images.iterdir()) == names
    for name in names:
        assert cv2.imread(str(images / name)).shape == (72, 96, 3)
    assert list(partial.iterdir()) == []
    # each report finds its image in place (a later one may already be there too: the
    # worker goes on while the report travels), never an unfinished name
    counts = [len(s) for s in seen]
    assert len(seen) == 3 and counts == sorted(counts) and counts[-1] == 3
    assert all(n >= k + 1 for k, n in enumerate(counts))
    assert all(set(s) <= set(names) for s in seen)


@pytest.fixture(scope="module")
def rendered(tmp_path_factory):
    folder = tmp_path_factory.mktemp("layout")
    project = write_project_file(small_survey(n_photos=4, samples=2, size_px=(96, 72)),
                                 folder / "p")
    summary = render_project(project, folder / "out", workers=1)
    return project, summary


def _paths_in(readme: str) -> list[str]:
    """Every path the README names relative to the folder (images/…, ground-truth/…)."""
    return sorted(set(re.findall(r"(?<![\w/])((?:images|ground-truth)/[\w./-]*)", readme)))


def test_the_readme_names_files_that_exist(rendered):
    _, summary = rendered
    out = summary.out_dir
    readme = (out / "README.txt").read_text()
    paths = _paths_in(readme)
    for path in paths:
        assert (out / path).exists(), f"README.txt names {path}, which is not there"
    # every ground-truth file written is named, under the program that reads it
    written = {p.relative_to(out).as_posix() for key, p in summary.ground_truth.items()
               if not key.startswith("colmap")}
    assert written and written <= set(paths)
    assert "ground-truth/colmap/" in paths
    assert "--image_path images" in readme
    assert "4 images (IMG_000.png … IMG_003.png), PNG, 96 x 72 px" in readme
    odm = readme[readme.index("OpenDroneMap"):readme.index("Agisoft Metashape")]
    assert "ground-truth/odm/gcp_list.txt" in odm and "ground-truth/odm/geo.txt" in odm
    assert "beside images/, not inside it" in odm


def test_the_readme_leaves_out_programs_whose_files_were_not_written(tmp_path):
    project = small_survey(n_photos=2, samples=1, size_px=(64, 48))
    project = dataclasses.replace(project, outputs=m.Outputs("output", ("colmap", "gcp")))
    out = tmp_path / "out"
    summary = render_project(write_project_file(project, tmp_path / "p"), out, workers=1)
    readme = (out / "README.txt").read_text()
    assert readme == readme_text(out, [p.image_name for p in summary.prepared.poses],
                                 summary.ground_truth, project="project.xml",
                                 image_size_px=(64, 48))
    assert "COLMAP" in readme and "ground-truth/gcp_truth.csv" in readme
    assert "OpenDroneMap" not in readme and "Metashape" not in readme
    for path in _paths_in(readme):
        assert (out / path).exists(), path


def _to_old_layout(out):
    """The folder as designer wrote it before images/ existed: images at the top."""
    for image in sorted((out / "images").iterdir()):
        os.replace(image, out / image.name)
    (out / "images").rmdir()
    (out / "README.txt").unlink()


def test_an_old_layout_folder_is_checked_and_resume_moves_it(rendered, tmp_path):
    import shutil

    project, summary = rendered
    out = tmp_path / "old"
    shutil.copytree(summary.out_dir, out, symlinks=True)
    _to_old_layout(out)
    assert uses_old_layout(out) and images_dir(out) == out

    status = check_output(out, project)
    assert status.old_layout and not status.ok
    assert len(status.up_to_date) == 4 and not status.missing and not status.stale
    text = status.summary()
    assert "old layout" in text and f"designer render {project} -o {out} --resume" in text
    assert status.to_json()["images_dir"] == str(out)

    # the CLI says the same, exit code 1
    from designer.cli.main import main

    assert main(["check-output", str(out), "--project", str(project)]) == 1
    # and the desktop designer's Render panel line
    from designer.gui.state.output_state import render_state
    from designer.project import load_project

    state = render_state(out, project, load_project(project))
    assert not state.ok and state.stale == {} and state.missing == []
    assert "old layout" in state.text and "images/" in state.text

    # --resume moves the images into images/ and renders nothing again
    again = render_project(project, out, workers=1, resume=True)
    assert again.report.rendered == {} and sorted(again.report.skipped) == [0, 1, 2, 3]
    assert sorted(p.name for p in (out / "images").iterdir()) == sorted(
        p.image_name for p in summary.prepared.poses)
    assert not uses_old_layout(out) and not list(out.glob("*.png"))
    status = check_output(out, project)
    assert status.ok, status.summary()
    assert (out / "README.txt").is_file()


def test_resume_renders_only_what_is_missing_from_images(rendered, tmp_path):
    import shutil

    project, summary = rendered
    out = tmp_path / "resumed"
    shutil.copytree(summary.out_dir, out, symlinks=True)
    (out / "images" / "IMG_002.png").unlink()
    again = render_project(project, out, workers=1, resume=True)
    assert sorted(again.report.rendered) == [2] and sorted(again.report.skipped) == [0, 1, 3]
    assert check_output(out, project).ok


def test_only_the_projects_images_move_out_of_the_old_layout(tmp_path):
    (tmp_path / "IMG_1.png").write_bytes(b"x")
    (tmp_path / "mine.jpg").write_bytes(b"y")
    (tmp_path / ".IMG_2.rendering.png").write_bytes(b"z")
    assert images_dir(tmp_path) == tmp_path
    assert move_old_layout_images(tmp_path, ["IMG_1.png", "IMG_9.png"]) == ["IMG_1.png"]
    assert (tmp_path / "images" / "IMG_1.png").read_bytes() == b"x"
    assert (tmp_path / "mine.jpg").is_file()  # not the project's: left where it is
    assert images_dir(tmp_path) == tmp_path / "images"
    assert images_dir(tmp_path / "new") == tmp_path / "new" / "images"
