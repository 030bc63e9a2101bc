"""Every declared XML name is spelled in at most two source modules: its declaration and,
where an element has one, the hand-written part of its reader or writer. A third module
that spells it is a hand-written mapping the declaration should replace."""

from __future__ import annotations

import ast
from pathlib import Path

import designer
from designer.project import model as m
from designer.project.declare import attributes, declared_elements, element_of

PACKAGE = Path(designer.__file__).resolve().parent
MOST_MODULES = 2


def declared_names() -> set[str]:
    """The XML names of every declared attribute and text value that contain a hyphen.

    A one-word name (``X``, ``seed``, ``name``, ``camera``) is also a Python identifier, a
    dictionary key and a column name elsewhere, so its count says nothing about hand-written
    XML; a name that is also an element's tag (``rolling-shutter``) is spelled where the
    element is found. Neither is counted."""
    classes = declared_elements(m.Project)
    tags = {element_of(cls).tag for cls in classes}
    return {d.xml for cls in classes for _, d in attributes(cls)
            if "-" in d.xml and d.xml not in tags}


def modules_spelling(names: set[str], root: Path = PACKAGE) -> dict[str, list[str]]:
    """name → the Python modules under ``root`` that hold it as a whole string literal."""
    out: dict[str, list[str]] = {name: [] for name in names}
    for path in sorted(root.rglob("*.py")):
        found = {node.value for node in ast.walk(ast.parse(path.read_text(encoding="utf-8")))
                 if isinstance(node, ast.Constant) and isinstance(node.value, str)}
        for name in names & found:
            out[name].append(str(path.relative_to(root.parent)))
    return out


def test_every_declared_xml_name_is_spelled_in_at_most_two_modules():
    names = declared_names()
    assert {"tilt-deg", "front-overlap-percent", "repeat-X", "sigma-X", "x-mm",
            "start-azimuth-deg"} <= names
    over = {name: modules for name, modules in modules_spelling(names).items()
            if len(modules) > MOST_MODULES}
    assert not over, (
        "XML names spelled in more than two modules (declare them with attr(...) and read, "
        f"write and check them from the declaration): {over}")


def test_a_third_module_is_found(tmp_path):
    """The count can fail: three modules that spell ``tilt-deg``."""
    package = tmp_path / "pkg"
    package.mkdir()
    for i in range(3):
        (package / f"m{i}.py").write_text(f'NAME_{i} = "tilt-deg"\nOTHER = "tilt"\n')
    (package / "m3.py").write_text('TEXT = "a tilt-deg in a sentence"\n')
    found = modules_spelling({"tilt-deg"}, package)
    assert found == {"tilt-deg": ["pkg/m0.py", "pkg/m1.py", "pkg/m2.py"]}
