"""Exact ground truth of a virtual survey, written for SfM software.

Modules, one per format (each documents its pixel origin, rotation convention,
units and coefficient swaps at the top):

* :mod:`~designer.export.groundtruth` — the data: CameraPose, GroundControlPoint,
  GcpObservation, and observe_gcps (true GCPs projected into the images);
* :mod:`~designer.export.colmap` — COLMAP text model (and a reader for round trips);
* :mod:`~designer.export.colmap_read` — the COLMAP model reader (text and binary),
  shared by the round trip and the accuracy assessment;
* :mod:`~designer.export.odm` — OpenDroneMap gcp_list.txt and geo.txt;
* :mod:`~designer.export.metashape` — Metashape calibration XML and reference CSVs;
* :mod:`~designer.export.tables` — designer's own CSV tables (ω φ κ, GCP truth,
  GCP image points), with readers;
* :mod:`~designer.export.dispatch` — write_all, every format into one folder.

Depends on numpy, lxml and designer.core only. Every file is written atomically.
"""

from designer.export._text import ExportError
from designer.export.dispatch import FORMATS, write_all
from designer.export.groundtruth import (
    GCP_ROLES,
    CameraPose,
    GcpObservation,
    GroundControlPoint,
    observe_gcps,
)

__all__ = [
    "FORMATS",
    "GCP_ROLES",
    "CameraPose",
    "ExportError",
    "GcpObservation",
    "GroundControlPoint",
    "observe_gcps",
    "write_all",
]
