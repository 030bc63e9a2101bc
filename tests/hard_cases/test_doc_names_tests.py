"""docs/hard-cases.md names a test and a tolerance in every row, says how the test was
shown to fail without its guard, and every test it names exists in the tests tree."""

from __future__ import annotations

import ast
import re
from functools import cache
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
DOC = ROOT / "docs" / "hard-cases.md"
#: a test named in the doc: `tests/…/test_x.py::test_name` with an optional [parameter]
NAMED = re.compile(r"`(tests/[\w/]+\.py)::(\w+)(\[[^`]*\])?`")
COLUMNS = ["Case", "Naive code", "What designer does", "Test", "Tolerance",
           "Fails without the guard"]


def table_rows(text: str) -> list[dict[str, str]]:
    """Every row of the doc's case tables, as {column: cell}."""
    rows, header = [], None
    for line in text.splitlines():
        if not line.startswith("|"):
            header = None
            continue
        cells = [c.strip() for c in line.strip().strip("|").split(" | ")]
        if header is None:
            header = cells
        elif not set(line) <= set("|- "):
            rows.append(dict(zip(header, cells, strict=False)))
    return rows


@cache
def _defined(path: Path) -> frozenset[str]:
    """Names of the test functions of a test module (top level or in a class)."""
    tree = ast.parse(path.read_text())
    return frozenset(node.name for node in ast.walk(tree)
                     if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef))


def missing_tests(text: str, root: Path = ROOT) -> list[str]:
    """The tests ``text`` names that do not exist under ``root``."""
    out = []
    for file, name, _ in NAMED.findall(text):
        path = root / file
        if not path.is_file() or name not in _defined(path):
            out.append(f"{file}::{name}")
    return out


def test_every_row_names_its_test_tolerance_and_how_it_was_checked():
    rows = table_rows(DOC.read_text())
    assert len(rows) >= 20
    for row in rows:
        assert list(row) == COLUMNS, row
        case = row["Case"]
        assert NAMED.search(row["Test"]), f"{case}: no test named as `tests/…py::name`"
        assert row["Tolerance"] not in ("", "—"), f"{case}: no tolerance"
        checked = row["Fails without the guard"]
        assert checked not in ("", "—") and "not re-checked" not in checked, case
    cases = " ".join(r["Case"] for r in rows)
    for needed in ("N 9 999 000", "horizontally", "κ wrapping", "Fisheye", "fold",
                   "1 mm and 50 cm GSD", "self-calibration", "collinear",
                   "One image, one flight line, zero overlap", "1° and 89°",
                   "rolling-shutter readout", "10 million points", "float32 at UTM",
                   "A study of one run", "same seed twice"):
        assert needed in cases, f"docs/hard-cases.md has no row for {needed!r}"


def test_every_test_the_doc_names_exists():
    text = DOC.read_text()
    assert len(NAMED.findall(text)) >= 30
    assert missing_tests(text) == []


@pytest.mark.parametrize("misspelt", [
    "`tests/hard_cases/test_sun_extremes.py::test_shadows_are_what_the_sun_hieght_makes_them`",
    "`tests/hard_cases/test_no_such_file.py::test_shadows_are_what_the_sun_height_makes_them`",
])
def test_a_misspelt_test_name_is_caught(misspelt):
    assert missing_tests(misspelt) == [misspelt.strip("`")]
    real = misspelt.replace("hieght", "height").replace("test_no_such_file", "test_sun_extremes")
    assert missing_tests(real) == []


def test_the_hard_cases_run_in_the_default_pytest():
    """`python -m pytest` (what `make test` runs) collects tests/hard_cases: the test path
    is the tests tree and no marker is deselected by default (blender and slow label)."""
    import tomllib

    settings = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["pytest"][
        "ini_options"]
    assert settings["testpaths"] == ["tests"]
    options = settings.get("addopts", "").split()
    assert "-m" not in options and not any(o.startswith(("-m=", "--deselect", "--ignore"))
                                           for o in options), options
    for conftest in (ROOT / "tests").rglob("conftest.py"):
        text = conftest.read_text()
        assert "collection_modifyitems" not in text and "hard_cases" not in text, conftest
