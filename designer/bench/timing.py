"""Best-of-N wall-clock timing shared by the benchmarks."""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import TypeVar

T = TypeVar("T")


def best_of(repeats: int, func: Callable[[], T]) -> tuple[float, T]:
    """(shortest wall-clock seconds of ``repeats`` calls of ``func``, the last call's result).

    ``func`` runs at least once. The minimum is the figure least disturbed by other
    processes on the machine.
    """
    best = float("inf")
    for _ in range(max(1, repeats)):
        t0 = time.perf_counter()
        result = func()
        best = min(best, time.perf_counter() - t0)
    return best, result
