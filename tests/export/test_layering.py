import subprocess
import sys

FORBIDDEN = ["bpy", "PySide6", "cv2", "pyvista", "pyvistaqt", "vtk", "scipy", "pycolmap"]


def test_the_exporters_need_numpy_and_lxml_only():
    code = (
        "import sys, pkgutil, importlib, designer.export as export\n"
        "for m in pkgutil.iter_modules(export.__path__):\n"
        "    importlib.import_module('designer.export.' + m.name)\n"
        f"bad = [m for m in {FORBIDDEN!r} if m in sys.modules]\n"
        "print(','.join(bad))\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == ""
