"""Moments in the project's files: ISO 8601 text in UTC (the time line's take-off, the
images' times), read and written here for the model, its checks and the world over time."""

from __future__ import annotations

import datetime as _dt

#: a moment as the files write it, for messages
EXAMPLE_UTC = "2026-06-21T09:30:00Z"


def parse_utc(text: str) -> _dt.datetime | None:
    """The moment of an ISO 8601 text in UTC (aware datetime), or None if it is not one."""
    try:
        moment = _dt.datetime.fromisoformat(text.strip())
    except ValueError:
        return None
    if moment.tzinfo is None or moment.utcoffset() != _dt.timedelta(0):
        return None
    return moment.astimezone(_dt.UTC)


def iso_utc(moment: _dt.datetime) -> str:
    """ISO 8601 text of a UTC moment with microseconds and 'Z': 2026-06-21T09:30:04.250000Z."""
    return moment.astimezone(_dt.UTC).strftime("%Y-%m-%dT%H:%M:%S.%fZ")
