import subprocess
import sys

LAZY = ["bpy", "PySide6", "pyvista", "vtk", "rasterio", "plyfile"]


def test_scene_modules_load_heavy_readers_lazily():
    code = (
        "import sys, pkgutil, importlib, designer.scene as scene\n"
        "for m in pkgutil.iter_modules(scene.__path__):\n"
        "    importlib.import_module('designer.scene.' + m.name)\n"
        f"print(','.join(m for m in {LAZY!r} if m in sys.modules))\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True)
    assert out.stdout.strip() == ""
