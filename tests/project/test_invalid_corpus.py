"""The corpus of invalid project files: each gives its expected messages and exit code 2."""

from __future__ import annotations

import os
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest
import xmlschema
from lxml import etree

from designer.cli.main import main
from designer.project.schema import NAMESPACE, schema_path, xml_schema

CORPUS = Path(__file__).resolve().parent / "invalid"
EXPECTED = tomllib.loads((CORPUS / "expected.toml").read_text(encoding="utf-8"))
ROOT = Path(__file__).resolve().parents[2]


def test_the_corpus_is_complete():
    files = sorted(p.name for p in CORPUS.glob("*.xml"))
    assert files == sorted(EXPECTED)
    assert len(files) >= 30


def check(capsys, path: Path, *extra: str) -> tuple[int, str, str]:
    cwd = os.getcwd()
    os.chdir(path.parent)  # messages start with the path as given
    try:
        code = main(["check", *extra, path.name])
    finally:
        os.chdir(cwd)
    out = capsys.readouterr()
    return code, out.out, out.err


@pytest.mark.parametrize("name", sorted(EXPECTED))
def test_invalid_file_gives_its_messages_and_exit_code_2(name, capsys):
    code, out, err = check(capsys, CORPUS / name)
    assert code == 2
    assert out == ""
    lines = err.splitlines()
    for expected in EXPECTED[name]:
        assert f"{name}:{expected}" in [line[: len(name) + 1 + len(expected)] for line in lines]
    problems = [line for line in lines if not line.endswith("not a valid designer project")]
    assert len(problems) == len(EXPECTED[name]), "every problem is listed, none unexpected"
    assert "Traceback" not in err


def test_a_50_mb_file_is_refused_by_size_before_parsing(tmp_path, capsys):
    path = tmp_path / "huge.xml"
    head = f'<project xmlns="{NAMESPACE}" schema-version="1.0"><!-- '.encode()
    with path.open("wb") as f:
        f.write(head)
        f.write(b"x" * (50 * 1024 * 1024))
        f.write(b" --></project>")
    code, _, err = check(capsys, path)
    assert code == 2
    assert "huge.xml:1:1: <project>: the file is 52.4 MB, larger than the 32 MB limit" in err


def test_nothing_is_written_when_checking(tmp_path, capsys):
    target = tmp_path / "nan.xml"
    target.write_bytes((CORPUS / "nan.xml").read_bytes())
    before = sorted(tmp_path.iterdir())
    assert check(capsys, target)[0] == 2
    assert sorted(tmp_path.iterdir()) == before


def test_all_files_are_reported_in_one_run(capsys):
    code = main(["check", str(CORPUS / "nan.xml"), str(CORPUS / "empty.xml")])
    err = capsys.readouterr().err
    assert code == 2 and "nan.xml:54:" in err and "empty.xml:1:1:" in err


def test_the_command_line_process_reports_without_traceback():
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    out = subprocess.run([sys.executable, "-m", "designer", "check", "many-semantic-errors.xml"],
                         cwd=CORPUS, capture_output=True, text=True, env=env, timeout=120)
    assert out.returncode == 2
    assert "Traceback" not in out.stderr
    assert out.stderr.count("many-semantic-errors.xml:") == 5  # 4 problems + the summary


def _project_tree(path: Path) -> etree._ElementTree | None:
    """The tree of a well-formed file whose root is a version-1 <project>, else None."""
    try:
        tree = etree.parse(str(path), etree.XMLParser(resolve_entities=False, no_network=True))
    except etree.XMLSyntaxError:
        return None
    if tree.getroot().tag != f"{{{NAMESPACE}}}project" or tree.docinfo.doctype:
        return None
    return tree


PROJECT_DOCUMENTS = [n for n in sorted(EXPECTED) if _project_tree(CORPUS / n) is not None]


@pytest.fixture(scope="module")
def second_validator():
    return xmlschema.XMLSchema10(str(schema_path()))


@pytest.mark.parametrize("name", PROJECT_DOCUMENTS)
def test_the_independent_validator_agrees_on_schema_validity(name, second_validator):
    tree = _project_tree(CORPUS / name)
    assert xml_schema().validate(tree) == second_validator.is_valid(str(CORPUS / name))
