"""The desktop designer: a PySide6 + pyvistaqt window over the project model.

Two sub-packages, arrows pointing one way (model first, views listen):

* :mod:`designer.gui.state`, Qt-free, importable without PySide6 or VTK (tests prove
  it): :mod:`~designer.gui.state.document` (the observable project: current value,
  file, dirty flag, plain-Python events), :mod:`~designer.gui.state.edits` (pure model
  edits), :mod:`~designer.gui.state.derived` (figures derived from a project),
  :mod:`~designer.gui.state.view_geometry` (arrays the 3D view draws),
  :mod:`~designer.gui.state.wording` (the window's messages),
  :mod:`~designer.gui.state.camera_presets`, :mod:`~designer.gui.state.results_data`.
* :mod:`designer.gui.qt`, the widgets: :mod:`~designer.gui.qt.main_window` (menus,
  docks, files, undo), :mod:`~designer.gui.qt.scene_view` (the one owner of the
  pyvistaqt ``QtInteractor``), :mod:`~designer.gui.qt.scene_sync` (model events → view
  updates, heavy work off the UI thread), :mod:`~designer.gui.qt.panels` (one dock per
  module), :mod:`~designer.gui.qt.command_process` (a ``designer`` command run from the
  window).

Beside them, the start-up: :mod:`~designer.gui.app` (the application and its window)
and :mod:`~designer.gui.xvfb` (a virtual X display when there is none).

Start it with ``designer gui [PROJECT.xml] [--screenshot FILE.png]`` or
:func:`designer.gui.app.run`.
"""
