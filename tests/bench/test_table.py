"""The benchmarks' text table: headings aligned as their values, a rule as wide as the
headings unless told, a row per measurement, the note last."""

import pytest

from designer.bench.table import Column, text_table


def test_headings_align_as_their_values():
    columns = [Column("step", "<6", "step"), Column("n", "4d", "n"),
               Column("s", ">7.2f", "s"),
               Column("per s", ">6", lambda r: f"{r['n'] / r['s']:.0f}/s")]
    rows = [{"step": "read", "n": 12, "s": 0.5}, {"step": "write", "n": 3, "s": 1.25}]
    assert text_table(columns, rows, "(best of 3)").splitlines() == [
        "step      n       s  per s",
        "-" * 26,
        "read     12    0.50   24/s",
        "write     3    1.25    2/s",
        "(best of 3)"]


def test_the_rule_width_and_no_note():
    table = text_table([Column("ms", ">8.0f", "ms")], [{"ms": 12.6}], rule_width=10)
    assert table.splitlines() == ["      ms", "-" * 10, "      13"]


def test_a_missing_value_is_an_error():
    with pytest.raises(KeyError):
        text_table([Column("ms", ">8.0f", "ms")], [{"s": 1.0}])
