#!/usr/bin/env python3
"""Seconds each test file took in a measured run, written as tests/durations.json.

    .venv/bin/python -m pytest -n 2 --dist loadfile --junitxml=run.xml
    python3 scripts/test-durations.py run.xml > tests/durations.json

The test run starts the files that took longest first (tests/conftest.py), so the two
workers do not end with one of them running a long file alone. A file missing from the
table (a new one) starts after every file in it; re-measure when the slow files change.
"""

from __future__ import annotations

import collections
import json
import sys
import xml.etree.ElementTree as ET


def file_seconds(junit_xml: str) -> dict[str, float]:
    seconds: collections.Counter[str] = collections.Counter()
    for case in ET.parse(junit_xml).getroot().iter("testcase"):
        # classname "tests.gui.test_x" or "tests.gui.test_x.TestClass"
        parts = [p for p in case.get("classname", "").split(".") if not p[:1].isupper()]
        if parts:
            seconds["/".join(parts) + ".py"] += float(case.get("time", 0.0))
    return {name: round(s, 1) for name, s in seconds.most_common()}


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit("usage: test-durations.py JUNIT.xml > tests/durations.json")
    json.dump(file_seconds(sys.argv[1]), sys.stdout, indent=1)
    sys.stdout.write("\n")
