"""Run a block of code with OpenBLAS on one thread.

The Schur solver's dense Cholesky (a few hundred unknowns) is over in milliseconds on
one thread; OpenBLAS splits it over every core, and its threads wait for each other by
spinning: on a machine whose cores are busy with other work a 560 × 560 factorisation
then takes 60 times as long (scipy.linalg.cho_factor, 2 shared cores at load average 9:
1.8 s wall instead of 0.03 s). This
sets the thread count of every OpenBLAS loaded in the process (numpy's and scipy's own
copies) for the duration of a ``with`` block, as threadpoolctl does, and restores it.
Where the libraries cannot be found (no /proc, another BLAS) nothing changes.
"""

from __future__ import annotations

import contextlib
import ctypes
from collections.abc import Iterator

#: (getter, setter) symbol names of OpenBLAS builds (plain, 64-bit integers, scipy's)
_SYMBOLS = [(f"{prefix}openblas_get_num_threads{suffix}",
             f"{prefix}openblas_set_num_threads{suffix}")
            for prefix in ("", "scipy_") for suffix in ("", "64_")]


def _openblas_libraries() -> list[tuple[object, object]]:
    """(get, set) functions of each OpenBLAS mapped into this process."""
    try:
        with open("/proc/self/maps") as f:
            paths = sorted({line.split()[-1] for line in f if len(line.split()) >= 6})
        paths = [p for p in paths if "openblas" in p.rsplit("/", 1)[-1].lower()
                 and ".so" in p]
    except OSError:
        return []
    out, seen = [], set()
    for path in paths:
        try:
            lib = ctypes.CDLL(path)
        except OSError:
            continue
        for get_name, set_name in _SYMBOLS:
            get, set_ = getattr(lib, get_name, None), getattr(lib, set_name, None)
            if get is not None and set_ is not None:
                key = ctypes.cast(get, ctypes.c_void_p).value
                if key not in seen:
                    seen.add(key)
                    get.restype = ctypes.c_int
                    set_.argtypes = [ctypes.c_int]
                    out.append((get, set_))
                break
    return out


def openblas_threads() -> list[int]:
    """The thread count of each OpenBLAS in the process (empty without one)."""
    return [int(get()) for get, _ in _openblas_libraries()]


@contextlib.contextmanager
def one_blas_thread() -> Iterator[None]:
    """OpenBLAS on one thread inside the block; the previous counts restored after."""
    libs = _openblas_libraries()
    before = [int(get()) for get, _ in libs]
    for _, set_ in libs:
        set_(1)
    try:
        yield
    finally:
        for (_, set_), n in zip(libs, before, strict=True):
            set_(n)
