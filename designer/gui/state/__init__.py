"""The GUI's Qt-free state: the observable project, pure edits, derived figures, view
geometry as arrays, files, study and results data, and the window's wording.

Nothing here imports PySide6, pyvista, pyvistaqt or VTK, at module level or inside a
function, and nothing imports :mod:`designer.gui.qt`: every module imports and is tested
without a display. tests/test_architecture.py enforces both (``THIRD_PARTY_ONLY_IN``,
``SUBPACKAGE_MAY_NOT_IMPORT`` and ``IMPORT_WITHOUT``).
"""
