"""designer.effects is plain numpy/SciPy/OpenCV: no bpy, no Qt, no project XML stack."""

import subprocess
import sys

FORBIDDEN = ["bpy", "PySide6", "pyvista", "pyvistaqt", "vtk", "lxml", "designer.project"]


def test_effects_import_without_blender_or_the_project_stack():
    code = (
        "import sys, pkgutil, importlib, designer.effects as fx\n"
        "for m in pkgutil.iter_modules(fx.__path__):\n"
        "    importlib.import_module('designer.effects.' + m.name)\n"
        f"print(','.join(m for m in {FORBIDDEN!r} if m in sys.modules))\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == ""
