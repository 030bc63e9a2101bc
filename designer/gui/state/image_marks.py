"""Where a rendered image shows its GCPs, for the image viewer's marks.

The render exports the GCP image points of every image it rendered
(``OUT/ground-truth/gcp_observations.csv``): targets hidden behind buildings are left
out, and a rolling-shutter image's points are where its rows' own poses put them. Those
are the marks for an image on disk, whatever the project has become since. The exported
table is used when it is at least as new as the image (a render writes it after its
images); otherwise — an image rendered later, by an interrupted run, or an output folder
without the GCP tables — the caller projects the GCPs with the plan.
"""

from __future__ import annotations

from pathlib import Path

from designer.core.layout import GROUND_TRUTH_DIR, IMAGES_DIR

GCP_OBSERVATIONS_CSV = "gcp_observations.csv"


def exported_marks(image_path: str | Path) -> list[tuple[str, float, float]] | None:
    """(GCP id, u px, v px) of the GCPs the render exported for this image (designer's
    pixel convention: u right, v down, from the top-left corner of the top-left pixel),
    or None when no exported table is current for it."""
    image = Path(image_path)
    out = image.parent.parent if image.parent.name == IMAGES_DIR else image.parent
    table = out / GROUND_TRUTH_DIR / GCP_OBSERVATIONS_CSV
    from designer.errors import DesignerError
    from designer.export.tables import read_gcp_observations_csv

    try:
        if table.stat().st_mtime < image.stat().st_mtime:
            return None
        rows = read_gcp_observations_csv(table)
    except (OSError, ValueError, DesignerError):  # none, unreadable or not designer's
        return None
    return [(o.gcp_id, float(o.uv_px[0]), float(o.uv_px[1]))
            for o in rows if o.image_name == image.name]
