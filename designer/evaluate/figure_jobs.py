"""What every figure writer offers: the jobs it may run (writers of :mod:`.maps`) and its
interface, :class:`Writers`.

Shared by the thread writer (:mod:`.figures`) and the forked processes
(:mod:`.figure_processes`), so neither needs the other's module for them.
"""

from __future__ import annotations

#: the writers of :mod:`.maps` a job may call
JOBS = ("write_histogram_png", "write_error_map_png", "write_error_map_geotiff")


class Writers:
    """What every figure writer offers: ``submit``, ``close`` (wait, re-raise the first
    writer error), ``abort``; as a context manager it closes on success and aborts on
    an error."""

    def submit(self, job: str, *args, **kwargs) -> None:
        raise NotImplementedError

    def close(self) -> None:
        raise NotImplementedError

    def abort(self) -> None:
        raise NotImplementedError

    def __enter__(self):
        return self

    def __exit__(self, exc_type, exc, tb) -> None:
        if exc_type is None:
            self.close()
        else:
            self.abort()
