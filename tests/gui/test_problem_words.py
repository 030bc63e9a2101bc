"""The Problems list names a value the file check refuses as the panel and field that edit
it (``Camera › sensor width``), never by its XML element and attribute; a click on the
line brings that panel to the front."""

from __future__ import annotations

import re

import pytest
from PySide6.QtCore import Qt

from designer.gui.state import files
from designer.project import project_to_bytes
from tests.gui.helpers import open_with_ctrl_o, problems

pytestmark = pytest.mark.gui


def test_a_refused_file_names_panel_and_field_as_labelled(qtbot, window, tmp_path):
    w = window
    text = project_to_bytes(files.blank_project()).decode()
    text = re.sub(r'<sensor width-mm="[^"]*" height-mm="[^"]*"',
                  '<sensor width-mm="13200" height-mm="8800"', text)
    text = text.replace('elevation-deg="50.0"', 'elevation-deg="95"')
    path = tmp_path / "hand-edited.xml"
    path.write_text(text)

    open_with_ctrl_o(qtbot, w, path)
    listed = problems(w)
    assert len(listed) == 3, listed
    joined = "\n".join(listed)
    assert "width-mm" not in joined and "<sensor>" not in joined and "<sun>" not in joined
    assert any("Camera › sensor width 13200 must be greater than 0 and at most 1000 mm"
               in line for line in listed), listed
    assert any("Camera › sensor height 8800 must be greater than 0 and at most 1000 mm"
               in line for line in listed), listed
    assert any("Lighting › elevation 95 must be greater than 0 and at most 90 °"
               in line for line in listed), listed
    assert all(line.startswith(f"{path}:") for line in listed)  # the place stays

    # a click on the sensor line brings the Camera panel to the front
    w.docks["Terrain"].raise_()
    row = next(i for i, line in enumerate(listed) if "sensor width" in line)
    rect = w.problems.visualItemRect(w.problems.item(row))
    qtbot.mouseClick(w.problems.viewport(), Qt.MouseButton.LeftButton, pos=rect.center())
    qtbot.waitUntil(lambda: not w.panels["Camera"].visibleRegion().isEmpty(), timeout=3000)


def test_every_declared_field_is_placed_in_a_panel():
    """A range problem of any declared field of the project's elements names a panel
    (the Problems line's ``Panel › field``), as its element's place in the project says."""
    from designer.gui.state.field_places import PANEL_KEYWORDS, _classes, panel_for_object
    from designer.project import model as m
    from designer.project.declare import declared, element_of

    titles = {title for title, _words in PANEL_KEYWORDS} | {"Moving objects"}
    unplaced = []
    for cls in _classes(m.Project):
        el = element_of(cls)
        if el is None or not declared(cls) or cls in (m.Origin, m.SceneObject, m.Placement,
                                                          m.Rig):
            continue  # the origin, scene objects (and their placement) and rigs have no
            # panel of their own
        for d in declared(cls):
            tag = d.xml if d.attr.text else (d.attr.child or el.tag)
            panel = panel_for_object(object.__new__(cls), tag)
            if panel not in titles:
                unplaced.append(f"{cls.__name__}.{d.name}: {panel}")
    assert not unplaced, unplaced
