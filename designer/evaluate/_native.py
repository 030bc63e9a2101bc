"""The compiled kernels of the comparison (sources in ``designer/evaluate/csrc``).

``pip install`` builds them into the extension module ``designer.evaluate._ckernels``
(a C compiler and the Python headers are needed; ``make setup`` has both). They load in
about a millisecond — no compiler at run time, nothing to warm up — and run their long
loops on POSIX threads without the GIL.
"""

from __future__ import annotations

import os
from functools import cache

import numpy as np

from designer.core.compiled import missing
from designer.errors import DesignerError


@cache
def ckernels():
    """The extension module; a one-line error saying how to build it when it is missing."""
    try:
        from designer.evaluate import _ckernels
    except ImportError as error:
        raise missing(error) from None
    return _ckernels


def threads() -> int:
    """Threads for a parallel kernel: ``DESIGNER_THREADS`` when set (>= 1), else every
    CPU this process may run on."""
    value = os.environ.get("DESIGNER_THREADS", "").strip()
    if value:
        try:
            n = int(value)
        except ValueError:
            n = 0
        if n < 1:
            raise DesignerError(f"DESIGNER_THREADS={value!r}: give a whole number >= 1")
        return n
    if hasattr(os, "sched_getaffinity"):
        return max(1, len(os.sched_getaffinity(0)))
    return max(1, os.cpu_count() or 1)


def f8(a) -> np.ndarray:
    """``a`` as a C-contiguous float64 array (a view when it already is one)."""
    return np.ascontiguousarray(a, dtype=np.float64)


def i8(a) -> np.ndarray:
    """``a`` as a C-contiguous int64 array (a view when it already is one)."""
    return np.ascontiguousarray(a, dtype=np.int64)
