"""The desktop designer: a PySide6 + pyvistaqt window over the project model.

Layers, arrows pointing one way (model first, views listen):

* Qt-free, importable without PySide6 or VTK (tests prove it):
  :mod:`~designer.gui.document` (the observable project: current value, file, dirty
  flag, plain-Python events), :mod:`~designer.gui.edits` (pure model edits),
  :mod:`~designer.gui.view_geometry` (arrays the 3D view draws),
  :mod:`~designer.gui.camera_presets`, :mod:`~designer.gui.results_data`.
* Qt: :mod:`~designer.gui.main_window` (menus, docks, files, undo),
  :mod:`~designer.gui.scene_view` (the one owner of the pyvistaqt ``QtInteractor``),
  :mod:`~designer.gui.scene_sync` (model events → view updates, heavy work off the UI
  thread), :mod:`~designer.gui.panels` (one dock per module).

Start it with ``designer gui [PROJECT.xml] [--screenshot FILE.png]`` or
:func:`designer.gui.app.run`.
"""
