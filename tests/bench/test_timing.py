import time

import pytest

from designer.bench.timing import best_of


@pytest.mark.parametrize(("repeats", "calls"), [(3, 3), (1, 1), (0, 1)])
def test_best_of_runs_at_least_once_and_returns_the_last_result(repeats, calls):
    results = iter(range(10))
    seconds, last = best_of(repeats, lambda: next(results))
    assert last == calls - 1
    assert seconds > 0


def test_best_of_reports_the_shortest_call(monkeypatch):
    """On a clock that reads 0, 5 | 10, 12 | 20, 27 the three calls take 5, 2 and 7 s."""
    readings = iter([0.0, 5.0, 10.0, 12.0, 20.0, 27.0])
    monkeypatch.setattr(time, "perf_counter", lambda: next(readings))
    seconds, _ = best_of(3, lambda: None)
    assert seconds == 2.0
