"""The layer contract of the package, stated once as tables and checked on every module.

Static part: every ``import`` of every module (also those inside functions, which load
lazily) is read from its source; a designer package may import only the packages its row
of :data:`MAY_IMPORT` names, and the heavy third-party libraries only where
:data:`THIRD_PARTY_ONLY_IN` allows. Run-time part: importing a package face or a data
type loads none of the heavy modules it must not (:data:`NOT_LOADED_BY`).

The test suite has a rule of its own: no file under tests/ imports a test module
(``test_*``) or a ``conftest``; shared test code lives in helper modules
(tests/synthetic.py, tests/*/helpers.py, ...) and fixtures reach tests through pytest.
"""

from __future__ import annotations

import ast
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[1] / "designer"
TESTS = Path(__file__).resolve().parent

#: the small shared modules at the top of the package that everything may use
BASE = {"errors", "atomic", "_lazy", "lifetime"}

#: designer package → the designer packages its modules may import (arrows point down)
MAY_IMPORT: dict[str, set[str]] = {
    "core": set(),
    "project": {"core"},
    "export": {"core"},
    "scene": {"core", "project"},
    "survey": {"core", "project", "scene"},
    "effects": {"core", "project"},
    "flight": {"core", "project", "scene", "survey"},
    "evaluate": {"core", "project", "scene", "export"},
    "sfm": {"core", "project", "scene", "survey", "export", "evaluate"},
    "render": {"core", "project", "scene", "survey", "export", "effects"},
    "validate": {"core", "scene", "effects", "render"},
    "demo": {"core", "project", "scene", "survey", "export", "effects", "evaluate", "sfm",
             "render"},
    "study": {"core", "project", "scene", "survey", "export", "effects", "evaluate", "sfm",
              "render"},
    "gui": {"core", "project", "scene", "survey", "export", "effects", "evaluate", "sfm",
            "render", "study", "flight"},
    "bench": {"core", "project", "scene", "survey", "export", "effects", "evaluate", "sfm",
              "render", "validate", "gui", "study"},
    "cli": {"core", "project", "scene", "survey", "export", "effects", "evaluate", "sfm",
            "render", "validate", "demo", "gui", "bench", "study", "flight"},
    "__main__": {"cli"},
}

#: third-party module → the designer modules or packages that may import it
THIRD_PARTY_ONLY_IN: dict[str, tuple[str, ...]] = {
    "bpy": ("render.worker",),
    "mathutils": ("render.worker",),
    "PySide6": ("gui", "bench.gui"),
    "pyvista": ("gui", "bench"),  # bench compare measures pyvista's distance filter too
    "pyvistaqt": ("gui",),
    "vtk": ("gui",),
    "vtkmodules": ("gui",),
    "pycolmap": ("sfm",),
    "pyceres": ("sfm",),
    "distributed": ("render.cluster", "study.run"),
    "pyexiv2": ("flight.image_meta", "render.exif"),
}

#: module imported in a fresh interpreter (P.* = every module of package P) → modules that
#: must not be loaded after it
NOT_LOADED_BY: dict[str, tuple[str, ...]] = {
    "designer.core.*": ("bpy", "PySide6", "cv2", "pyvista", "vtk", "scipy", "lxml"),
    "designer.scene.*": ("bpy", "PySide6", "pyvista", "vtk", "rasterio", "plyfile"),
    "designer.export.*": ("bpy", "PySide6", "cv2", "pyvista", "vtk", "scipy", "pycolmap"),
    "designer.effects.*": ("bpy", "PySide6", "pyvista", "vtk", "lxml"),
    "designer.project.model": ("lxml", "numba", "cv2", "scipy"),
    "designer.core.truth": ("lxml", "numba", "cv2", "scipy", "designer.export"),
    "designer.project": ("lxml", "designer.project.xml_read", "designer.project.templates"),
    "designer.export": ("lxml", "designer.export.colmap", "designer.export.odm",
                        "designer.export.metashape", "designer.export.dispatch"),
    "designer.effects": ("numba", "cv2", "scipy", "designer.effects.chain"),
    "designer.evaluate": ("numba", "matplotlib", "rasterio", "laspy", "scipy"),
    "designer.cli.main": ("numba", "cv2", "lxml", "matplotlib", "bpy", "PySide6", "pycolmap"),
    "designer.render.job_spec": ("numpy", "bpy", "cv2", "lxml"),
    "designer.flight": ("lxml", "pyproj", "pyexiv2", "designer.flight.importer"),
}


def _package_of(module: str) -> str:
    parts = module.split(".")
    return parts[1] if len(parts) > 1 else ""


def _modules(root: Path) -> list[str]:
    out = []
    for path in root.rglob("*.py"):
        parts = path.relative_to(root).with_suffix("").parts
        out.append(".".join(("designer", *(parts[:-1] if parts[-1] == "__init__" else parts))))
    return sorted(out)


def _imports(root: Path, module: str) -> list[tuple[int, str]]:
    """(line, imported module) of every import statement of ``module``."""
    rel = Path(*module.split(".")[1:])
    path = root / rel / "__init__.py"
    if not path.is_file():
        path = root / rel.with_suffix(".py")
    out = []
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        if isinstance(node, ast.Import):
            out += [(node.lineno, a.name) for a in node.names]
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            out.append((node.lineno, node.module))
            if node.module == "designer":  # from designer import x
                out += [(node.lineno, f"designer.{a.name}") for a in node.names
                        if not a.name.startswith("__")]
    return out


def violations(root: Path, module: str) -> list[str]:
    """What ``module`` (a file under ``root``, the designer package) imports against the
    contract, as 'module:line imports X (reason)'."""
    own = _package_of(module)
    inside = module.split(".", 1)[1] if "." in module else ""
    allowed = MAY_IMPORT.get(own)
    found = []
    for line, name in _imports(root, module):
        if name.startswith("designer."):
            target = _package_of(name)
            if target == own or target in BASE or target == "":
                continue
            if allowed is None:
                found.append(f"{module}:{line} is in package {own!r}, which has no row in "
                             "the layer table")
            elif target not in allowed:
                found.append(f"{module}:{line} imports {name}: {own} may import only "
                             f"{', '.join(sorted(allowed)) or 'nothing of designer'}")
            elif any(p.startswith("_") for p in name.split(".")[2:]):
                found.append(f"{module}:{line} imports the private {name} of another package")
            continue
        top = name.split(".")[0]
        places = THIRD_PARTY_ONLY_IN.get(top)
        if places and not any(inside == p or inside.startswith(p + ".") for p in places):
            found.append(f"{module}:{line} imports {top}: only {', '.join(places)} may")
    return found


MODULES = _modules(PACKAGE)


@pytest.mark.parametrize("module", MODULES)
def test_every_module_keeps_the_layer_contract(module):
    assert violations(PACKAGE, module) == []


def test_every_package_has_a_row_in_the_table():
    packages = {_package_of(m) for m in MODULES} - BASE - {""}
    assert packages == set(MAY_IMPORT)


@pytest.mark.parametrize(("module", "line", "fragment"), [
    ("core/rotation.py", "from designer.project import model", "core may import only"),
    ("export/odm.py", "from designer.render.job import prepare_job", "export may import only"),
    ("survey/flight.py", "    from designer.gui import app", "survey may import only"),
    ("evaluate/clouds.py", "from designer.scene._private import x", "private"),
    ("effects/chain.py", "import bpy", "only render.worker may"),
    ("sfm/reconstruct.py", "from PySide6 import QtCore", "only gui, bench.gui may"),
])
def test_the_contract_catches_a_wrong_import(tmp_path, module, line, fragment):
    """A copy of the package with one deliberately wrong import fails the check."""
    root = tmp_path / "designer"
    shutil.copytree(PACKAGE, root, ignore=shutil.ignore_patterns("__pycache__"))
    path = root / module
    text = path.read_text()
    if line.startswith(" "):  # an import inside a function (loaded lazily) counts too
        text += f"\n\ndef _late():\n{line}\n"
    else:
        text += f"\n{line}\n"
    path.write_text(text)
    name = "designer." + module.removesuffix(".py").replace("/", ".")
    found = violations(root, name)
    assert len(found) == 1 and fragment in found[0], found
    assert all(violations(root, m) == [] for m in _modules(root) if m != name)


@pytest.mark.parametrize("module", sorted(NOT_LOADED_BY))
def test_importing_loads_nothing_heavy(module):
    forbidden = NOT_LOADED_BY[module]
    if module.endswith(".*"):
        package = module[:-2]
        load = (f"import importlib, pkgutil, {package}\n"
                f"for m in pkgutil.iter_modules({package}.__path__):\n"
                f"    importlib.import_module('{package}.' + m.name)\n")
    else:
        load = f"import {module}\n"
    code = (f"import sys\n{load}"
            f"print(' '.join(m for m in {forbidden!r} if m in sys.modules))\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True, cwd=PACKAGE.parent)
    assert out.stdout.split() == []


def test_the_run_time_check_sees_a_loaded_module():
    """The sys.modules check can fail: importing the project's XML reader loads lxml."""
    code = "import sys, designer.project.xml_read\nprint('lxml' in sys.modules)\n"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True, cwd=PACKAGE.parent)
    assert out.stdout.strip() == "True"


def _is_test_module(name: str) -> bool:
    last = name.rsplit(".", 1)[-1]
    return last.startswith("test_") or last == "conftest"


def imports_of_test_modules(root: Path) -> list[str]:
    """Every import of a test module or a conftest by a file under ``root`` (the tests
    folder), as 'path:line imports X'; relative imports and ``from package import
    test_x`` count too."""
    found = []
    for path in sorted(root.rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text(), str(path))):
            if isinstance(node, ast.Import):
                names = [a.name for a in node.names]
            elif isinstance(node, ast.ImportFrom):
                module = "." * node.level + (node.module or "")
                prefix = module if module.endswith(".") else module + "."
                names = ([module] if _is_test_module(module)
                         else [prefix + a.name for a in node.names])
            else:
                continue
            found += [f"{path.relative_to(root.parent)}:{node.lineno} imports {name}"
                      for name in names if _is_test_module(name)]
    return found


def test_no_test_file_imports_a_test_module_or_a_conftest():
    found = imports_of_test_modules(TESTS)
    assert not found, "move the shared code into a helper module:\n" + "\n".join(found)


@pytest.mark.parametrize(("line", "found"), [
    ("from tests.world.test_moving_objects import box", "tests.world.test_moving_objects"),
    ("import tests.render.test_render_accuracy as acc", "tests.render.test_render_accuracy"),
    ("from tests.evaluate import test_compare_cli", "tests.evaluate.test_compare_cli"),
    ("from .test_chain import write_png", ".test_chain"),
    ("from . import conftest", ".conftest"),
    ("from ..conftest import survey", "..conftest"),
    ("from .. import test_architecture", "..test_architecture"),
    ("    from tests.conftest import survey", "tests.conftest"),
    ("from tests.world.helpers import ORIGIN", None),
    ("from . import helpers", None),
    ("import pytest", None),
])
def test_the_test_import_rule_catches_a_wrong_import(tmp_path, line, found):
    """A small tests tree with one import added to a module: only a test module or a
    conftest is reported, with its file and line."""
    root = tmp_path / "tests"
    (root / "world").mkdir(parents=True)
    for name in ("__init__.py", "world/__init__.py", "world/helpers.py"):
        (root / name).write_text('"""A module."""\n')
    text = "import numpy as np\n"
    if line.startswith(" "):  # an import inside a function (loaded lazily) counts too
        text += f"\n\ndef test_late():\n{line}\n"
    else:
        text += f"{line}\n"
    (root / "world" / "test_case.py").write_text(text)
    lineno = text.splitlines().index(line) + 1
    expected = [] if found is None else [f"tests/world/test_case.py:{lineno} imports {found}"]
    assert imports_of_test_modules(root) == expected
