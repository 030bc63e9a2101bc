"""``designer export-flight``: a project's planned flight as a QGC plan, KML/KMZ or WPML."""

from __future__ import annotations

from pathlib import Path

from designer.errors import DesignerError
from designer.flight.exposures import FlightSpec, flight_spec
from designer.project import model as m

FORMATS = ("qgc", "kml", "wpml")
#: file suffixes each format is written with
SUFFIXES = {"qgc": (".plan",), "kml": (".kml", ".kmz"), "wpml": (".kmz",)}


def export_flight(
    project: m.Project, base_dir: Path, fmt: str, out: Path, **options
) -> FlightSpec:
    """Write the flight of ``project`` in ``fmt`` to ``out`` (atomic); options go to
    :func:`designer.flight.exposures.flight_spec`. Returns what was written."""
    if fmt not in FORMATS:
        raise DesignerError(f"--format {fmt}: use one of {', '.join(FORMATS)}")
    out = Path(out)
    if out.suffix.lower() not in SUFFIXES[fmt]:
        raise DesignerError(f"{out}: a {fmt} flight is written to a "
                            f"{' or '.join(SUFFIXES[fmt])} file; change the -o name")
    if not out.parent.is_dir():
        raise DesignerError(f"{out}: the folder {out.parent} does not exist; create it first")
    spec = flight_spec(project, base_dir, **options)
    if fmt == "qgc":
        from designer.flight.qgc import write_plan as write
    elif fmt == "kml":
        from designer.flight.kml import write_kml as write
    else:
        from designer.flight.wpml import write_wpml as write
    write(spec, out)
    return spec
