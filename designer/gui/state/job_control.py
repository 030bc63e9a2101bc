"""Cooperative cancellation of the window's background jobs (Qt-free).

The window's task runner (:mod:`designer.gui.qt.tasks`) runs each job inside
:func:`job`, with a test that says whether a newer job of the same key was submitted
since. Long jobs call :func:`check` between their stages (or pass it to the survey code
that loops): a superseded job raises :class:`Superseded` there and stops, so the thread
and the interpreter lock are free for the job of the latest edit. Outside a job
:func:`check` does nothing.
"""

from __future__ import annotations

import threading
from collections.abc import Callable, Iterator
from contextlib import contextmanager

_local = threading.local()


class Superseded(Exception):
    """A newer job of the same key was submitted: this one's result would be dropped."""


@contextmanager
def job(superseded: Callable[[], bool]) -> Iterator[None]:
    """Run the body as a job that :func:`check` stops once ``superseded()`` is true."""
    previous = getattr(_local, "superseded", None)
    _local.superseded = superseded
    try:
        yield
    finally:
        _local.superseded = previous


def check() -> None:
    """Raise :class:`Superseded` if the job running in this thread was superseded."""
    superseded = getattr(_local, "superseded", None)
    if superseded is not None and superseded():
        raise Superseded
