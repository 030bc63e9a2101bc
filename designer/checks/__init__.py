"""What ``designer check`` and ``designer plan`` tell of a project before anything renders,
beyond the project's own validation (the schema and the semantic checks of
:mod:`designer.project`, ``validate*.py``, which every reader of a project runs).

* :mod:`.project_checks` — every check ``designer check`` runs, in its order: the
  validation, the stations' clearance (refusing), then the warnings;
* :mod:`.station_clearance` — camera stations under the terrain, in a building or a plant;
* :mod:`.hard_cases` — cases that degrade results (docs/hard-cases.md): nearly collinear
  control, GSD against texel, a lens near its fold, thin networks, optics beyond a survey's;
* :mod:`.terrain_reach` — places beyond the ground a DEM or terrain mesh holds;
* :mod:`.plan_report` — what ``designer plan`` reports: the flight's figures over the real
  terrain and its warnings (the hard cases among them).

The package sits above :mod:`designer.survey` and :mod:`designer.scene`, whose stations,
terrain and analysis it weighs; the reconstruction, the window and the command line use it.
"""
