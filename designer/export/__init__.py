"""Exact ground truth of a virtual survey, written for SfM software.

Modules, one per format (each documents its pixel origin, rotation convention,
units and coefficient swaps at the top):

* :mod:`~designer.export.colmap` — COLMAP text model (and a reader for round trips);
* :mod:`~designer.export.colmap_read` — the COLMAP model reader (text and binary),
  shared by the round trip and the accuracy assessment;
* :mod:`~designer.export.odm` — OpenDroneMap gcp_list.txt and geo.txt;
* :mod:`~designer.export.metashape` — Metashape calibration XML and reference CSVs;
* :mod:`~designer.export.tables` — designer's own CSV tables (ω φ κ, GCP truth,
  GCP image points), with readers;
* :mod:`~designer.export.dispatch` — write_all, every format into one folder.

The data written (CameraPose, GroundControlPoint, GcpObservation) are value types of
:mod:`designer.core.truth`. Depends on numpy, lxml and designer.core only. Every file
is written atomically. The names below load their module on first use, so importing
this package loads no exporter.
"""

from typing import TYPE_CHECKING

from designer._lazy import attach

__getattr__, __dir__, __all__ = attach(__name__, {
    "ExportError": "designer.export._text",
    "FORMATS": "designer.export.dispatch",
    "write_all": "designer.export.dispatch",
})

if TYPE_CHECKING:
    from designer.export._text import ExportError
    from designer.export.dispatch import FORMATS, write_all
