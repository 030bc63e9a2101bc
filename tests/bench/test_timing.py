import math

import pytest

from designer.bench.timing import best_of


@pytest.mark.parametrize(("repeats", "calls"), [(3, 3), (1, 1), (0, 1)])
def test_best_of_runs_at_least_once_and_returns_the_last_result(repeats, calls):
    results = iter(range(10))
    seconds, last = best_of(repeats, lambda: next(results))
    assert last == calls - 1
    assert math.isfinite(seconds) and seconds >= 0
