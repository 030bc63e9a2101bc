"""A value that is not a number where the file holds one (``width-mm="abc"``, a typo
in a hand-edited file) is listed in the Problems list as the panel, the field, its unit
and range as the window labels them, never by the XML element and attribute."""

from __future__ import annotations

import re

import pytest
from PySide6.QtCore import Qt

from designer.gui.state import files
from designer.project import project_to_bytes
from tests.gui.helpers import open_with_ctrl_o, problems

pytestmark = pytest.mark.gui


def test_values_that_are_not_numbers_are_worded_as_the_panels_label_them(qtbot, window,
                                                                         tmp_path):
    w = window
    text = project_to_bytes(files.blank_project()).decode()
    for old, new in [(r'<sensor width-mm="[^"]*"', '<sensor width-mm="abc"'),
                     (r'elevation-deg="50.0"', 'elevation-deg="high"'),
                     (r'<focal-length-mm>[^<]*<', '<focal-length-mm>8,8<'),
                     (r'<image width-px="\d+"', '<image width-px="12.5"'),
                     (r'height-mm="[^"]*"', 'height-mm="INF"')]:
        text, n = re.subn(old, new, text)
        assert n == 1, old
    path = tmp_path / "hand-edited.xml"
    path.write_text(text)

    open_with_ctrl_o(qtbot, w, path)
    listed = problems(w)
    assert len(listed) == 5, listed
    joined = "\n".join(listed)
    for xml in ("width-mm", "<sensor>", "<sun>", "elevation-deg", "<focal-length-mm>",
                "width-px", "<image>", "height-mm", "expected:", "is not valid here"):
        assert xml not in joined, (xml, listed)
    want = [
        "Camera › sensor width “abc” is not a number; give a number greater than 0 and at "
        "most 1000 mm",
        "Lighting › elevation “high” is not a number; give a number greater than 0 and at "
        "most 90 °",
        "Camera › focal length “8,8” is not a number; give a number greater than 0 and at "
        "most 1000 mm",
        "Camera › image width “12.5” is not a whole number; give a whole number from 1 to "
        "100000 px",
        "Camera › sensor height infinity must be greater than 0 and at most 1000 mm",
    ]
    for line in want:
        assert any(line in shown for shown in listed), (line, listed)
    assert all(line.startswith(f"{path}:") for line in listed)  # the place stays

    # a click on the elevation line brings the Lighting panel to the front
    w.docks["Terrain"].raise_()
    row = next(i for i, line in enumerate(listed) if "elevation" in line)
    rect = w.problems.visualItemRect(w.problems.item(row))
    qtbot.mouseClick(w.problems.viewport(), Qt.MouseButton.LeftButton, pos=rect.center())
    qtbot.waitUntil(lambda: not w.panels["Lighting"].visibleRegion().isEmpty(),
                    timeout=3000)
