import subprocess
import sys

HEAVY = ["numba", "matplotlib", "rasterio", "laspy", "pyvista", "vtk", "bpy", "PySide6"]


def test_importing_evaluate_loads_no_heavy_module():
    """Kernels, plotting and file formats load on first use, so ``designer --help``
    and the other layers stay fast."""
    code = ("import sys, designer.evaluate, designer.cli.compare\n"
            f"print(','.join(m for m in {HEAVY!r} if m in sys.modules))\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True)
    assert out.stdout.strip() == ""
