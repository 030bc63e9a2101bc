"""The GUI's Qt widgets: the main window, the 3D view (the one owner of the pyvistaqt
``QtInteractor``), the dockable panels, undo, background tasks and the command
processes (render, reconstruct, study) run from the window.

They listen to and edit the state of :mod:`designer.gui.state`; the state never
imports them.
"""
