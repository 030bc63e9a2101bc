import subprocess
import sys

FORBIDDEN = ["bpy", "PySide6", "cv2", "pyvista", "pyvistaqt", "vtk", "scipy"]


def test_the_core_imports_numpy_only():
    code = (
        "import sys, pkgutil, importlib, designer.core as core\n"
        "for m in pkgutil.iter_modules(core.__path__):\n"
        "    importlib.import_module('designer.core.' + m.name)\n"
        f"bad = [m for m in {FORBIDDEN!r} if m in sys.modules]\n"
        "print(','.join(bad))\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == ""
