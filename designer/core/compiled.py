"""designer's compiled extension modules, loaded on first use.

``pip install`` builds them from their C sources (``designer/core/csrc``: the terrain's
ray marching and noise; ``designer/evaluate/csrc``: the comparison's kernels); a C
compiler and the Python headers are needed, and ``make setup`` has both. They load in
about a millisecond: nothing is compiled or cached at run time.
"""

from __future__ import annotations

import importlib
from functools import cache

from designer.errors import DesignerError


@cache
def extension(name: str):
    """The extension module ``name`` (``"designer.core._cterrain"``, …); a one-line error
    saying how to build it when it is missing."""
    try:
        return importlib.import_module(name)
    except ImportError as error:
        raise DesignerError(
            f"designer's compiled kernels are missing ({error}): build them with "
            "`pip install -e .` in the source folder (needs a C compiler)") from None


def cterrain():
    """``designer.core._cterrain``: the terrain's ray marching and value noise."""
    return extension("designer.core._cterrain")
