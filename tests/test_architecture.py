"""The layer contract of the package, stated once as tables and checked on every module.

Static part: every ``import`` of every module (also those inside functions, which load
lazily) is read from its source; a designer package may import only the packages its row
of :data:`MAY_IMPORT` names, and the heavy third-party libraries only where
:data:`THIRD_PARTY_ONLY_IN` allows; and no module imports itself through others, inside
a package or across packages (:func:`test_no_import_cycle_between_modules` states what
counts as an edge). Run-time part: importing a package face or a data
type loads none of the heavy modules it must not (:data:`NOT_LOADED_BY`).

Functions stay short: none of the package is over 80 lines but the reasoned few of
:data:`LONG_FUNCTIONS`, a list that only shrinks.

The test suite has a rule of its own: no file under tests/ imports a test module
(``test_*``) or a ``conftest``; shared test code lives in helper modules
(tests/synthetic.py, tests/*/helpers.py, ...) and fixtures reach tests through pytest.
"""

from __future__ import annotations

import ast
import itertools
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
    # render time: the estimate's model, the records of measured renders, a render's
    # timings; the plan's estimate and the render both use it
    "render_time": {"core", "project"},
    "survey": {"core", "project", "scene", "render_time"},
    "effects": {"core", "project"},
    # what designer check and designer plan say beyond validation: above the survey
    # whose stations and analysis they weigh
    "checks": {"core", "project", "scene", "survey", "render_time"},
    "flight": {"core", "project", "scene", "survey"},
    "evaluate": {"core", "project", "scene", "export"},
    "sfm": {"core", "project", "scene", "survey", "checks", "export", "evaluate"},
    "render": {"core", "project", "scene", "survey", "render_time", "export", "effects"},
    "experiments": {"core", "scene", "effects", "render"},
    "demo": {"core", "project", "scene", "survey", "checks", "export", "effects", "evaluate",
             "sfm", "render"},
    "study": {"core", "project", "scene", "survey", "export", "effects", "evaluate", "sfm",
              "render"},
    "gui": {"core", "project", "scene", "survey", "checks", "render_time", "export",
            "effects", "evaluate", "sfm", "render", "study", "flight"},
    "bench": {"core", "project", "scene", "survey", "checks", "render_time", "export",
              "effects", "evaluate", "sfm", "render", "experiments", "gui", "study"},
    "cli": {"core", "project", "scene", "survey", "checks", "render_time", "export",
            "effects", "evaluate", "sfm", "render", "experiments", "demo", "gui", "bench",
            "study", "flight"},
    "__main__": {"cli"},
}

#: third-party module → the designer modules or packages that may import it
THIRD_PARTY_ONLY_IN: dict[str, tuple[str, ...]] = {
    "bpy": ("render.worker",),
    "mathutils": ("render.worker",),
    # Qt and VTK only in the GUI's widgets and its start-up; never in gui.state
    "PySide6": ("gui.qt", "gui.app", "bench.gui", "bench.gui_survey"),
    "pyvista": ("gui.qt", "bench"),  # bench compare measures pyvista's distance filter too
    "pyvistaqt": ("gui.qt",),
    "vtk": ("gui.qt",),
    "vtkmodules": ("gui.qt",),
    # the benchmarks build synthetic blocks as pycolmap reconstructions (bench doming, the
    # rolling-shutter block) and keep the old per-observation Ceres solver as a reference;
    # bench mapper runs sfm.mapping's incremental mapper, which is handed pycolmap
    "pycolmap": ("sfm", "bench.doming", "bench.rolling_reference", "bench.synthetic_rolling",
                 "bench.synthetic_block", "bench.mapper"),
    "pyceres": ("sfm", "bench.rolling_reference"),
    "distributed": ("render.cluster", "study.run"),
    "pyexiv2": ("flight.image_meta", "render.exif"),
}

#: sub-package → the designer modules or packages it must not import, inside its own
#: package's row of MAY_IMPORT: the GUI's Qt-free state never imports its widgets or the
#: start-up that builds them (the arrows point from the widgets to the state)
SUBPACKAGE_MAY_NOT_IMPORT: dict[str, tuple[str, ...]] = {
    "gui.state": ("gui.qt", "gui.app"),
}

#: module imported in a fresh interpreter (P.* = every module of package P) → modules that
#: must not be loaded after it
NOT_LOADED_BY: dict[str, tuple[str, ...]] = {
    "designer.core.*": ("bpy", "PySide6", "PyQt5", "cv2", "pyvista", "vtk", "scipy", "lxml"),
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
    "designer.render_time.*": ("bpy", "PySide6", "cv2", "lxml", "scipy", "designer.render",
                               "designer.survey"),
    "designer.flight": ("lxml", "pyproj", "pyexiv2", "designer.flight.importer"),
    # the validations (and the commands running them) plan and check renders; only the
    # render worker, in Blender, loads bpy
    "designer.experiments.*": ("bpy",),
    "designer.bench.accuracy": ("bpy",),
    "designer.cli.validate": ("bpy",),
    "designer.gui.state.*": ("PySide6", "pyvista", "pyvistaqt", "vtk", "vtkmodules"),
}

#: third-party modules made missing (``sys.modules[name] = None``) in a fresh interpreter
#: with a bare environment → modules that must import all the same (P.* = every module of
#: package P): the GUI's Qt-free state and the command line, whose
#: parser must also take a ``gui`` command there
IMPORT_WITHOUT: dict[tuple[str, ...], tuple[str, ...]] = {
    ("PySide6", "vtk", "vtkmodules", "pyvista", "pyvistaqt"): (
        "designer.gui", "designer.gui.state.*", "designer.gui.xvfb", "designer.cli.gui",
        "designer.cli.main"),
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


def _imports(root: Path, module: str, expand: bool = False) -> list[tuple[int, str]]:
    """(line, imported module) of every import statement of ``module``; with ``expand``,
    ``from designer.p import m`` also names the module designer.p.m where there is one."""
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
            elif expand and node.module.startswith("designer."):  # from designer.p import m
                base = root.joinpath(*node.module.split(".")[1:])
                out += [(node.lineno, f"{node.module}.{a.name}") for a in node.names
                        if (base / f"{a.name}.py").is_file() or (base / a.name).is_dir()]
    return out


def violations(root: Path, module: str) -> list[str]:
    """What ``module`` (a file under ``root``, the designer package) imports against the
    contract, as 'module:line imports X (reason)'."""
    own = _package_of(module)
    inside = module.split(".", 1)[1] if "." in module else ""
    allowed = MAY_IMPORT.get(own)
    found = []
    for sub, barred in SUBPACKAGE_MAY_NOT_IMPORT.items():
        if not (inside == sub or inside.startswith(sub + ".")):
            continue
        for line, name in _imports(root, module, expand=True):
            within = name.split(".", 1)[1] if name.startswith("designer.") else ""
            if any(within == b or within.startswith(b + ".") for b in barred):
                found.append(f"{module}:{line} imports {name}: {sub} may not import "
                             f"{', '.join(barred)}")
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
    # the checks weigh the survey; the survey never asks the checks
    ("survey/coverage.py", "    from designer.checks.hard_cases import point_spread",
     "survey may import only"),
    ("checks/hard_cases.py", "from designer.sfm.georeference import fit_similarity",
     "checks may import only"),
    ("render_time/record.py", "from designer.render.job import PreparedJob",
     "render_time may import only"),
    ("evaluate/point_clouds.py", "from designer.scene._private import x", "private"),
    ("effects/chain.py", "import bpy", "only render.worker may"),
    ("sfm/reconstruct.py", "from PySide6 import QtCore", "only gui.qt, gui.app, bench.gui"),
    # the GUI's state stays Qt-free: no Qt or VTK import, not even a lazy one, and none of
    # the widgets
    ("gui/state/document.py", "from PySide6.QtCore import QObject", "only gui.qt, gui.app"),
    ("gui/state/wording.py", "    import pyvista", "only gui.qt, bench may"),
    ("gui/state/view_geometry.py", "    from pyvistaqt import QtInteractor", "only gui.qt may"),
    ("gui/state/edits.py", "from designer.gui.qt.widgets import Bindings",
     "gui.state may not import gui.qt"),
    ("gui/state/derived.py", "    from designer.gui import app", "may not import gui.qt, gui.app"),
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


def _is_type_checking(node: ast.AST) -> bool:
    test = node.test if isinstance(node, ast.If) else None
    return ((isinstance(test, ast.Name) and test.id == "TYPE_CHECKING")
            or (isinstance(test, ast.Attribute) and test.attr == "TYPE_CHECKING"))


def _run_time_imports(tree: ast.AST):
    """Every import statement of ``tree``, at any depth, except those under ``if
    TYPE_CHECKING:`` (never run)."""
    for node in ast.iter_child_nodes(tree):
        if isinstance(node, ast.Import | ast.ImportFrom):
            yield node
        elif _is_type_checking(node):
            for child in node.orelse:
                yield from _run_time_imports(ast.Module(body=[child], type_ignores=[]))
        else:
            yield from _run_time_imports(node)


def _lazy_table(tree: ast.AST) -> dict[str, str]:
    """A lazy package face's ``attach(__name__, {name: module, ...})`` table; {} if none."""
    for node in ast.walk(tree):
        if (isinstance(node, ast.Call) and isinstance(node.func, ast.Name)
                and node.func.id == "attach" and len(node.args) == 2
                and isinstance(node.args[1], ast.Dict)):
            return {k.value: v.value for k, v in zip(node.args[1].keys, node.args[1].values,
                                                     strict=True)}
    return {}


def module_graph(root: Path) -> dict[str, dict[str, int]]:
    """module → {designer module it imports: line of the first such import}, for every
    module of the package at ``root``; see :func:`test_no_import_cycle_between_modules`
    for what counts as an edge."""
    modules = set(_modules(root))
    trees, packages = {}, set()
    for module in modules:
        rel = Path(*module.split(".")[1:])
        path = root / rel / "__init__.py"
        if path.is_file():
            packages.add(module)
        else:
            path = root / rel.with_suffix(".py")
        trees[module] = ast.parse(path.read_text(), str(path))
    tables = {m: _lazy_table(t) for m, t in trees.items() if m in packages}

    def nearest(name: str) -> str | None:  # the module itself, else its nearest package
        while name and name not in modules:
            name = name.rpartition(".")[0]
        return name or None

    graph: dict[str, dict[str, int]] = {}
    for module, tree in trees.items():
        edges = graph[module] = {}
        here = module if module in packages else module.rpartition(".")[0]
        for node in _run_time_imports(tree):
            if isinstance(node, ast.Import):
                targets = [nearest(a.name) for a in node.names]
            else:
                base = node.module or ""
                if node.level:  # relative: from its package, one level up per extra dot
                    parent = here.split(".")[:len(here.split(".")) - node.level + 1]
                    base = ".".join(parent + ([base] if base else []))
                targets = []
                for a in node.names:
                    if f"{base}.{a.name}" in modules:
                        targets.append(f"{base}.{a.name}")
                    elif a.name in tables.get(base, {}):
                        targets.append(nearest(tables[base][a.name]))
                    else:
                        targets.append(nearest(base))
            for target in targets:
                if target is not None and target != module:
                    edges.setdefault(target, node.lineno)
    return graph


def import_cycles(graph: dict[str, dict[str, int]]) -> list[list[str]]:
    """One cycle per strongly connected group of modules, as [a, b, ..., a] (shortest
    from the group's first module), the groups sorted."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    groups = []
    for start in sorted(graph):  # Tarjan's algorithm, without recursion
        if start in index:
            continue
        work = [(start, iter(sorted(graph[start])))]
        index[start] = low[start] = len(index)
        stack.append(start)
        while work:
            node, children = work[-1]
            child = next(children, None)
            if child is None:
                work.pop()
                if work:
                    low[work[-1][0]] = min(low[work[-1][0]], low[node])
                if low[node] == index[node]:
                    group = []
                    while not group or group[-1] != node:
                        group.append(stack.pop())
                    if len(group) > 1:
                        groups.append(sorted(group))
            elif child not in graph:
                continue
            elif child not in index:
                index[child] = low[child] = len(index)
                stack.append(child)
                work.append((child, iter(sorted(graph[child]))))
            elif child in stack:
                low[node] = min(low[node], index[child])
    return [_shortest_cycle(graph, group) for group in sorted(groups)]


def _shortest_cycle(graph: dict[str, dict[str, int]], group: list[str]) -> list[str]:
    """The shortest cycle from ``group[0]`` back to it within ``group`` (breadth first)."""
    first, members = group[0], set(group)
    came_from: dict[str, str] = {}
    level = [first]
    while level:
        following = []
        for node in level:
            for child in sorted(graph[node]):
                if child == first:
                    path = [first, node]
                    while path[-1] != first:
                        path.append(came_from[path[-1]])
                    return path[::-1]
                if child in members and child not in came_from:
                    came_from[child] = node
                    following.append(child)
        level = following
    raise AssertionError(f"no cycle in {group}")


def _format_cycle(graph: dict[str, dict[str, int]], cycle: list[str]) -> str:
    return " → ".join(f"{a} (line {graph[a][b]})" for a, b in itertools.pairwise(cycle)) + \
        f" → {cycle[-1]}"


def test_no_import_cycle_between_modules():
    """No module imports itself through others, within a package or across packages.

    Edges, one per import statement of a module (at module level or inside a function,
    class or ``try``; not under ``if TYPE_CHECKING:``, which never runs):

    * ``import designer.a.b`` → designer.a.b;
    * ``from designer.a import b`` → designer.a.b when that is a module, else the module
      that the lazy face of designer.a (its ``attach`` table) says defines ``b``, else
      designer.a itself (a name defined in the face, or a compiled extension module);
    * relative imports likewise, from the importing module's package.

    Importing designer.a.b also runs designer/a/__init__.py first; that implicit import
    of a parent package is not an edge (Python allows a package face to import its own
    submodules while one of them is being imported; the lazy faces import none at all).
    """
    graph = module_graph(PACKAGE)
    cycles = import_cycles(graph)
    assert not cycles, "import cycles:\n" + "\n".join(_format_cycle(graph, c)
                                                      for c in cycles)


@pytest.mark.parametrize(("graph", "cycles"), [
    ({"a": {"b": 1}, "b": {"c": 1}, "c": {}}, []),
    ({"a": {"b": 1}, "b": {"a": 1}}, [["a", "b", "a"]]),
    ({"a": {"b": 1}, "b": {"c": 1}, "c": {"a": 1, "d": 1}, "d": {}}, [["a", "b", "c", "a"]]),
    ({"x": {"a": 1}, "a": {"b": 1, "c": 1}, "b": {"c": 1}, "c": {"a": 1}, "d": {"e": 1},
      "e": {"d": 1}}, [["a", "c", "a"], ["d", "e", "d"]]),
    ({"a": {"b": 1, "z": 1}, "b": {"a": 1}}, [["a", "b", "a"]]),  # z: outside the graph
])
def test_the_cycle_finder(graph, cycles):
    assert import_cycles(graph) == cycles


_FACE = ('from designer._lazy import attach\n'
         '__getattr__, __dir__, __all__ = attach(__name__, {"f": "designer.pkg.one"})\n')


@pytest.mark.parametrize(("one", "two", "cycle"), [
    ("from designer.pkg.two import g", "from designer.pkg.one import f",
     ["designer.pkg.one", "designer.pkg.two", "designer.pkg.one"]),
    ("import designer.pkg.two", "def g():\n    from designer.pkg import one",
     ["designer.pkg.one", "designer.pkg.two", "designer.pkg.one"]),
    ("def f():\n    from designer.pkg.two import g", "from designer.pkg import f",
     ["designer.pkg.one", "designer.pkg.two", "designer.pkg.one"]),  # through the face
    ("from .two import g", "from . import one",
     ["designer.pkg.one", "designer.pkg.two", "designer.pkg.one"]),
    ("from designer.pkg.two import g", "from designer.other import h",
     ["designer.other", "designer.pkg.one", "designer.pkg.two", "designer.other"]),
    ("from designer.pkg.two import g", "from designer.other import k", None),  # other module
    ("from designer.pkg.two import g",
     "from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n    from designer.pkg import f",
     None),
    ("from designer.pkg.two import g", "from designer.pkg import _native_ext", None),
])
def test_the_cycle_check_catches_a_planted_cycle(tmp_path, one, two, cycle):
    """A small package: pkg with a lazy face (``f`` from pkg.one), modules pkg.one and
    pkg.two, and other (importing pkg.one); planted imports in one and two make a cycle
    or not. pkg/_native_ext stands for a compiled extension (no .py file)."""
    root = tmp_path / "designer"
    (root / "pkg").mkdir(parents=True)
    files = {"__init__.py": "", "_lazy.py": "def attach(p, names): ...\n",
             "pkg/__init__.py": _FACE, "pkg/one.py": one + "\n",
             "pkg/two.py": two + "\n\ndef g(): ...\n",
             "other.py": "from designer.pkg.one import f\n\ndef h(): ...\n"}
    if "k" in two:
        files["other.py"] = "def k(): ...\n"
    for name, text in files.items():
        (root / name).write_text(text)
    found = import_cycles(module_graph(root))
    assert found == ([] if cycle is None else [cycle])


def test_the_cycle_check_sees_a_cycle_planted_in_the_package(tmp_path):
    """A copy of the package with one function-level import closing a cycle inside one
    package (job_light → job_buildings → job_files, planted: job_files → job_light) fails
    the check."""
    root = tmp_path / "designer"
    shutil.copytree(PACKAGE, root, ignore=shutil.ignore_patterns("__pycache__"))
    path = root / "render" / "job_files.py"
    path.write_text(path.read_text()
                    + "\n\ndef _late():\n    from designer.render.job_light import frame_suns\n")
    graph = module_graph(root)
    cycles = import_cycles(graph)
    assert cycles == [["designer.render.job_buildings", "designer.render.job_files",
                       "designer.render.job_light", "designer.render.job_buildings"]]
    assert "designer.render.job_files (line " in _format_cycle(graph, cycles[0])


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


@pytest.mark.parametrize("missing", sorted(IMPORT_WITHOUT), ids=",".join)
def test_importing_works_without_the_missing_libraries(missing):
    modules = []
    for name in IMPORT_WITHOUT[missing]:  # P.* → every module of package P
        if name.endswith(".*"):
            folder = PACKAGE.joinpath(*name[:-2].split(".")[1:])
            modules += [f"{name[:-2]}.{p.stem}" for p in sorted(folder.glob("*.py"))
                        if p.stem != "__init__"]
        else:
            modules.append(name)
    assert len(modules) > len(IMPORT_WITHOUT[missing])  # the state's modules were found
    code = ("import sys\n"
            f"for name in {missing!r}:\n"
            "    sys.modules[name] = None\n"
            + "".join(f"import {name}\n" for name in modules))
    if "designer.cli.main" in modules:
        code += ("from designer.cli.main import build_parser\n"
                 "build_parser().parse_args(['gui', 'x.xml', '--screenshot', 'x.png'])\n")
    root = PACKAGE.parent
    result = subprocess.run([sys.executable, "-c", code], cwd=root, capture_output=True,
                            text=True, env={"PYTHONPATH": str(root), "PATH": "/usr/bin"})
    assert result.returncode == 0, result.stderr


def test_the_missing_library_check_sees_an_import():
    """The check can fail: the GUI's main window needs Qt."""
    code = ("import sys\nsys.modules['PySide6'] = None\n"
            "import designer.gui.qt.main_window\n")
    result = subprocess.run([sys.executable, "-c", code], cwd=PACKAGE.parent,
                            capture_output=True, text=True)
    assert result.returncode != 0 and "PySide6" in result.stderr


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


#: the longest a function of the package may be, lines from ``def`` to its last line
MAX_FUNCTION_LINES = 80

#: functions over :data:`MAX_FUNCTION_LINES` lines, 'path:qualified name' → why it is not
#: split yet. The list only shrinks: a function split below the limit must leave it (the
#: test says so), and a new long function is split, not added.
LONG_FUNCTIONS: dict[str, str] = {
    # pipelines with one option inline per step; being split into named steps (issue #54)
    "designer/study/run.py:_execute":
        "the study's render and processing tasks scheduled with their caches and progress "
        "in one loop; its task kinds to become functions of their own",
    # numerical kernels: one pass over arrays each, written out for numba or for speed
    "designer/effects/_resample_kernels.py:bspline_coefficients":
        "a numba kernel: the two recursive filter passes share loop variables; split, it "
        "would copy the image between passes",
    "designer/bench/rolling_reference.py:adjust_rolling_ceres":
        "the old solver kept unchanged in what it computes, as the oracle of the "
        "vectorised one (bench rolling-adjustment)",
    "designer/evaluate/compare.py:compare_cloud":
        "cloud-to-mesh distances, their statistics and files in one function; to split "
        "into distances, statistics and writing",
    # text written out line by line: long, but a flat sequence of sections
    "designer/experiments/projection_report.py:_markdown":
        "the validation report's sections written one after another (flat text)",
    "designer/experiments/texture.py:write_texture_report":
        "the texture validation's report written section after section (flat text)",
    "designer/render/readme.py:readme_text":
        "the output folder's README, one paragraph per file kind (flat text)",
    "designer/gui/state/wording.py:issue_text":
        "one branch per kind of validation issue; to go with structured errors "
        "(issue #54 item 4)",
    "designer/export/dispatch.py:write_all":
        "one block per export format; to become a registry of exporters",
    "designer/survey/flight.py:plan_flight":
        "the flight planner's strips, crosshatch, terrain following and stations in one "
        "pass; to split by what it plans",
    # Qt panels: the widgets of one panel laid out in order
    "designer/gui/qt/panels/flight.py:FlightPanel.build":
        "the panel's widgets laid out in reading order; shared panel widgets (issue #54 "
        "item 5) shorten it",
    "designer/gui/qt/panels/study.py:StudyPanel.build":
        "the panel's widgets laid out in reading order (as FlightPanel.build)",
    "designer/gui/qt/panels/processing.py:ProcessingPanel.build":
        "the panel's widgets laid out in reading order (as FlightPanel.build)",
    "designer/gui/qt/panels/gcps.py:GcpPanel.build":
        "the panel's widgets laid out in reading order (as FlightPanel.build)",
}


def function_lengths(root: Path) -> dict[str, int]:
    """'path:qualified name' → lines (``def`` to the last line, decorators aside) of every
    function and method of the package under ``root``, nested ones too."""
    out: dict[str, int] = {}

    def walk(node: ast.AST, path: str, prefix: str) -> None:
        for child in ast.iter_child_nodes(node):
            if isinstance(child, ast.FunctionDef | ast.AsyncFunctionDef):
                name = prefix + child.name
                out[f"{path}:{name}"] = child.end_lineno - child.lineno + 1
                walk(child, path, name + ".")
            elif isinstance(child, ast.ClassDef):
                walk(child, path, prefix + child.name + ".")
            else:
                walk(child, path, prefix)

    for file in sorted(root.rglob("*.py")):
        walk(ast.parse(file.read_text(), str(file)), str(file.relative_to(root.parent)), "")
    return out


def test_no_function_is_longer_than_80_lines():
    """A function reads in one screen: none is over :data:`MAX_FUNCTION_LINES` lines but
    those of :data:`LONG_FUNCTIONS`, each with why. The list only shrinks: an entry whose
    function is gone or short now fails too, so that it leaves the list."""
    lengths = function_lengths(PACKAGE)
    long = {name for name, n in lengths.items() if n > MAX_FUNCTION_LINES}
    new = sorted(long - set(LONG_FUNCTIONS))
    assert not new, "split these into named steps:\n" + "\n".join(
        f"{name} ({lengths[name]} lines)" for name in new)
    done = sorted(set(LONG_FUNCTIONS) - long)
    assert not done, "short or gone now; take them off LONG_FUNCTIONS:\n" + "\n".join(done)


def test_the_length_check_measures_nested_functions_and_methods(tmp_path):
    root = tmp_path / "designer"
    root.mkdir()
    body = "".join(f"        x{i} = {i}\n" for i in range(80))
    (root / "one.py").write_text(f"class A:\n    def build(self):\n        def inner():\n"
                                 f"            pass\n{body}\n\ndef short():\n    pass\n")
    lengths = function_lengths(root)
    assert lengths == {"designer/one.py:A.build": 83, "designer/one.py:A.build.inner": 2,
                       "designer/one.py:short": 2}
