"""designer's compiled extension modules, loaded on first use.

``pip install`` builds them from their C sources (``designer/core/csrc``: the terrain's
ray marching and noise; ``designer/evaluate/csrc``: the comparison's kernels); a C
compiler and the Python headers are needed, and ``make setup`` has both. They load in
about a millisecond: nothing is compiled or cached at run time.
"""

from __future__ import annotations

from functools import cache

from designer.errors import DesignerError


def missing(error: ImportError) -> DesignerError:
    """The one-line error for a compiled module that is not built, saying how to build it."""
    return DesignerError(
        f"designer's compiled kernels are missing ({error}): build them with "
        "`pip install -e .` in the source folder (needs a C compiler)")


@cache
def cterrain():
    """``designer.core._cterrain``: the terrain's ray marching and value noise."""
    try:
        from designer.core import _cterrain
    except ImportError as error:
        raise missing(error) from None
    return _cterrain
