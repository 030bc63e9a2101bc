"""Booleans that are not true or false, attributes missing and attributes the file does
not know (typos in a hand-edited file) are listed in the Problems list as the panel and
field the window labels, never by the XML element and attribute."""

from __future__ import annotations

import pytest

from tests.gui.helpers import open_with_ctrl_o, problems

pytestmark = pytest.mark.gui


def _open_edited(qtbot, w, tmp_path, edits) -> list[str]:
    """The survey template's file with ``edits`` (old → new, each once) opened with
    Ctrl+O: the lines of the Problems list."""
    from designer.cli.main import main

    path = tmp_path / "hand-edited.xml"
    assert main(["new", str(path), "--template", "survey"]) == 0
    text = path.read_text()
    for old, new in edits:
        assert text.count(old) == 1, old
        text = text.replace(old, new)
    path.write_text(text)
    open_with_ctrl_o(qtbot, w, path)
    listed = problems(w)
    assert listed and all(line.startswith(f"{path}:") for line in listed)  # the place stays
    return listed


def _no_xml(listed, *xml) -> None:
    joined = "\n".join(line.split(": ", 1)[1] for line in listed)  # after the place
    for word in ("<", "=\"", "expected:", "attribute", *xml):
        assert word not in joined, (word, listed)


def test_booleans_that_are_not_true_or_false_are_worded_as_the_panels_label_them(
        qtbot, window, tmp_path):
    listed = _open_edited(qtbot, window, tmp_path, [
        ("<crosshatch>false</crosshatch>", "<crosshatch>no</crosshatch>"),
        ('<vignetting corner-falloff="0.2"/>',
         '<vignetting corner-falloff="0.2" natural-cos4="yes"/>')])
    assert len(listed) == 2, listed
    _no_xml(listed, "crosshatch>", "natural-cos4", "xs:boolean")
    for want in ("Flight › crosshatch “no” is neither true nor false; give true or false "
                 "(the box ticked or not)",
                 "Effects › natural cos⁴ fall-off of the lens “yes” is neither true nor "
                 "false; give true or false (the box ticked or not)"):
        assert any(want in line for line in listed), (want, listed)


def test_missing_attributes_are_worded_as_the_panels_label_them(qtbot, window, tmp_path):
    listed = _open_edited(qtbot, window, tmp_path, [
        (' height-mm="8.8"', ""), (' azimuth-deg="135.0"', "")])
    assert len(listed) == 2, listed
    _no_xml(listed, "height-mm", "azimuth-deg", "required")
    for want in ("Camera › sensor height is missing; give a number greater than 0 and at "
                 "most 1000 mm",
                 "Lighting › azimuth is missing; give a number at least 0 and below 360 °"):
        assert any(want in line for line in listed), (want, listed)


def test_unknown_attributes_are_worded_as_the_panels_label_them(qtbot, window, tmp_path):
    listed = _open_edited(qtbot, window, tmp_path, [
        ('elevation-deg="50.0"', 'elevation-deg="50.0" elevaton-deg="40"'),
        ('<vignetting corner-falloff="0.2"/>', '<vignetting falloff="0.2"/>')])
    assert len(listed) == 2, listed
    _no_xml(listed, "sun>", "vignetting>")
    for want in ("Lighting › unknown setting “elevaton-deg” (did you mean elevation?); "
                 "remove it (the settings here: azimuth, elevation)",
                 "Effects › unknown setting “falloff” (did you mean corner fall-off (ρ²)?); "
                 "remove it (the settings here: "):
        assert any(want in line for line in listed), (want, listed)


def test_hand_mapped_attributes_and_places_off_the_terrain_are_worded_as_labelled(
        qtbot, window, tmp_path):
    """A σ of the simulated survey (an attribute group no element declares on its own)
    that is not a number, and a survey-area vertex off the terrain (a check across
    fields), listed with the labels and panels of the window."""
    listed = _open_edited(qtbot, window, tmp_path, [
        ('sigma-X="0.01"', 'sigma-X="1 cm"'),
        ('<vertex X="511965.0" Y="5405965.0"/>', '<vertex X="0" Y="5405965.0"/>')])
    _no_xml(listed, "sigma-X", "survey-accuracy", "vertex>", "extent>")
    assert any("GCPs › sigma X “1 cm” is not a number; give a number from 0 to 1000000 m"
               in line for line in listed), listed
    # the schema refuses the file first; with the σ mended, the vertex is listed
    (tmp_path / "mended").mkdir()
    listed = _open_edited(qtbot, window, tmp_path / "mended", [
        ('<vertex X="511965.0" Y="5405965.0"/>', '<vertex X="0" Y="5405965.0"/>')])
    _no_xml(listed, "vertex>", "extent>")
    assert any("Flight › vertex 1 of the survey area at X 0, Y 5405965 lies outside the "
               "terrain extent; move it inside, or enlarge the terrain in the Terrain panel"
               in line for line in listed), listed
