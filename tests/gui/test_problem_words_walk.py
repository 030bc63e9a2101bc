"""Every value the file check refuses, in every element the templates hold, is listed in
the Problems list in the window's words: no ``<element>`` and no ``attribute="…"`` or
``attribute =`` of the file, also for the attributes the reader maps by hand (a GCP's
surveyed position, an object's placement, the survey area's vertices …).

The walk writes each template with one attribute of one element changed to a bad value
(not a number, far out of range) or left out, opens it as File → Open does
(designer.gui.state.wording.problem_text over the schema's and the semantic checks'
problems) and reads every line, those about that attribute and those its value set off
elsewhere (a GCP off the terrain, a grid that no longer divides the extent)."""

from __future__ import annotations

import contextlib
import io
import re

import pytest
from lxml import etree

from designer.cli.main import main
from designer.gui.state.wording import problem_text
from designer.project import semantic_problems
from designer.project.load import read_project_file
from designer.project.problems import ProjectError

TEMPLATES = ("survey", "survey-structures", "survey-dynamic", "validation-cube", "texture")
#: not a number, far out of range, inside the declared range but against other fields,
#: not finite, and None: the attribute left out
BAD_VALUES = ("abc", "-1e20", "1e20", "0", "-1", "1", "45", "100000", "NaN", "INF", None)
#: an element of the file (``<sensor``) or an attribute with its value (``width-mm="``,
#: ``k1=-1``, ``width-mm = 13200``), or the schema's own words
XML_WORDS = re.compile(r"<[A-Za-z][\w.-]*|[A-Za-z][\w-]*\s?=\s?[\"'\w-]|expected:")


def _listed(path) -> list[tuple[object, str]]:
    """The Problems list's lines (after their place) for the file ``path``, with the
    issue each is worded from; problems without one (the file is no designer project, or
    of another schema version: nothing a panel sets) left out."""
    try:
        project, smap = read_project_file(path)
        found = semantic_problems(project, path.parent, smap)
    except ProjectError as error:
        found = error.problems
    return [(p.issue, problem_text(p, str(path)).split(": ", 1)[1]) for p in found
            if p.issue is not None]


def _walk(template: str, tmp_path) -> tuple[int, list[str]]:
    folder = tmp_path / template
    with contextlib.redirect_stdout(io.StringIO()):
        assert main(["new", str(folder / "p.xml"), "--template", template]) == 0
    text = (folder / "p.xml").read_bytes()
    tree = etree.fromstring(text).getroottree()
    seen, worded, xml = set(), 0, []
    for el in tree.iter():
        if not isinstance(el.tag, str):
            continue
        tag = etree.QName(el).localname
        parent = el.getparent()
        where = (None if parent is None else etree.QName(parent).localname, tag)
        for attr in el.attrib:
            if (*where, attr) in seen:
                continue
            seen.add((*where, attr))
            for bad in BAD_VALUES:
                copy = etree.fromstring(text)
                target = copy.getroottree().xpath(tree.getpath(el))[0]
                if bad is None:
                    del target.attrib[attr]
                else:
                    target.set(attr, bad)
                path = folder / "bad.xml"
                path.write_bytes(etree.tostring(copy))
                for issue, line in _listed(path):
                    worded += issue.tag == tag and issue.attr == attr
                    if XML_WORDS.search(line) or ("-" in attr and attr in line):
                        xml.append(f"{template}: <{tag} {attr}={bad!r}>: {line}")
    return worded, xml


@pytest.mark.parametrize("template", TEMPLATES)
def test_refused_values_are_listed_in_the_windows_words(template, tmp_path):
    worded, xml = _walk(template, tmp_path)
    assert worded > 20  # the walk reached the checks of the attributes it changed
    assert not xml, "\n".join(xml)


def test_a_readout_against_the_trigger_interval_and_a_distorted_rolling_shutter(tmp_path):
    """Two checks across elements no single value of the walk sets off: a rolling
    shutter's readout not shorter than the time line's trigger interval, and a rolling
    shutter behind a distorting lens."""
    import dataclasses

    from designer.project import model as m
    from designer.project.problems import SourceMap

    folder = tmp_path / "p"
    with contextlib.redirect_stdout(io.StringIO()):
        assert main(["new", str(folder / "p.xml"), "--template", "survey-structures"]) == 0
    project, _ = read_project_file(folder / "p.xml")
    camera = dataclasses.replace(project.cameras[0],
                                 rolling_shutter=m.RollingShutter(readout_s=0.5),
                                 distortion=m.BrownConradyDistortion(k1=-0.01))
    time_line = dataclasses.replace(project.trajectory.time_line, trigger_interval_s=0.4)
    project = dataclasses.replace(
        project, cameras=(camera, *project.cameras[1:]),
        trajectory=dataclasses.replace(project.trajectory, time_line=time_line))
    lines = [problem_text(p, "p.xml").split(": ", 1)[1]
             for p in semantic_problems(project, folder, SourceMap(""))]
    assert lines == [
        f"Camera › camera '{camera.id}': the readout 0.5 s is not shorter than the trigger "
        "interval 0.4 s; a frame must be read before the next is taken: shorten the readout "
        "in the Camera panel",
        f"Camera › camera '{camera.id}' has a lens distortion and a rolling shutter, which "
        "designer does not render exactly; set the distortion to none or the readout to 0 s "
        "in the Camera panel"], lines


def test_photos_named_for_another_format_than_the_renders(tmp_path):
    """The Render panel's format changed under photos named .png (the validation cube's):
    each photo listed as not named for the format, without the file's <output format>."""
    import dataclasses

    from designer.project.problems import SourceMap

    folder = tmp_path / "p"
    with contextlib.redirect_stdout(io.StringIO()):
        assert main(["new", str(folder / "p.xml"), "--template", "validation-cube"]) == 0
    project, _ = read_project_file(folder / "p.xml")
    photo = project.trajectory.exterior_orientations[0]
    assert photo.name.endswith(".png")
    project = dataclasses.replace(project, render=dataclasses.replace(
        project.render, output_format="jpeg"))
    lines = [problem_text(p, "p.xml").split(": ", 1)[1]
             for p in semantic_problems(project, folder, SourceMap(""))]
    assert lines[0] == (f"Flight › photo '{photo.name}' is not named as a jpeg image; choose "
                        "the format its name says in the Render panel, or name it with .jpg "
                        "or .jpeg"), lines
    assert not any(XML_WORDS.search(line) for line in lines), lines
