"""A walk of every message a study file's check gives (``designer study check``, the
Study panel's problems): they name factors, re-drawn draws and metrics in words, not as
the study file's identifiers (``altitude-m``, ``gcp-selection``, ``check_rmse_xy_m``),
and speak no XML outside the command line's ``FILE:LINE:COL: <element>:`` locator
(issue #53, finding 10). On the command line an identifier may follow its words in
parentheses (``“flight height above ground (m)” (altitude-m)``): that is what the file
says; the panel names none.

The sentences are enumerated from the code (every literal of the modules that word a
study's problems) and every kind of problem is triggered and read as both say it."""

from __future__ import annotations

import contextlib
import io
import re
from pathlib import Path

import pytest

from designer.cli.main import main
from designer.gui.state.study_words import study_problem_lines
from designer.project.problems import ProjectError
from designer.study.design import plan_study
from designer.study.factors import DRAWS, FACTORS
from designer.study.results import METRIC_COLUMNS
from designer.study.templates import write_template
from designer.study.xml import read_study
from tests.project.message_text import LOCATOR, SNAKE, XML, _sentences

ROOT = Path(__file__).resolve().parents[2]
#: the modules that word a study's problems
STUDY_MESSAGE_MODULES = [ROOT / "designer" / p for p in (
    "study/design.py", "study/xml.py", "study/factors.py", "study/words.py",
    "gui/state/study_words.py",
    "gui/state/study_data.py", "gui/qt/panels/study.py", "gui/qt/panels/study_files.py",
    "gui/qt/panels/study_run.py", "gui/qt/study_form.py")]
#: every identifier a study file writes that is not a word (k1, images, registered are)
IDENTIFIERS = sorted({n for n in (*FACTORS, *DRAWS, *METRIC_COLUMNS) if re.search(r"[-_]", n)},
                     key=len, reverse=True)
#: an XML element or end tag
TAG = re.compile(r"</?[A-Za-z!][\w.:-]*")
#: the rich text of the panel's labels
MARKUP = re.compile(r"</?(b|br|small|i)>")
#: an identifier after its words, as the command line may give it
NAMED = re.compile(r"(“[^”]*”) \([\w-]+\)")


def _identifiers(text: str) -> list[str]:
    return [n for n in IDENTIFIERS if re.search(rf"(?<![\w-]){re.escape(n)}(?![\w-])", text)]


def test_no_sentence_of_a_studys_messages_names_an_identifier_or_xml():
    found = []
    for path in STUDY_MESSAGE_MODULES:
        for line, text in _sentences(path):
            bare = NAMED.sub(r"\1", LOCATOR.sub(r"\1", MARKUP.sub("", text)))
            bad = XML.findall(bare) + SNAKE.findall(bare) + _identifiers(bare)
            if bad:
                found.append(f"{path.relative_to(ROOT)}:{line}: {bad} in {text!r}")
    assert not found, "\n".join(found)


def test_every_draws_description_is_in_words():
    """The Study panel's tooltip of each re-drawn seed (and the study schema's
    documentation) names the elements by their titles, not as XML (the walk of 12-06
    found "the <cloud-shadows> seed" there: built from the declarations, no sentence of
    the source shows it)."""
    bad = {name: doc for name, (doc, _) in DRAWS.items()
           if XML.findall(doc) or TAG.findall(doc) or SNAKE.findall(doc)}
    assert not bad, bad


STUDY = """<?xml version="1.0"?>
<study xmlns="urn:designer:project:1" schema-version="1.0" name="bad">
  <base-project file="tiny-base.xml"/>
{body}
</study>
"""

CASES = {
    "unknown-factor": '  <factor name="altitude">\n    <values>20 30</values>\n  </factor>',
    "invalid-level": '  <factor name="altitude-m">\n    <values>20 -5</values>\n  </factor>',
    "not-a-choice": '  <factor name="calibration">\n    <values>fixed sometimes</values>\n'
                    '  </factor>',
    "not-a-number": '  <factor name="jpeg-quality">\n    <values>90 abc</values>\n  </factor>',
    "empty": "",
    "twice": '  <factor name="k1"><values>0 0.1</values></factor>\n'
             '  <factor name="k1"><values>0.2</values></factor>',
    "repeated": '  <factor name="gsd-m"><values>0.01 0.01</values></factor>',
    "metric": '  <factor name="k1"><values>0 0.1</values></factor>\n'
              '  <metrics>check-rmse-xy-m</metrics>',
    "draw": '  <factor name="k1"><values>0 0.1</values></factor>\n'
            '  <replicates count="2" vary="gcp-selektion"/>',
    "range": '  <factor name="k1">\n    <range start="0" stop="0.1" step="-1"/>\n  </factor>',
    "both-bases": '  <factor name="k1"><values>0 0.1</values></factor>',
    "no-base": '  <factor name="k1"><values>0 0.1</values></factor>',
    "missing-base": '  <factor name="k1"><values>0 0.1</values></factor>',
}


def _study(tmp_path: Path, case: str) -> Path:
    write_template("tiny", tmp_path / "tiny.xml")
    text = STUDY.format(body=CASES[case])
    if case == "both-bases":
        base = (tmp_path / "tiny-base.xml").read_text().split("?>", 1)[1].strip()
        text = text.replace('file="tiny-base.xml"/>', f'file="tiny-base.xml">{base}'
                            "</base-project>")
    elif case == "no-base":
        text = text.replace(' file="tiny-base.xml"', "")
    elif case == "missing-base":
        text = text.replace("tiny-base.xml", "nowhere.xml")
    path = tmp_path / "study.xml"
    path.write_text(text)
    return path


@pytest.mark.parametrize("case", sorted(CASES))
def test_every_problem_of_a_study_as_check_and_the_panel_say_it(case, tmp_path, capsys):
    path = _study(tmp_path, case)
    with contextlib.redirect_stdout(io.StringIO()):
        assert main(["study", "check", str(path)]) == 2
    line = capsys.readouterr().err.splitlines()[0]
    assert line.startswith(f"designer: error: {path}:"), line
    body = LOCATOR.sub("", line.split(f"{path}:", 1)[1].split(": ", 1)[1], count=1)
    # the study's part: a level's project problem after it is the project's own message
    # (walked with the project's), a schema error quotes a value as the file writes it
    bare = NAMED.sub(r"\1", body).split(" not valid: ")[0]
    assert not TAG.search(bare) and not SNAKE.search(bare), line
    if case != "draw":  # a name the schema refuses: the names the file may write
        assert not _identifiers(bare), line
    with pytest.raises(ProjectError) as error:
        plan_study(read_study(path))
    for panel in study_problem_lines(error.value):
        assert panel.startswith(f"{path}:") and ":1:1:" not in panel, panel
        assert not XML.search(panel) and not SNAKE.search(panel), panel
        assert not _identifiers(panel), panel
    if case in ("unknown-factor", "invalid-level", "twice", "repeated", "metric", "draw"):
        # named in words: a factor as the panel's list names it, a metric as its column
        said = {"unknown-factor": "flight height above ground", "invalid-level":
                "flight height above ground", "twice": "lens distortion k1", "repeated":
                "ground sample distance", "metric": "check-point RMSE XY",
                "draw": "gcp-selektion"}[case]
        assert said in body and said in panel, (body, panel)
