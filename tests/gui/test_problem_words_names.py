"""An id that is not a name the file accepts (a GCP id with a space, an empty one) is
listed in the Problems list as the panel and field that edit it, never by the XML
element and attribute."""

from __future__ import annotations

import pytest

from tests.gui.helpers import open_with_ctrl_o, problems

pytestmark = pytest.mark.gui


def test_ids_that_are_not_names_are_worded_as_the_panels_label_them(qtbot, window,
                                                                    tmp_path):
    from designer.cli.main import main

    w = window
    path = tmp_path / "hand-edited.xml"
    assert main(["new", str(path), "--template", "survey"]) == 0
    text = path.read_text()
    for old, new in [('id="GCP01"', 'id="GCP 01"'), ('id="GCP02"', 'id=""')]:
        assert text.count(old) == 1, old
        text = text.replace(old, new)
    path.write_text(text)

    open_with_ctrl_o(qtbot, w, path)
    listed = problems(w)
    assert len(listed) == 2, listed
    joined = "\n".join(listed)
    for xml in ("<target>", 'id="', "expected:"):
        assert xml not in joined, (xml, listed)
    rule = "use only letters, digits, _ . + - and begin with a letter or digit"
    assert any(f"GCPs › id “GCP 01” is not a name: {rule}" in line
               for line in listed), listed
    assert any(f"GCPs › id is empty: give a name ({rule})" in line
               for line in listed), listed
    assert all(line.startswith(f"{path}:") for line in listed)  # the place stays
