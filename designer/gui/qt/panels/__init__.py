"""Dockable side panels, one module each; every panel edits the project only through the
:class:`~designer.gui.qt.undo.Editor` and redraws itself from document events."""
