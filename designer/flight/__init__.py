"""Flight plans out (QGroundControl, KML/KMZ, DJI WPML) and flown surveys in (image
metadata, ODM geo.txt, reference CSVs).

Frames and units follow docs/conventions.md: the project's world frame is its CRS's grid
(X = Easting, Y = Northing, Z = height, metres); drones and their files use latitude,
longitude and angles from TRUE north. :mod:`.geodesy` converts between the two
(meridian convergence included), :mod:`.gimbal` between DJI gimbal angles and
``R_cam_to_world``.

Modules:

* :mod:`.geodesy` — CRS ↔ WGS 84, grid azimuth of true north;
* :mod:`.gimbal` — DJI gimbal yaw/pitch/roll (NED, ZYX) ↔ camera rotation;
* :mod:`.exposures` — the planned exposures of a project, as a drone flies them;
* :mod:`.qgc`, :mod:`.kml`, :mod:`.wpml` — writers, readers and field checks;
* :mod:`.image_meta` — GPS and DJI XMP from image files (pyexiv2);
* :mod:`.reference` — ODM geo.txt and Metashape/Pix4D-style reference CSVs;
* :mod:`.camera_pick` — the camera of a flown survey from its metadata;
* :mod:`.importer` — flown photos → a project with explicit exterior orientations.
"""

from designer._lazy import attach

__getattr__, __dir__, __all__ = attach(__name__, {
    "export_flight": "designer.flight.export",
    "import_flight": "designer.flight.importer",
})
