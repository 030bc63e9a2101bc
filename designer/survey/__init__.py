"""Survey generation and analysis: GCP layouts, flight plans, coverage, maps.

Plain functions on data (no file parsing; the XML layer calls them). Frames and units
follow docs/conventions.md: world X = east, Y = north, Z = up, metres, float64 (UTM-sized
values are fine — every module subtracts a local origin before doing arithmetic);
``R_cam_to_world`` maps photogrammetric camera vectors (x image right, y image top,
z backwards) to world. Angles are radians in the core and degrees where a name says
``_deg``. Only numpy and :mod:`designer.core` are imported here; :mod:`.maps` imports
matplotlib lazily, inside its functions.

Modules:

* :mod:`.area` — survey areas (simple polygons) and the polygon operations used here;
* :mod:`.gcp_layout` — GCP positions, control/check roles, simulated survey error;
* :mod:`.flight` — the flight planner (QGroundControl's CameraCalc formulas) and pose noise;
* :mod:`.visibility` — which cameras see which ground points (image + occlusion, by
  :mod:`designer.core.raycast`);
* :mod:`.coverage` — what ``designer plan`` reports: GSD, overlap, coverage, GCP views;
* :mod:`.maps` — PNG maps of coverage count and GSD.
"""
