"""Moments in UTC as the project files write them: read, refused, written back."""

import datetime as dt

import pytest

from designer.project.utc import EXAMPLE_UTC, iso_utc, parse_utc


def test_a_utc_moment_is_read_in_any_utc_spelling():
    want = dt.datetime(2026, 6, 21, 9, 30, tzinfo=dt.UTC)
    assert parse_utc(EXAMPLE_UTC) == want
    assert parse_utc(" 2026-06-21T09:30:00+00:00 ") == want
    assert parse_utc("2026-06-21T09:30:00.250Z") == want + dt.timedelta(milliseconds=250)


@pytest.mark.parametrize("text", ["2026-06-21T11:30:00+02:00", "2026-06-21T09:30:00",
                                  "21.06.2026 09:30", ""])
def test_other_zones_local_times_and_other_text_are_not_utc(text):
    assert parse_utc(text) is None


def test_written_moments_read_back_to_the_microsecond():
    moment = dt.datetime(2026, 6, 21, 9, 30, 4, 250000, tzinfo=dt.UTC)
    assert iso_utc(moment) == "2026-06-21T09:30:04.250000Z"
    assert parse_utc(iso_utc(moment)) == moment
    east = moment.astimezone(dt.timezone(dt.timedelta(hours=2)))
    assert iso_utc(east) == "2026-06-21T09:30:04.250000Z"
