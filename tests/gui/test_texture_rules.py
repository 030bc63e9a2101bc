"""The Texture panel checks the size of a procedural tile where the texel size or a
repeat is typed, in the numbers typed (and those it is made of: the extent over the
repeats): a tile of more texels than a texture may have, or too few to draw the pattern,
is refused — the field turns red and says why; nothing reaches the project."""

from __future__ import annotations

import pytest
from PySide6.QtWidgets import QDoubleSpinBox, QSpinBox

from tests.gui.helpers import field, open_panel, set_field, wait_idle

pytestmark = pytest.mark.gui


def _refused(qtbot, w, box, text: str) -> str:
    before = w.document.project
    set_field(qtbot, box, text)
    wait_idle(qtbot, w)
    assert w.document.project == before, "applied"
    assert box.property("invalid") and box.text().strip().startswith(text)
    assert not w.sync.errors.get("texture"), w.sync.errors
    message = w.panels["Texture"].input_label.text()
    assert "texel-size-m" not in message and "got (" not in message, message
    return message


def test_texel_size_and_repeats_that_make_no_texture_are_refused(qtbot, window):
    w = window
    assert w.file_actions.new("survey")  # 100 × 100 m, repeat 5 × 5, 0.025 m texels
    wait_idle(qtbot, w)
    texture = open_panel(w, "Texture")
    texel = field(texture, QDoubleSpinBox, "scene.texture.source.texel_size_m")
    message = _refused(qtbot, w, texel, "0.0001")
    assert ("texel size 0.0001 m makes a tile (20 × 20 m: the extent 100 × 100 m over "
            "repeat X 5, repeat Y 5) 200000 × 200000 texels, more than 8192") in message, message
    set_field(qtbot, texel, "0.025")  # back to the project's: the message goes
    wait_idle(qtbot, w)
    assert not texel.property("invalid")

    message = _refused(qtbot, w, texel, "3")
    assert ("texel size 3 m makes a tile (20 × 20 m: the extent 100 × 100 m over "
            "repeat X 5, repeat Y 5) 7 × 7 texels, fewer than 16") in message, message
    set_field(qtbot, texel, "0.025")
    wait_idle(qtbot, w)

    repeat_x = field(texture, QSpinBox, "scene.texture.repeat_X")
    message = _refused(qtbot, w, repeat_x, "10000")
    assert ("repeat X 10000 makes a tile (0.01 × 20 m: the extent 100 × 100 m over "
            "repeat X 10000, repeat Y 5) 0 × 800 texels of 0.025 m, fewer than 16") in message, \
        message
    # a repeat that keeps the tile drawable is applied
    set_field(qtbot, repeat_x, "10")
    wait_idle(qtbot, w)
    assert w.document.project.scene.texture.repeat_X == 10
    assert not repeat_x.property("invalid")
